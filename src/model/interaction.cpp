#include "model/interaction.hpp"

namespace fibrane::model {

namespace {

// final_<quantity> of every quantity at the last step written.
class FinalValues final : public Interaction::RunRecord {
 public:
  explicit FinalValues(const Interaction& i) : interaction_(i), values_(i.quantity_names().size(), 0.0) {}
  std::vector<std::string> step(int /*step*/, double /*t*/) override {
    for (std::size_t k = 0; k < values_.size(); ++k) values_[k] = interaction_.quantity(k);
    return {};
  }
  std::vector<SummaryField> fields() const override {
    const auto names = interaction_.quantity_names();
    std::vector<SummaryField> out;
    for (std::size_t k = 0; k < values_.size(); ++k) out.push_back({"final_" + names[k], values_[k]});
    return out;
  }

 private:
  const Interaction& interaction_;
  std::vector<double> values_;
};

}  // namespace

std::unique_ptr<Interaction::RunRecord> Interaction::run_record() const { return std::make_unique<FinalValues>(*this); }

}  // namespace fibrane::model
