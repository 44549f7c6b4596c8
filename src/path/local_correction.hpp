#pragma once
// A Newton update on part of the unknowns: the rows where a residual concentrates and their neighbours in
// the tangent's graph, solved with the principal submatrix of the tangent on them.
//
// A load step's predicted state is wrong mostly where the path is least smooth: on the bending example the
// contact front and the loaded fiber's end hold 99.9 % of |r|^2 in a few dozen of 278 k rows. The global
// Newton update that removes such a residual is itself concentrated there, and the same update on a tenth
// of the unknowns around it cuts |r| by ~35 (median) at the cost of a factorisation of that tenth
// (docs/performance.md, "A local first update"). Newton's first update of a step can be such a local one
// (NewtonOptions::local_share): the step then factorises the whole tangent once where it did twice.
//
// Nonlinear elimination and subspace-correction methods (Cai and Keyes 2002; Lanzkron, Rose and Wilkes
// 1996) treat a localized nonlinearity the same way; here the subspace is one linear solve, chosen afresh
// at each step from the residual and the tangent alone: no mesh, no model.
#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <functional>
#include <memory>
#include <vector>

#include "linalg/linear_solver.hpp"
#include "linalg/rank_one_terms.hpp"

namespace fibrane::solve {

/// The rows of a local update: the seeds (rows whose |r_i| is at least seed_level max|r|) and as many
/// layers of their neighbours in k's graph as bring the set to `share` of k's rows (the last layer taken
/// whole), at most max_layers. Sorted. `k` is square and compressed, its pattern structurally symmetric.
struct LocalRowsOptions {
  double share = 0.1;
  double seed_level = 1e-3;
  int max_layers = 64;
};
/// Where k is one process's summand of a matrix shared by several processes (NonlinearSystem::distributed),
/// `unite` makes each layer the same on every process: called with the rows a layer adds here (flags of
/// k's size, 1 for an added row), it flags the rows any process added. Every process calls it equally
/// often, and the layers are then those of the sum's graph (the union of the summands' graphs). Empty
/// (the default): k is the whole matrix.
using RowUnion = std::function<void(std::vector<char>& added)>;
std::vector<int> local_rows(const Eigen::VectorXd& r, const Eigen::SparseMatrix<double>& k,
                            const LocalRowsOptions& options, const RowUnion& unite = {});

/// K_SS: the principal submatrix of k on the rows S (sorted), in their order.
Eigen::SparseMatrix<double> principal_submatrix(const Eigen::SparseMatrix<double>& k, const std::vector<int>& rows);

/// The matrix a local update factorises: the principal submatrix on the rows S of a tangent assembled with
/// the rank-one terms `apart` held apart (NonlinearSystem::evaluate_tangent_on), without the exact zeros
/// that the terms' fill leaves there (entries whose row and column both lie among RankOneTerms::fill_rows;
/// exact zeros elsewhere stay). With no terms apart, principal_submatrix.
Eigen::SparseMatrix<double> local_matrix(const Eigen::SparseMatrix<double>& tangent, const std::vector<int>& rows,
                                         const RankOneTerms& apart);

/// The update dq with K_SS dq_S = -r_S on the rows S (sorted) and dq = 0 elsewhere, K_SS = `kss` plus the
/// terms `apart` on S (RankOneTerms::on_rows; `kss` as local_matrix gives it), `kss` factorised by
/// make_linear_solver("auto", symmetric) (LL^T, then LDL^T where it is indefinite; an LU for an
/// unsymmetric tangent) and the terms added by solve_with_rank_one_terms. False, dq untouched, where the
/// factorisation fails or the update is not finite.
bool local_update(const Eigen::VectorXd& r, const Eigen::SparseMatrix<double>& kss, const RankOneTerms& apart,
                  bool symmetric, const std::vector<int>& rows, Eigen::VectorXd& dq);

/// local_update for a sequence of updates, as a local Newton solve makes them: the solver, its analysis
/// and its factor's storage are kept from one update to the next (until release()) while the rows, the
/// pattern of `kss` (compared entry by entry: local_matrix's may change with the values; 4 bytes per entry
/// kept), the tangent's pattern (`pattern_version`, NonlinearSystem::pattern_version) and the symmetry stay
/// the same.
/// K_SS's ordering and symbolic factorisation are then made once per local solve instead of once per
/// update, and the numeric factorisation writes into the factor it replaces.
class LocalFactorization {
 public:
  bool update(const Eigen::VectorXd& r, const Eigen::SparseMatrix<double>& kss, const RankOneTerms& apart,
              bool symmetric, const std::vector<int>& rows, int pattern_version, Eigen::VectorXd& dq);
  /// Frees the solver, analysis and all (its symmetry probe's map alone is 4 bytes per entry of K_SS): the
  /// global factorisation after a local solve needs the memory, and the next local solve's rows differ.
  void release();
  /// How many analyses and factorisations it has made.
  int analyses() const { return analyses_; }
  int factorizations() const { return factorizations_; }

 private:
  std::unique_ptr<LinearSolver> solver_;
  std::vector<int> rows_;
  int pattern_version_ = 0;
  std::vector<int> column_start_, row_index_;  // kss's pattern at the last analysis
  bool symmetric_ = true;
  int analyses_ = 0, factorizations_ = 0;
};

}  // namespace fibrane::solve
