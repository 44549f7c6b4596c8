#include "path/nonlinear.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <limits>
#include <stdexcept>

#include "common/format.hpp"
#include "path/local_correction.hpp"

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

// One Newton solve at load t (newton_solve's work), its state between iterations kept as members.
class NewtonIteration {
 public:
  NewtonIteration(NonlinearSystem& sys, Eigen::VectorXd& q, double t, const NewtonOptions& opt, LinearSolver& solver,
                  bool factor_in_hand)
      : sys_(sys), q_(q), t_(t), opt_(opt), solver_(solver), give_up_(opt),
        carry_(factor_in_hand && opt.reuse_below > 0 && solver.held_factor_entries() > 0) {}

  NewtonReport run() {
    solver_.begin_step();
    for (int it = 0;; ++it) {
      // The global update after a local solve may reuse the factorisation in hand (chord_after_local_solve).
      const bool chord = chord_after_local_solve();
      if (chord) reuse_ = true;
      // The solve's first global update with the factorisation in hand (newton_solve's factor_in_hand).
      const bool carried = carry_ && !(it == 0 && local_first());
      if (carried) {
        reuse_ = factor_valid_ = true;
        factor_norm_ = std::numeric_limits<double>::infinity();  // no chord after a local solve with it
      }
      // A local first update assembles its own part of the tangent (local_step).
      bool with_tangent = !reuse_ && !expect_converged_ && !(it == 0 && local_first());
      double norm = evaluate(it, with_tangent);
      if (local_pending_) {
        norm = keep_or_undo_local(it, norm);
        with_tangent = with_tangent || !local_kept_;  // taken back: evaluated again with the tangent
        if (chord && !local_kept_) reuse_ = false;     // and factorised, as without the chord
      }
      rep_.residual_norm = norm;
      rep_.history.push_back(norm);
      if (opt_.verbose) std::fprintf(stderr, "  newton t=%.6g it=%d |r|=%.6e\n", t_, it, norm);
      if (!std::isfinite(norm)) {
        const std::string why = sys_.invalid_state();
        rep_.failure = (why.empty() ? "non-finite residual" : "invalid state (" + why + ")") + " at iteration " +
                       std::to_string(it);
        return rep_;
      }
      if (it == 0) scale_ = std::max(norm, sys_.residual_scale());
      if (converged(it, norm)) return rep_;
      previous_norm_ = norm;
      rep_.failure = give_up_.check(rep_.history, scale_);
      if (!rep_.failure.empty()) return rep_;
      if (it == 0 && local_first() && local_step(it)) continue;
      // A reused factorisation must keep cutting |r| by 4 (slower linear rates took dozens of updates on
      // the strongly nonlinear spring chain of the tests); where it did not, this iterate gets its own
      // tangent (one more evaluation, now with the tangent). A chord after a local solve is tried whatever
      // the local solve's contraction, which says nothing of the global rate.
      const double contraction = it > 0 ? norm / rep_.history[it - 1] : 1.0;
      if (reuse_ && !chord && !carried && (!factor_valid_ || !(contraction <= 0.25))) {
        reuse_ = false;
        factor_spent_ = factor_spent_ || reused_update_;
      }
      // A local solve where the last update was global and the residual has gathered on a local set.
      const bool after_local = local_solved_;
      local_solved_ = !reuse_ && it > 0 && !after_local && opt_.local_newton > 0 && local_solve(it);
      if (local_solved_) continue;
      const bool fresh = !reuse_;
      if (fresh && !with_tangent) sys_.evaluate(q_, t_, true);
      if (fresh && !factorise(it)) return rep_;
      if (!update(it)) return rep_;
      reused_update_ = !fresh;
      carry_ = false;
      // Newton is in its fast regime once an update cut |r| to reuse_below: the next updates reuse the
      // factorisation just made (while each cuts |r| by 4, above). With reuse_first, the step's first
      // factorisation is tried at once.
      // After a kept local update that cut |r| by 4, the fresh factorisation is reused too: the local update
      // did the global one's first work, and its own contraction says nothing of Newton's rate.
      if (fresh)
        reuse_ = opt_.reuse_below > 0 && (local_kept_ ? contraction <= 0.25
                                                      : it > 0 ? contraction <= opt_.reuse_below : opt_.reuse_first);
      local_kept_ = false;
      expect_converged_ = it > 0 && fresh && norm * contraction * contraction <= tolerance();
    }
  }

 private:
  double tolerance() const { return std::max(opt_.tol_relative * scale_, opt_.tol_absolute); }

  // Evaluates the iterate and returns |r|. Backtracking on |r| (steps.line_search, off by default): a full
  // update that raised the residual is halved (not at the round-off floor, where |r| wanders). It turns
  // overshooting updates (Newton on atan diverges) into converging ones; it did not help where the residual
  // is discontinuous (the bending example's closest-point branch switch at the fiber's tip).
  double evaluate(int it, bool with_tangent) {
    sys_.evaluate(q_, t_, with_tangent);
    double norm = residual_norm(sys_);
    for (int halvings = 0; it > 0 && !small_update_ && halvings < opt_.line_search && !(norm <= previous_norm_);
         ++halvings) {
      applied_ *= 0.5;
      q_ -= applied_ * last_update_;
      ++rep_.backtracks;
      sys_.evaluate(q_, t_, with_tangent);
      const double reduced = residual_norm(sys_);
      if (opt_.verbose)
        std::fprintf(stderr, "  newton t=%.6g it=%d |r|=%.6e: update x %g, |r|=%.6e\n", t_, it, norm, applied_, reduced);
      norm = reduced;
    }
    return norm;
  }

  // Whether the iterate has converged (recorded in the report).
  bool converged(int it, double norm) {
    // Round-off floor: after an update that barely moved q, a residual that was real would have been
    // removed by it; one that stayed within a factor 2 of the last is noise (summation round-off of large
    // internal forces). The residual there wanders up and down: on the bending example at 300 x 75 x 75
    // (floor 5.5e-6 > tolerance) requiring a fall cost 3-4 extra iterations per step.
    // Only where the residual is already small (sqrt(tol_relative) of the scale, 3e-5 at the default): a
    // tiny update from a singular tangent next to a large residual is no floor.
    const bool at_floor = small_update_ && norm <= 2.0 * previous_norm_ && norm <= std::sqrt(opt_.tol_relative) * scale_;
    // The floor estimated from the last tangent and the configuration's magnitudes: no iteration can get
    // below it, so a tolerance under it would be chased through cut-backs until the step size underflows.
    const bool at_estimated_floor = it > 0 && floor_estimate_ > 0 && norm <= kRoundoffFloorFactor * floor_estimate_;
    if (!(norm <= tolerance() || at_floor || at_estimated_floor)) return false;
    rep_.converged = true;
    rep_.at_roundoff_floor = at_estimated_floor && norm > tolerance();
    return true;
  }

  // Analyses (at a new pattern) and factorises the tangent just evaluated; false, with the report's
  // failure, where that fails.
  bool factorise(int it) {
    const Eigen::SparseMatrix<double>& k = sys_.tangent();
    // A non-finite entry (e.g. a closest point at a centre of curvature, where the projection's
    // derivative is unbounded) would make the factorisation fail only after a full LL^T and LU attempt.
    if (!sys_.tangent_finite()) {
      rep_.failure = "non-finite tangent at iteration " + std::to_string(it);
      return false;
    }
    analyze_if_needed(solver_, sys_, k);
    factor_valid_ = false;
    if (!solver_.factorize(k)) {
      const std::string detail = solver_.failure_detail();
      rep_.failure = "factorization failed (" + solver_.name() + (detail.empty() ? "" : ": " + detail) +
                     ") at iteration " + std::to_string(it);
      return false;
    }
    factor_valid_ = true;
    carry_ = false;
    factor_norm_ = rep_.history[it];
    factor_spent_ = false;
    floor_estimate_ = sys_.roundoff_floor();
    ++rep_.factorizations;
    rep_.negative_eigenvalues = solver_.negative_eigenvalues();
    if (opt_.verbose) {
      const std::string inertia = rep_.negative_eigenvalues >= 0
                                      ? ", " + std::to_string(rep_.negative_eigenvalues) + " negative eigenvalues"
                                      : "";
      std::fprintf(stderr, "  newton t=%.6g it=%d new tangent for %s%s; round-off floor ~ %.3e\n", t_, it,
                   solver_.name().c_str(), inertia.c_str(), floor_estimate_);
    }
    return true;
  }

  // Whether the global update after a local solve reuses the factorisation in hand (a chord) instead of
  // factorising this iterate's tangent: where that factorisation was made at an iterate whose |r| was at
  // most reuse_below of the solve's first (Newton was in its fast regime there, and the local solve has
  // taken up the part that is not), and no reused update with it has failed to cut |r| by 4. The reuse
  // rule then goes on as after any reused factorisation.
  bool chord_after_local_solve() const {
    return local_pending_ && local_solved_ && factor_valid_ && !factor_spent_ && opt_.reuse_below > 0 &&
           !rep_.history.empty() && factor_norm_ <= opt_.reuse_below * rep_.history.front();
  }

  // Whether a solve's first update is local (NewtonOptions::local_share).
  bool local_first() const { return opt_.local_share > 0; }

  // The first update on the rows where |r| concentrates (NewtonOptions::local_share), from the tangent's
  // entries on those rows alone (NonlinearSystem::evaluate_tangent_on; the rows grow through the pattern
  // of the tangent last assembled); false where it cannot be made (a factorisation that fails, rows that
  // are most of the unknowns): the iterate then takes the global update. Distributed, every process takes
  // the same branches: the rows, K_SS and so the update are the same bits on all of them.
  bool local_step(int it) {
    const auto start = std::chrono::steady_clock::now();
    const Eigen::SparseMatrix<double>& pattern = sys_.tangent();
    // Before a step's first tangent (the run's first iterate) there is no pattern, on any process.
    if (pattern.rows() != q_.size() || pattern.cols() != q_.size()) return false;
    const Eigen::VectorXd r = sys_.residual();
    RowUnion unite;
    if (sys_.distributed()) unite = [this](std::vector<char>& added) { sys_.unite_flags(added); };
    const std::vector<int> rows = local_rows(r, pattern, {.share = opt_.local_share}, unite);
    if (2 * rows.size() > static_cast<std::size_t>(q_.size())) return false;
    sys_.evaluate_tangent_on(q_, t_, rows, &apart_);
    const Eigen::SparseMatrix<double> kss = sys_.sum_over_processes(local_matrix(sys_.tangent(), rows, apart_));
    Eigen::VectorXd dq;
    if (!local_update(r, kss, apart_, sys_.symmetric(), rows, dq)) return false;
    q_ += dq;
    record_local(std::move(dq), it);
    if (opt_.verbose)
      std::fprintf(stderr, "  newton t=%.6g it=%d local update on %zu rows, %ld entries and %d rank-one terms (%.3f s)\n",
                   t_, it, rows.size(), static_cast<long>(kss.nonZeros()), apart_.size(),
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return true;
  }

  // The rows of a local solve: local_rows of the residual and the system's local_solve_rows, sorted.
  std::vector<int> local_solve_set(const Eigen::VectorXd& r) const {
    const double share = opt_.local_share > 0 ? opt_.local_share : 0.01;
    std::vector<int> rows = local_rows(r, sys_.tangent(), {.share = share});
    const std::vector<int> always = sys_.local_solve_rows();
    std::vector<int> both;
    both.reserve(rows.size() + always.size());
    std::set_union(rows.begin(), rows.end(), always.begin(), always.end(), std::back_inserter(both));
    return both;
  }

  // A local Newton solve (NewtonOptions::local_newton) from the iterate just evaluated with its global
  // tangent; false, with nothing changed, where it does not apply (|r| not gathered on the set, a set of
  // half the unknowns or more, a distributed system) or its first update could not be made.
  bool local_solve(int it) {
    const auto start = std::chrono::steady_clock::now();
    if (sys_.distributed() || sys_.tangent().rows() != q_.size()) return false;
    const std::vector<int> rows = local_solve_set(sys_.residual());
    if (rows.empty() || 2 * rows.size() > static_cast<std::size_t>(q_.size())) return false;
    const auto norm_on_rows = [&rows](const Eigen::VectorXd& v) {
      double sq = 0.0;
      for (int i : rows) sq += v[i] * v[i];
      return std::sqrt(sq);
    };
    constexpr double kGathered = 0.99, kEnough = 0.02;
    const double begin = norm_on_rows(sys_.residual());
    if (!(begin >= kGathered * sys_.residual().norm())) return false;
    Eigen::VectorXd total = Eigen::VectorXd::Zero(q_.size()), dq;
    double last = begin;
    Eigen::Index entries = 0;  // K_SS's, for the log
    int updates = 0;
    for (; updates < opt_.local_newton; ++updates) {
      sys_.evaluate_tangent_on(q_, t_, rows, &apart_);  // the set's rows of the residual are whole after it
      const double now = sys_.invalid_state().empty() ? norm_on_rows(sys_.residual()) : NAN;
      if (updates > 0 && !(now < last)) {  // the last update did not lower |r| on the set
        q_ -= dq;
        total -= dq;
        --updates;
        break;
      }
      last = now;
      if (updates > 0 && now <= kEnough * begin) break;
      const Eigen::SparseMatrix<double> kss = local_matrix(sys_.tangent(), rows, apart_);
      entries = kss.nonZeros();
      if (!local_factor_.update(sys_.residual(), kss, apart_, sys_.symmetric(), rows, sys_.pattern_version(), dq))
        break;
      q_ += dq;
      total += dq;
    }
    local_factor_.release();  // the global factorisation after it needs the memory
    if (opt_.verbose)
      std::fprintf(stderr, "  newton t=%.6g it=%d local solve on %zu rows, %ld entries and %d rank-one terms: %d updates,"
                   " |r| there %.3e -> %.3e (%.3f s)\n", t_, it, rows.size(), static_cast<long>(entries), apart_.size(),
                   updates, begin, last,
                   std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    if (updates == 0) {
      sys_.evaluate(q_, t_, true);  // the partial evaluation replaced the iterate's tangent
      return false;
    }
    record_local(std::move(total), it);
    return true;
  }

  // A local update dq (already added to q) as the iteration's update, which the next evaluation keeps or
  // takes back (keep_or_undo_local).
  void record_local(Eigen::VectorXd dq, int it) {
    last_update_ = std::move(dq);
    applied_ = 1.0;
    small_update_ = false;
    rep_.iterations = it + 1;
    ++rep_.local_updates;
    local_pending_ = true;
  }

  // |r| after a local update, or, where it did not fall below the last (or is not finite), the update taken
  // back and |r| of the iterate before it, evaluated again with its tangent.
  double keep_or_undo_local(int it, double norm) {
    local_pending_ = false;
    local_kept_ = norm < previous_norm_;
    if (local_kept_) return norm;
    q_ -= applied_ * last_update_;
    applied_ = 0.0;
    sys_.evaluate(q_, t_, true);
    const double back = residual_norm(sys_);
    if (opt_.verbose)
      std::fprintf(stderr, "  newton t=%.6g it=%d |r|=%.6e after the local update: taken back, |r|=%.6e\n", t_, it,
                   norm, back);
    return back;
  }

  // Solves for the update with the current factorisation and applies it; false, with the report's
  // failure, for a non-finite update.
  bool update(int it) {
    const Eigen::VectorXd dq = solver_.solve_to(-sys_.residual(), forcing_term(opt_, rep_.history, scale_));
    if (!dq.allFinite()) {
      // A solve that factorised inside (a Krylov solver renewing its preconditioner) may have failed there.
      const std::string detail = solver_.failure_detail();
      rep_.failure = "non-finite Newton update at iteration " + std::to_string(it) +
                     (detail.empty() ? "" : " (" + solver_.name() + ": " + detail + ")");
      return false;
    }
    q_ += dq;
    last_update_ = dq;
    applied_ = 1.0;
    small_update_ = opt_.tol_increment > 0 && dq.norm() <= opt_.tol_increment * q_.norm();
    rep_.iterations = it + 1;
    return true;
  }

  NonlinearSystem& sys_;
  Eigen::VectorXd& q_;
  const double t_;
  const NewtonOptions& opt_;
  LinearSolver& solver_;
  NewtonReport rep_;
  GiveUpRules give_up_;
  double scale_ = 0.0, previous_norm_ = 0.0, floor_estimate_ = 0.0;
  bool small_update_ = false;
  Eigen::VectorXd last_update_;
  double applied_ = 0.0;  // fraction of last_update_ in q
  // Factorisation reuse (opt.reuse_below): `reuse_` when the last update contracted |r| enough that this
  // iteration tries the factorisation it was solved with.
  bool reuse_ = false, factor_valid_ = false;
  double factor_norm_ = 0.0;  // |r| of the iterate whose tangent the factorisation in hand is
  bool factor_spent_ = false;  // a reused update with it did not cut |r| by 4: no chord after a local solve
  bool reused_update_ = false;  // the last global update solved with a reused factorisation
  // No tangent is assembled for an iterate the last update predicts converged (quadratic rate: |r| times
  // the last contraction squared below the tolerance): plain Newton would assemble one at its last iterate
  // and not use it. If the prediction fails, the iterate is evaluated once more, with its tangent. (The
  // bending example's steps mostly end inside reused factorisations, residual-only already: its count of
  // tangents did not change.)
  bool expect_converged_ = false;
  bool local_pending_ = false;  // the last update was local: the next evaluation keeps or undoes it
  bool local_kept_ = false;     // the last update was local and kept
  bool local_solved_ = false;   // the last update was a local solve (NewtonOptions::local_newton)
  // The solve's first global update is still to come, and it solves with the factorisation the solver
  // holds from before the solve (a chord; the reuse rule then goes on as after any reused factorisation).
  bool carry_ = false;
  LocalFactorization local_factor_;  // K_SS's solver during a local solve, its analysis kept between updates
  RankOneTerms apart_;  // the rank-one terms a partial evaluation held apart from the tangent
};

}  // namespace

bool analyze_if_needed(LinearSolver& solver, const NonlinearSystem& sys, const Eigen::SparseMatrix<double>& k) {
  if (!solver.needs_analysis(k, sys.pattern_version())) return false;
  solver.set_skew_candidates(sys.skew_candidates());
  return solver.analyze_if_needed(k, sys.pattern_version());
}

NewtonReport newton_solve(NonlinearSystem& sys, Eigen::VectorXd& q, double t, const NewtonOptions& opt,
                          LinearSolver& solver, bool factor_in_hand) {
  if (q.size() != sys.size()) throw std::invalid_argument("newton_solve: q has the wrong size");
  NewtonReport rep = NewtonIteration(sys, q, t, opt, solver, factor_in_hand).run();
  // A failed solve's factor is of no use (every caller factorises before it solves) and would be held
  // through the cut-back's first evaluation and factorisation, beside the memory they take.
  if (!rep.converged) solver.release_factor();
  return rep;
}

}  // namespace fibrane::solve
