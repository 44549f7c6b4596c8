// What Newton's local updates (path/local_correction.hpp) need of the model: a partial evaluation of
// only the elements whose free unknowns meet the update's rows, which hold every entry of the tangent's
// principal submatrix on those rows; the beams' unknowns, which a local solve always takes in; and, in a
// distributed run, the collectives that make the rows and that submatrix the same on every process.
#include <algorithm>

#include "linalg/partition.hpp"
#include "linalg/rank_one_terms.hpp"
#include "model/model.hpp"

namespace fibrane::model {

void Model::evaluate_tangent_on(const Eigen::VectorXd& q, double t, const std::vector<int>& rows,
                                solve::RankOneTerms* apart) {
  // Distributed, each process would hold only its own soft points' terms: they stay in the tangent there.
  if (apart) apart->clear();
  evaluate_elements(q, t, true, &rows, distributed() ? nullptr : apart);
}

std::vector<int> Model::local_solve_rows() const {
  std::vector<int> rows;
  for (const BeamBody& beam : beams) {
    const int first = dofs.block_offset(beam.block), end = first + dofs.block_size(beam.block);
    for (int d = first; d < end; ++d)
      if (const int i = constraints.free_index(d); i >= 0) rows.push_back(i);
  }
  std::sort(rows.begin(), rows.end());
  return rows;
}

void Model::unite_flags(std::vector<char>& flags) const {
  if (!distributed()) return;
  std::vector<double> any(flags.begin(), flags.end());
  distribution_->sum(any);
  for (std::size_t i = 0; i < flags.size(); ++i) flags[i] = any[i] > 0.0 ? 1 : 0;
}

Eigen::SparseMatrix<double> Model::sum_over_processes(Eigen::SparseMatrix<double> part) const {
  if (!distributed()) return part;
  // Indices below 2^53 are exact in a double.
  std::vector<double> entries;
  entries.reserve(3 * static_cast<std::size_t>(part.nonZeros()));
  for (int j = 0; j < part.outerSize(); ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(part, j); it; ++it)
      entries.insert(entries.end(), {static_cast<double>(j), static_cast<double>(it.row()), it.value()});
  const std::vector<double> all = distribution_->gather(entries);
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(all.size() / 3);
  for (std::size_t k = 0; k + 2 < all.size(); k += 3)
    triplets.emplace_back(static_cast<int>(all[k + 1]), static_cast<int>(all[k]), all[k + 2]);
  Eigen::SparseMatrix<double> sum(part.rows(), part.cols());
  sum.setFromTriplets(triplets.begin(), triplets.end());  // duplicates summed in the triplets' order
  return sum;
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
