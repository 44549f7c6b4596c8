#include "model/observables.hpp"

#include "model/model.hpp"

namespace fibrane::model {

std::vector<Observable> observables(const Model& m) {
  std::vector<Observable> out;
  out.push_back({"strain_energy", [](const Model& x) { return x.strain_energy(); }});
  for (std::size_t i = 0; i < m.interactions().size(); ++i) {
    const Interaction& interaction = *m.interactions()[i];
    const auto names = interaction.quantity_names();
    for (std::size_t k = 0; k < names.size(); ++k)
      out.push_back({interaction.name() + "_" + names[k],
                     [i, k](const Model& x) { return x.interactions()[i]->quantity(k); }});
  }
  for (std::size_t i = 0; i < m.monitors.size(); ++i)
    out.push_back({m.monitors[i]->name(), [i](const Model& x) { return x.monitors[i]->value(x); }});
  return out;
}

}  // namespace fibrane::model
