#include "linalg/krylov_reuse.hpp"

#include <algorithm>
#include <cstdio>
#include <limits>

#include "linalg/krylov.hpp"

namespace fibrane::solve {

KrylovReuseSolver::KrylovReuseSolver(std::unique_ptr<LinearSolver> direct, const KrylovReuseOptions& options,
                                     bool symmetric, Factory exact_fallback)
    : direct_(std::move(direct)), exact_fallback_(std::move(exact_fallback)), options_(options), symmetric_(symmetric) {}

bool KrylovReuseSolver::fall_back_to_exact() const {
  direct_ = exact_fallback_();
  direct_->set_skew_candidates(candidates_);
  ++stats_.exact_fallbacks;
  pending_analysis_ = true;
  const bool ok = refactorize();
  if (options_.verbose)
    std::fprintf(stderr, "  the approximate factorisation could not be refined; from now on %s\n", direct_->name().c_str());
  return ok;
}

void KrylovReuseSolver::analyze(const Eigen::SparseMatrix<double>& a) {
  pending_analysis_ = true;
  if (a.rows() != factored_size_) factor_valid_ = fresh_ = false;
}

bool KrylovReuseSolver::refactorize() const {
  if (pending_analysis_) {
    direct_->analyze(*matrix_);
    pending_analysis_ = false;
    ++stats_.analyses;
  }
  ++stats_.factorizations;
  factor_valid_ = direct_->factorize(*matrix_);
  fresh_ = factor_valid_;
  stale_ = false;
  if (factor_valid_) factored_size_ = matrix_->rows();
  return factor_valid_;
}

bool KrylovReuseSolver::factorize_numeric(const Eigen::SparseMatrix<double>& a) {
  matrix_ = &a;
  if (factor_valid_ && !stale_ && a.rows() == factored_size_) {
    fresh_ = false;
    return true;
  }
  return refactorize();
}

bool KrylovReuseSolver::factorize_exactly(const Eigen::SparseMatrix<double>& a) {
  matrix_ = &a;
  return refactorize();
}

Eigen::VectorXd KrylovReuseSolver::solve_to(const Eigen::VectorXd& b, double relative_accuracy) const {
  ++stats_.solves;
  const auto failed = [&] { return Eigen::VectorXd::Constant(b.size(), std::numeric_limits<double>::quiet_NaN()); };
  if (!factor_valid_ || !matrix_) return failed();
  if (fresh_ && direct_->exact()) return direct_->solve(b);
  const VectorOperator apply = [this](const Eigen::VectorXd& x, Eigen::VectorXd& y) { parallel_multiply(*matrix_, x, y); };
  const VectorOperator precondition = [this](const Eigen::VectorXd& x, Eigen::VectorXd& y) { y = direct_->solve(x); };
  const double tolerance = std::max(options_.tolerance, relative_accuracy);
  ++stats_.krylov_solves;  // once per solve, however many preconditioners it tries
  for (int attempt = 0; attempt < 2; ++attempt) {
    const Eigen::VectorXd x0 = direct_->solve(b);
    if (!x0.allFinite()) return failed();
    const int limit = 3 * options_.max_iterations;
    const bool cg = symmetric_ && direct_->negative_eigenvalues() == 0;
    KrylovResult k = cg ? preconditioned_cg(apply, precondition, b, x0, tolerance, limit) : KrylovResult{};
    if (!cg || k.breakdown) k = preconditioned_gmres(apply, precondition, b, x0, tolerance, limit, options_.restart);
    if (options_.verbose)
      std::fprintf(stderr, "  %s: %d iterations to %.2e (asked %.1e) with the factorisation of %s\n", cg ? "cg" : "gmres",
                   k.iterations, k.relative_residual, tolerance, fresh_ ? "this matrix" : "an earlier matrix");
    stats_.krylov_iterations += k.iterations;
    if (k.iterations > options_.max_iterations) stale_ = true;
    if (k.converged) return k.x;
    // A fresh approximate factorisation that cannot be refined: the exact solver from now on.
    if (fresh_ && !direct_->exact() && exact_fallback_) return fall_back_to_exact() ? direct_->solve(b) : failed();
    // Not converged with this preconditioner: factorise the current matrix (once) and solve again.
    if (fresh_ || attempt > 0) return failed();
    ++stats_.stale_refactorizations;
    if (!refactorize()) return failed();
    if (direct_->exact()) return direct_->solve(b);
  }
  return failed();
}

std::string KrylovReuseSolver::analysis_summary() const {
  std::string inner = direct_->analysis_summary();
  return (inner.empty() ? "" : inner + "; ") + std::to_string(stats_.factorizations) + " factorisations, " +
         std::to_string(stats_.krylov_iterations) + " Krylov iterations in " + std::to_string(stats_.krylov_solves) +
         " of " + std::to_string(stats_.solves) + " solves";
}

}  // namespace fibrane::solve
