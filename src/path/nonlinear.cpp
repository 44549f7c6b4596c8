#include "path/nonlinear.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "common/format.hpp"

namespace fibrane::solve {

namespace {

// |r| of the last evaluation, NaN for a state outside the system's domain (so that the line search backs
// off from it and Newton fails on it like on a non-finite residual).
double residual_norm(const NonlinearSystem& sys) {
  if (!sys.invalid_state().empty()) return std::numeric_limits<double>::quiet_NaN();
  return sys.residual().norm();
}

// The relative accuracy of the next linear solve (NewtonOptions::forcing_max): Eisenstat and Walker's
// choice 2 (gamma = 0.9, alpha = 2) from the last contraction, capped, and relaxed to what the tolerance needs.
double forcing_term(const NewtonOptions& opt, const std::vector<double>& history, double scale) {
  if (opt.forcing_max <= 0 || history.empty()) return 0.0;
  const double norm = history.back();
  double eta = opt.forcing_max;
  if (history.size() >= 2) eta = std::min(eta, 0.9 * std::pow(norm / history[history.size() - 2], 2));
  const double tolerance = std::max(opt.tol_relative * scale, opt.tol_absolute);
  if (norm > 0) eta = std::max(eta, std::min(opt.forcing_max, 0.5 * tolerance / norm));
  return eta;
}

}  // namespace

std::string GiveUpRules::check(const std::vector<double>& h, double scale) {
  const int it = static_cast<int>(h.size()) - 1;
  const double norm = h.back();
  const std::string at = " at iteration " + std::to_string(it);
  if (norm > options_.divergence_factor * scale) return "diverged" + at + " (|r| = " + format_number(norm) + ")";
  if (h.size() >= 5 && std::abs(h[it] - h[it - 2]) <= 1e-3 * h[it] &&
      std::abs(h[it - 1] - h[it - 3]) <= 1e-3 * h[it - 1] && std::abs(h[it] - h[it - 1]) > 1e-2 * h[it])
    return "cycling between two states" + at + " (|r| = " + format_number(h[it - 1]) + ", " + format_number(norm) + ")";
  if (it == 0 || norm < 0.5 * best_ || norm > 10 * best_) {
    best_ = norm;
    best_at_ = it;
  }
  if (options_.stall_iterations > 0 && it - best_at_ >= options_.stall_iterations)
    return "no progress in " + std::to_string(it - best_at_) + " iterations (|r| = " + format_number(norm) +
           ", none below half of " + format_number(best_) + " at iteration " + std::to_string(best_at_) + ")";
  if (it >= options_.max_iterations)
    return "no convergence in " + std::to_string(options_.max_iterations) + " iterations (|r| = " +
           format_number(norm) + ")";
  return {};
}

const Eigen::VectorXd& NonlinearSystem::load_derivative() const {
  static const Eigen::VectorXd none;
  return none;
}

bool NonlinearSystem::tangent_finite() const {
  const Eigen::SparseMatrix<double>& k = tangent();
  return Eigen::Map<const Eigen::VectorXd>(k.valuePtr(), k.nonZeros()).allFinite();
}

namespace {

NewtonReport newton_iterate(NonlinearSystem& sys, Eigen::VectorXd& q, double t, const NewtonOptions& opt,
                            LinearSolver& solver) {
  NewtonReport rep;
  double scale = 0.0, previous_norm = 0.0, floor_estimate = 0.0;
  GiveUpRules give_up(opt);
  bool small_update = false;
  Eigen::VectorXd last_update;
  double applied = 0.0;  // fraction of last_update in q
  // Factorisation reuse (opt.reuse_below): `reuse` when the last update contracted |r| enough that this
  // iteration tries the factorisation it was solved with.
  bool reuse = false, factor_valid = false;
  // No tangent is assembled for an iterate the last update predicts converged (quadratic rate: |r| times
  // the last contraction squared below the tolerance): plain Newton would assemble one at its last iterate
  // and not use it. If the prediction fails, the iterate is evaluated once more, with its tangent. (The
  // bending example's steps mostly end inside reused factorisations, residual-only already: its count of
  // tangents did not change.)
  bool expect_converged = false;
  solver.begin_step();
  for (int it = 0;; ++it) {
    bool with_tangent = !reuse && !expect_converged;
    sys.evaluate(q, t, with_tangent);
    double norm = residual_norm(sys);
    // Backtracking on |r| (steps.line_search, off by default): a full update that raised the residual is
    // halved (not at the round-off floor, where |r| wanders). It turns overshooting updates (Newton on
    // atan diverges) into converging ones; it did not help where the residual is discontinuous (the
    // bending example's closest-point branch switch at the fiber's tip).
    for (int halvings = 0; it > 0 && !small_update && halvings < opt.line_search && !(norm <= previous_norm);
         ++halvings) {
      applied *= 0.5;
      q -= applied * last_update;
      ++rep.backtracks;
      sys.evaluate(q, t, with_tangent);
      const double reduced = residual_norm(sys);
      if (opt.verbose) std::fprintf(stderr, "  newton t=%.6g it=%d |r|=%.6e: update x %g, |r|=%.6e\n", t, it, norm, applied, reduced);
      norm = reduced;
    }
    const Eigen::VectorXd& r = sys.residual();
    rep.residual_norm = norm;
    rep.history.push_back(norm);
    if (opt.verbose) std::fprintf(stderr, "  newton t=%.6g it=%d |r|=%.6e\n", t, it, norm);
    if (!std::isfinite(norm)) {
      const std::string why = sys.invalid_state();
      rep.failure = (why.empty() ? "non-finite residual" : "invalid state (" + why + ")") + " at iteration " +
                    std::to_string(it);
      return rep;
    }
    if (it == 0) scale = std::max(norm, sys.residual_scale());
    // Round-off floor: after an update that barely moved q, a residual that was real would have been
    // removed by it; one that stayed within a factor 2 of the last is noise (summation round-off of large
    // internal forces). The residual there wanders up and down: on the bending example at 300 x 75 x 75
    // (floor 5.5e-6 > tolerance) requiring a fall cost 3-4 extra iterations per step.
    // Only where the residual is already small (sqrt(tol_relative) of the scale, 3e-5 at the default): a
    // tiny update from a singular tangent next to a large residual is no floor.
    const bool at_floor = small_update && norm <= 2.0 * previous_norm && norm <= std::sqrt(opt.tol_relative) * scale;
    // The floor estimated from the last tangent and the configuration's magnitudes: no iteration can get
    // below it, so a tolerance under it would be chased through cut-backs until the step size underflows.
    const bool at_estimated_floor = it > 0 && floor_estimate > 0 && norm <= kRoundoffFloorFactor * floor_estimate;
    if (norm <= std::max(opt.tol_relative * scale, opt.tol_absolute) || at_floor || at_estimated_floor) {
      rep.converged = true;
      rep.at_roundoff_floor = at_estimated_floor && norm > std::max(opt.tol_relative * scale, opt.tol_absolute);
      return rep;
    }
    previous_norm = norm;
    rep.failure = give_up.check(rep.history, scale);
    if (!rep.failure.empty()) return rep;
    // A reused factorisation must keep cutting |r| by 4 (slower linear rates took dozens of updates on
    // the strongly nonlinear spring chain of the tests); where it did not, this iterate gets its own
    // tangent (one more evaluation, now with the tangent).
    const double contraction = it > 0 ? norm / rep.history[it - 1] : 1.0;
    if (reuse && (!factor_valid || !(contraction <= 0.25))) reuse = false;
    const bool fresh = !reuse;
    if (fresh && !with_tangent) {
      sys.evaluate(q, t, true);
      with_tangent = true;
    }
    if (fresh) {
      const Eigen::SparseMatrix<double>& k = sys.tangent();
      // A non-finite entry (e.g. a closest point at a centre of curvature, where the projection's
      // derivative is unbounded) would make the factorisation fail only after a full LL^T and LU attempt.
      if (!sys.tangent_finite()) {
        rep.failure = "non-finite tangent at iteration " + std::to_string(it);
        return rep;
      }
      analyze_if_needed(solver, sys, k);
      factor_valid = false;
      if (!solver.factorize(k)) {
        const std::string detail = solver.failure_detail();
        rep.failure = "factorization failed (" + solver.name() + (detail.empty() ? "" : ": " + detail) +
                      ") at iteration " + std::to_string(it);
        return rep;
      }
      factor_valid = true;
      floor_estimate = sys.roundoff_floor();
      ++rep.factorizations;
      rep.negative_eigenvalues = solver.negative_eigenvalues();
      if (opt.verbose) {
        const std::string inertia = rep.negative_eigenvalues >= 0
                                        ? ", " + std::to_string(rep.negative_eigenvalues) + " negative eigenvalues"
                                        : "";
        std::fprintf(stderr, "  newton t=%.6g it=%d new tangent for %s%s; round-off floor ~ %.3e\n", t, it,
                     solver.name().c_str(), inertia.c_str(), floor_estimate);
      }
    }
    const Eigen::VectorXd dq = solver.solve_to(-r, forcing_term(opt, rep.history, scale));
    if (!dq.allFinite()) {
      // A solve that factorised inside (a Krylov solver renewing its preconditioner) may have failed there.
      const std::string detail = solver.failure_detail();
      rep.failure = "non-finite Newton update at iteration " + std::to_string(it) +
                    (detail.empty() ? "" : " (" + solver.name() + ": " + detail + ")");
      return rep;
    }
    q += dq;
    last_update = dq;
    applied = 1.0;
    small_update = opt.tol_increment > 0 && dq.norm() <= opt.tol_increment * q.norm();
    rep.iterations = it + 1;
    // Newton is in its fast regime once an update cut |r| to reuse_below: the next updates reuse the
    // factorisation just made (while each cuts |r| by 4, above). With reuse_first, the step's first
    // factorisation is tried at once.
    if (fresh) reuse = opt.reuse_below > 0 && (it > 0 ? contraction <= opt.reuse_below : opt.reuse_first);
    const double tolerance = std::max(opt.tol_relative * scale, opt.tol_absolute);
    expect_converged = it > 0 && fresh && norm * contraction * contraction <= tolerance;
  }
}

}  // namespace

bool analyze_if_needed(LinearSolver& solver, const NonlinearSystem& sys, const Eigen::SparseMatrix<double>& k) {
  if (!solver.needs_analysis(k, sys.pattern_version())) return false;
  solver.set_skew_candidates(sys.skew_candidates());
  return solver.analyze_if_needed(k, sys.pattern_version());
}

NewtonReport newton_solve(NonlinearSystem& sys, Eigen::VectorXd& q, double t, const NewtonOptions& opt,
                          LinearSolver& solver) {
  if (q.size() != sys.size()) throw std::invalid_argument("newton_solve: q has the wrong size");
  NewtonReport rep = newton_iterate(sys, q, t, opt, solver);
  // A failed solve's factor is of no use (every caller factorises before it solves) and would be held
  // through the cut-back's first evaluation and factorisation, beside the memory they take.
  if (!rep.converged) solver.release_factor();
  return rep;
}

}  // namespace fibrane::solve
