#pragma once
// A LinearSolver that factorises rarely: a factorisation made for one tangent preconditions CG or GMRES
// on the tangents of later Newton iterations and steps, until the Krylov iteration count says it has
// gone stale. It also refines approximate factorisations (single precision, block low-rank) to double
// precision.
#include <functional>
#include <memory>
#include <string>

#include "linalg/linear_solver.hpp"

namespace fibrane::solve {

// Settings of KrylovReuseSolver (case files: steps.krylov).
struct KrylovReuseOptions {
  // Every solve ends at |b - A x| <= tolerance |b|, or at the looser accuracy its caller asks for
  // (solve_to: newton_solve's forcing terms).
  double tolerance = 1e-8;
  // A solve that needed more Krylov iterations marks the factorisation stale: the next factorize()
  // factorises its matrix. A solve that does not converge within 3 x max_iterations factorises the
  // current matrix at once and solves again.
  int max_iterations = 20;
  int restart = 60;  // GMRES(restart): the basis holds restart + 1 vectors (3 x max_iterations by default)
  bool verbose = false;  // a line per Krylov solve on stderr (fibrane run --newton-log)
};

// Counts for reports.
struct KrylovReuseStatistics {
  long factorizations = 0;       // numeric factorisations of the inner solver
  long analyses = 0;             // symbolic analyses of the inner solver
  long solves = 0;
  long krylov_solves = 0;        // solves that iterated (a reused or an inexact factorisation)
  long krylov_iterations = 0;
  long stale_refactorizations = 0;  // factorisations forced within a solve that did not converge
  long exact_fallbacks = 0;         // approximate factorisations replaced by the exact solver (0 or 1)
};

// Wraps a direct solver. factorize(a) records a (which must stay alive and unchanged until the next
// factorize(), as Newton's and arc-length's tangents do) and factorises it only when there is no
// factorisation, the last one is stale, or the matrix's size changed; a new sparsity pattern of the same
// size (analyze()) keeps the old factorisation as the preconditioner and analyses the new pattern when
// it is next factorised. solve(b) is the direct solve when the current matrix was just factorised
// exactly; otherwise preconditioned CG (the model promises symmetry and the factorisation is positive
// definite) or GMRES from the preconditioned right-hand side.
// negative_eigenvalues() is that of the current matrix when it was factorised, -1 when a factorisation
// of another matrix is being reused. factorize_exactly() always factorises (arc-length's sign rule needs
// the inertia of the tangent at a converged state).
// An approximate factorisation (single precision, low rank) of an ill-conditioned matrix can be too far
// from it for any Krylov method (condition number times single precision's 6e-8 above 1): when the
// refinement of a fresh approximate factorisation fails, the solver switches for good to the solver that
// `exact_fallback` makes (the same path in double precision), factorises and solves with it.
class KrylovReuseSolver final : public LinearSolver {
 public:
  using Factory = std::function<std::unique_ptr<LinearSolver>()>;
  KrylovReuseSolver(std::unique_ptr<LinearSolver> direct, const KrylovReuseOptions& options, bool symmetric,
                    Factory exact_fallback = {});
  void analyze(const Eigen::SparseMatrix<double>& a) override;
  bool factorize_numeric(const Eigen::SparseMatrix<double>& a) override;
  bool factorize_exactly(const Eigen::SparseMatrix<double>& a) override;
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override { return solve_to(b, 0.0); }
  // Iterates to max(relative_accuracy, options.tolerance).
  Eigen::VectorXd solve_to(const Eigen::VectorXd& b, double relative_accuracy) const override;
  std::string name() const override { return "krylov(" + direct_->name() + ")"; }
  long factor_nonzeros() const override { return direct_->factor_nonzeros(); }
  long factorizations() const override { return stats_.factorizations; }
  std::string analysis_summary() const override;
  int negative_eigenvalues() const override { return fresh_ ? direct_->negative_eigenvalues() : -1; }
  std::string failure_detail() const override { return direct_->failure_detail(); }
  void begin_step() override { direct_->begin_step(); }
  void set_skew_candidates(std::optional<std::vector<int>> rows) override {
    candidates_ = rows;
    direct_->set_skew_candidates(std::move(rows));
  }
  const KrylovReuseStatistics& statistics() const { return stats_; }

 private:
  bool refactorize() const;
  // Replaces an approximate direct solver by exact_fallback_'s and factorises the current matrix.
  bool fall_back_to_exact() const;

  mutable std::unique_ptr<LinearSolver> direct_;
  Factory exact_fallback_;
  KrylovReuseOptions options_;
  bool symmetric_;
  std::optional<std::vector<int>> candidates_;  // set_skew_candidates()'s, for the exact fallback
  const Eigen::SparseMatrix<double>* matrix_ = nullptr;
  mutable bool pending_analysis_ = true, factor_valid_ = false, fresh_ = false, stale_ = false;
  mutable Eigen::Index factored_size_ = -1;
  mutable KrylovReuseStatistics stats_;
};

}  // namespace fibrane::solve
