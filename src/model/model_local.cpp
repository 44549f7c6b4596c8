// A partial evaluation for Newton's local first update (path/local_correction.hpp): only the elements
// whose free unknowns meet the update's rows, which hold every entry of the tangent's principal
// submatrix on those rows.
#include <algorithm>

#include "linalg/partition.hpp"
#include "model/model.hpp"

namespace fibrane::model {

void Model::evaluate_tangent_on(const Eigen::VectorXd& q, double t, const std::vector<int>& rows) {
  if (distribution_)
    evaluate(q, t, true);
  else
    evaluate_elements(q, t, true, &rows);
}

// Every element that adds to an entry (i, j) with i and j in `rows` has both among its unknowns.
std::vector<char> Model::elements_meeting(const std::vector<int>& rows) const {
  std::vector<char> in_rows(static_cast<std::size_t>(size()), 0);
  for (const int r : rows) in_rows[static_cast<std::size_t>(r)] = 1;
  std::vector<char> meets;
  for (const auto& e : entries_) {
    const auto unknowns = solve::element_unknowns(constraints, e.contribution->element_dofs(dofs));
    const auto first = static_cast<std::size_t>(e.first_element);
    if (meets.size() < first + unknowns.size()) meets.resize(first + unknowns.size(), 0);
    for (std::size_t k = 0; k < unknowns.size(); ++k)
      meets[first + k] = std::any_of(unknowns[k].begin(), unknowns[k].end(),
                                     [&](int u) { return in_rows[static_cast<std::size_t>(u)] != 0; });
  }
  return meets;
}

}  // namespace fibrane::model
