#pragma once
// The sparsity pattern of this process's rows of a matrix that is the sum of the processes' summands
// (each process's tangent summand, model/model.hpp, in the solver's numbering), for the exact
// preallocation of PETSc's matrix.
#include <vector>

#include <Eigen/SparseCore>

#include "parallel/mpi_distribution.hpp"

namespace fibrane::parallel {

// Rows [first, first + begin.size() - 1) of the sum: row `first + r` has the sorted columns
// columns[begin[r] ... begin[r + 1]).
struct RowPattern {
  int first = 0;
  std::vector<int> begin{0}, columns;
  int rows() const { return static_cast<int>(begin.size()) - 1; }
};

// Collective. This process's rows (ownership.begin) of the union of every process's `summand` pattern,
// columns >= row only when `upper` (symmetric storage). Every summand must have a symmetric pattern
// (element blocks): the columns of row i are then the rows of column i, so each process sends the columns
// of its summand that fall into another process's rows to that process.
RowPattern owned_rows(const Eigen::SparseMatrix<double>& summand, bool upper, const solve::UnknownOwnership& ownership,
                      const MpiDistribution& distribution);

// The rows of a column-major matrix, round by round: next(end) gives the rows from the last round's end
// up to `end` with their values, each row's columns sorted. Each column keeps a cursor to its first entry
// not yet given, so all rounds together visit every entry once. (PETSc's AIJ matrices store rows: a row
// handed over whole finds its columns in one sweep, where a column's entries would each search a row.)
class RowRounds {
 public:
  explicit RowRounds(const Eigen::SparseMatrix<double>& a);
  const RowPattern& next(int end);
  const std::vector<double>& values() const { return values_; }

 private:
  const Eigen::SparseMatrix<double>& a_;
  std::vector<int> cursor_, fill_;
  RowPattern rows_;
  std::vector<double> values_;
};

}  // namespace fibrane::parallel
