// The arc-length method's options, its restart state, the path tangent at a converged state and the
// choice of the predictor's direction (solve/arc_length.hpp); the corrector and the step loop are in
// arc_length.cpp.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "common/error.hpp"
#include "path/arc_length.hpp"
#include "path/arc_length_detail.hpp"

namespace fibrane::solve {

using arc_length_detail::sign_of;

void check_arc_length_control(const ArcLengthControl& c) {
  if (!(c.ds_min > 0) || !(c.ds_initial >= c.ds_min) || !(c.ds_max >= c.ds_min) ||
      !(c.cutback > 0 && c.cutback < 1) || !(c.growth >= 1) || c.desired_iterations < 1 ||
      !(c.t_min <= c.t_start && c.t_start <= c.t_max) || !(c.max_path_length > 0) ||
      (c.initial_direction != 1 && c.initial_direction != -1) ||
      !(c.ambiguous_cosine >= 0 && c.ambiguous_cosine <= 1) || std::isnan(c.t_end) || std::isnan(c.load_scale))
    throw InputError("arc-length control: need 0 < ds_min <= ds_initial, ds_min <= ds_max, 0 < cutback < 1, "
                     "growth >= 1, desired_iterations >= 1, t_min <= t_start <= t_max, max_path_length > 0, "
                     "initial_direction = 1 or -1 and 0 <= ambiguous_cosine <= 1");
}

ArcLength::ArcLength(ArcLengthControl control, NewtonOptions newton)
    : control_(control), newton_(std::move(newton)) {
  check_arc_length_control(control_);
}

MethodState ArcLength::save() const {
  return {{"t", {t_}}, {"ds", {ds_}}, {"load_scale", {c_}}, {"path_length", {path_length_}},
          {"steps", {static_cast<double>(steps_)}}, {"have_prev", {have_prev_ ? 1.0 : 0.0}},
          {"dq_prev", std::vector<double>(dq_prev_.data(), dq_prev_.data() + dq_prev_.size())},
          {"dt_prev", {dt_prev_}}, {"tangent_dt_sign", {static_cast<double>(tangent_dt_sign_)}},
          {"negative_eigenvalues", {static_cast<double>(inertia_prev_)}},
          {"have_tangent", {have_tangent_ ? 1.0 : 0.0}},
          {"tangent_dq", std::vector<double>(tangent_.dq.data(), tangent_.dq.data() + tangent_.dq.size())},
          {"tangent_dt", {tangent_.dt}},
          {"tangent_negative_eigenvalues", {static_cast<double>(tangent_.negative_eigenvalues)}},
          {"sign_disagreements", {static_cast<double>(disagreements_)}}};
}

void ArcLength::restore(const MethodState& s) {
  auto value = [&s](const char* key) { return s.at(key).at(0); };
  t_ = value("t"), ds_ = value("ds"), c_ = value("load_scale"), path_length_ = value("path_length");
  steps_ = static_cast<int>(value("steps"));
  have_prev_ = value("have_prev") != 0.0;
  const auto& dq = s.at("dq_prev");
  dq_prev_ = Eigen::Map<const Eigen::VectorXd>(dq.data(), static_cast<Eigen::Index>(dq.size()));
  dt_prev_ = value("dt_prev");
  tangent_dt_sign_ = static_cast<int>(value("tangent_dt_sign"));
  inertia_prev_ = static_cast<int>(value("negative_eigenvalues"));
  // A state without the tangent (e.g. one assembled by hand) has it recomputed at the restored state.
  have_tangent_ = s.count("have_tangent") && value("have_tangent") != 0.0;
  if (have_tangent_) {
    const auto& tq = s.at("tangent_dq");
    tangent_.dq = Eigen::Map<const Eigen::VectorXd>(tq.data(), static_cast<Eigen::Index>(tq.size()));
    tangent_.dt = value("tangent_dt");
    tangent_.negative_eigenvalues = static_cast<int>(value("tangent_negative_eigenvalues"));
  }
  disagreements_ = s.count("sign_disagreements") ? static_cast<int>(value("sign_disagreements")) : 0;
  restored_ = true;
}

// The extended (bordered) system [K r_t; row_q^T row_t] [x; y] = [rhs_q; rhs_t], solved as one sparse
// unsymmetric matrix by UMFPACK: regular at a simple limit point, where K alone is singular (Keller 1977,
// "Numerical solution of bifurcation and nonlinear eigenvalue problems", in Applications of Bifurcation
// Theory, Academic Press, 359-384).
bool ArcLength::bordered_solve(const Eigen::SparseMatrix<double>& k, const Eigen::VectorXd& r_t,
                               const Eigen::VectorXd& row_q, double row_t, const Eigen::VectorXd& rhs_q,
                               double rhs_t, Eigen::VectorXd& x, double& y) {
  const Eigen::Index n = k.rows();
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(static_cast<size_t>(k.nonZeros() + 2 * n + 1));
  for (Eigen::Index col = 0; col < k.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(k, col); it; ++it)
      entries.emplace_back(it.row(), it.col(), it.value());
  for (Eigen::Index i = 0; i < n; ++i) {
    entries.emplace_back(i, n, r_t[i]);
    entries.emplace_back(n, i, row_q[i]);
  }
  entries.emplace_back(n, n, row_t);
  Eigen::SparseMatrix<double> extended(n + 1, n + 1);
  extended.setFromTriplets(entries.begin(), entries.end());
  if (!extended_) extended_ = make_linear_solver("umfpack", false);
  extended_->analyze(extended);
  if (!extended_->factorize(extended)) return false;
  Eigen::VectorXd rhs(n + 1);
  rhs << rhs_q, rhs_t;
  const Eigen::VectorXd solution = extended_->solve(rhs);
  if (!solution.allFinite()) return false;
  x = solution.head(n);
  y = solution[n];
  return true;
}

// The tangent at the state of the system's last evaluation (with the tangent): K v = -r_t with one
// factorisation of K, or the extended system bordered with the last increment (the tangent then points
// forward along it) or, before the first step, with (0, initial_direction).
bool ArcLength::tangent_at_state(NonlinearSystem& sys, LinearSolver& solver, Tangent& tangent) {
  const Eigen::SparseMatrix<double>& k = sys.tangent();
  const Eigen::VectorXd& r_t = sys.load_derivative();
  if (r_t.size() != k.rows())
    throw std::invalid_argument("arc-length continuation needs the system's load derivative (d residual / d t)");
  if (!sys.tangent_finite() || !r_t.allFinite()) return false;
  analyze_if_needed(solver, sys, k);
  // The sign rule compares the inertia of consecutive path tangents: this matrix's own factorisation.
  if (solver.factorize_exactly(k)) {
    tangent.dq = solver.solve(-r_t);
    tangent.dt = 1.0;
    tangent.negative_eigenvalues = solver.negative_eigenvalues();
    if (tangent.dq.allFinite()) return true;
  }
  tangent.negative_eigenvalues = -1;
  // The extended system needs the whole tangent, which a distributed system does not hold.
  if (sys.distributed()) return false;
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(k.rows());
  return have_prev_ ? bordered_solve(k, r_t, dq_prev_, c_ * c_ * dt_prev_, zero, 1.0, tangent.dq, tangent.dt)
                    : bordered_solve(k, r_t, zero, control_.initial_direction, zero, 1.0, tangent.dq, tangent.dt);
}

// +1 or -1: the orientation of the predictor along `tangent` (see ArcLengthControl::ambiguous_cosine).
// Records dt/ds and the inertia at this state for the next step's determinant rule.
int ArcLength::predictor_sign(const Tangent& tangent) {
  int sign = sign_of(tangent.dt) * control_.initial_direction;
  if (have_prev_) {
    const double c2 = c_ * c_;
    const double dot = tangent.dq.dot(dq_prev_) + c2 * tangent.dt * dt_prev_;
    const double norms = std::sqrt((tangent.dq.squaredNorm() + c2 * tangent.dt * tangent.dt) *
                                   (dq_prev_.squaredNorm() + c2 * dt_prev_ * dt_prev_));
    const int angle_sign = dot >= 0 ? 1 : -1;
    // Determinant rule: dt/ds changes sign with det K, i.e. with the parity of the negative eigenvalues.
    int det_sign = 0;
    if (tangent.negative_eigenvalues >= 0 && inertia_prev_ >= 0 && tangent_dt_sign_ != 0 && tangent.dt != 0) {
      const bool flipped = (tangent.negative_eigenvalues - inertia_prev_) % 2 != 0;
      det_sign = (flipped ? -tangent_dt_sign_ : tangent_dt_sign_) * sign_of(tangent.dt);
    }
    const bool ambiguous = !(std::abs(dot) >= control_.ambiguous_cosine * norms);
    sign = (ambiguous && det_sign != 0) ? det_sign : angle_sign;
    if (det_sign != 0 && det_sign != angle_sign) {
      ++disagreements_;
      if (newton_.verbose)
        std::fprintf(stderr, "arc length at t=%.6g: angle rule (cos %.3g) and determinant rule disagree; "
                     "following the %s rule\n", t_, norms > 0 ? dot / norms : 0.0,
                     sign == angle_sign ? "angle" : "determinant");
    }
  }
  tangent_dt_sign_ = sign * sign_of(tangent.dt);
  inertia_prev_ = tangent.negative_eigenvalues;
  return sign;
}

// One corrector update (delta_q, delta_t) at the system's last evaluation, for the current increment
// (dq, dt) of a step of length ds: the bordering algorithm with one factorisation of K, or the extended
// system where K cannot be factorised.

}  // namespace fibrane::solve
