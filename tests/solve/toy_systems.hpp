#pragma once
// Small NonlinearSystems with closed-form residual, tangent and exact load derivative d r / d t, for the
// continuation tests: a scalar fold, the von Mises truss (two-bar toggle) under a dead load and the same
// truss loaded through a linear spring in series (Crisfield's snap-back example); solver doubles (one
// reporting inertia from a dense eigen-decomposition, one refusing to factorise) and a helper recording a
// traced path.
#include <cmath>
#include <string>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <Eigen/SparseCore>

#include "path/continuation.hpp"
#include "path/nonlinear.hpp"

namespace fibrane::solve::testing {

// r(q, t), K = d r / d q and r_t = d r / d t given as functions. The tangent is stored sparse with its full
// pattern (explicit zeros kept), so pattern_version() never changes.
class ToySystem : public NonlinearSystem {
 public:
  using VectorFn = std::function<Eigen::VectorXd(const Eigen::VectorXd&, double)>;
  using MatrixFn = std::function<Eigen::MatrixXd(const Eigen::VectorXd&, double)>;

  ToySystem(int n, VectorFn residual, MatrixFn tangent, VectorFn load_derivative)
      : n_(n), residual_fn_(std::move(residual)), tangent_fn_(std::move(tangent)),
        load_derivative_fn_(std::move(load_derivative)) {
    std::vector<Eigen::Triplet<double>> full;
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) full.emplace_back(i, j, 1.0);
    k_.resize(n, n);
    k_.setFromTriplets(full.begin(), full.end());
  }

  int size() const override { return n_; }
  void evaluate(const Eigen::VectorXd& q, double t, bool with_tangent) override {
    ++evaluations_;
    r_ = residual_fn_(q, t);
    if (!with_tangent) return;
    const Eigen::MatrixXd k = tangent_fn_(q, t);
    for (int j = 0; j < n_; ++j)
      for (Eigen::SparseMatrix<double>::InnerIterator it(k_, j); it; ++it) it.valueRef() = k(it.row(), j);
    r_t_ = load_derivative_fn_(q, t);
  }
  const Eigen::VectorXd& residual() const override { return r_; }
  const Eigen::SparseMatrix<double>& tangent() const override { return k_; }
  const Eigen::VectorXd& load_derivative() const override { return r_t_; }
  int pattern_version() const override { return 0; }
  void accept(const Eigen::VectorXd&, double) override { ++accepted_; }
  void reject() override { ++rejected_; }

  // The residual at (q, t) without touching the evaluated state (for finite differences).
  Eigen::VectorXd residual_at(const Eigen::VectorXd& q, double t) const { return residual_fn_(q, t); }
  Eigen::MatrixXd dense_tangent_at(const Eigen::VectorXd& q, double t) const { return tangent_fn_(q, t); }
  Eigen::VectorXd load_derivative_at(const Eigen::VectorXd& q, double t) const { return load_derivative_fn_(q, t); }
  int accepted() const { return accepted_; }
  int rejected() const { return rejected_; }
  int evaluations() const { return evaluations_; }

 private:
  int n_;
  VectorFn residual_fn_;
  MatrixFn tangent_fn_;
  VectorFn load_derivative_fn_;
  Eigen::VectorXd r_, r_t_;
  Eigen::SparseMatrix<double> k_;
  int accepted_ = 0, rejected_ = 0, evaluations_ = 0;
};

// r = f(q) - t with f(q) = q - q^3 / 3: limit points of t at q = +-1 (t = +-2/3).
inline double fold_f(double q) { return q - q * q * q / 3; }
inline ToySystem make_fold() {
  return ToySystem(
      1, [](const Eigen::VectorXd& q, double t) { return Eigen::VectorXd::Constant(1, fold_f(q[0]) - t); },
      [](const Eigen::VectorXd& q, double) { return Eigen::MatrixXd::Constant(1, 1, 1 - q[0] * q[0]); },
      [](const Eigen::VectorXd&, double) { return Eigen::VectorXd::Constant(1, -1.0); });
}

// Von Mises truss: bars of axial stiffness k from (-1, 0) and (1, 0) to the apex (0, h); w is the apex's
// downward displacement. Energy U(w) = k (L - L0)^2 with L = sqrt(1 + z^2), z = h - w, L0 = sqrt(1 + h^2):
//   U'(w)  = -2 k z (1 - L0 / L)       (the force the bars put up against w)
//   U''(w) = 2 k (1 - L0 / L^3)        (d/dz [z (1 - L0/L)] = 1 - L0 (L^2 - z^2) / L^3 and L^2 - z^2 = 1)
// U'' < 0 exactly where L^3 < L0: the unstable middle part |z| < z* = sqrt(L0^(2/3) - 1).
struct Truss {
  double h = 1.0, k = 1.0;
  double rest() const { return std::sqrt(1 + h * h); }
  double length(double w) const { return std::sqrt(1 + (h - w) * (h - w)); }
  double force(double w) const { return -2 * k * (h - w) * (1 - rest() / length(w)); }
  double stiffness(double w) const { return 2 * k * (1 - rest() / std::pow(length(w), 3)); }
  // Apex displacements where U''(w) = s: L^3 = L0 / (1 - s / 2k), z = +-sqrt(L^2 - 1); the smaller w first.
  std::pair<double, double> where_stiffness(double s) const {
    const double l = std::cbrt(rest() / (1 - s / (2 * k))), z = std::sqrt(l * l - 1);
    return {h - z, h + z};
  }
};

// The truss under the dead load P t at the apex: r = U'(w) - P t, analytic path t = U'(w) / P, limit
// loads t = U'(w) / P at U''(w) = 0.
inline ToySystem make_truss(const Truss& truss, double load) {
  return ToySystem(
      1,
      [truss, load](const Eigen::VectorXd& q, double t) {
        return Eigen::VectorXd::Constant(1, truss.force(q[0]) - load * t);
      },
      [truss](const Eigen::VectorXd& q, double) { return Eigen::MatrixXd::Constant(1, 1, truss.stiffness(q[0])); },
      [load](const Eigen::VectorXd&, double) { return Eigen::VectorXd::Constant(1, -load); });
}

// The truss loaded through a linear spring k_s in series: q = (w1 apex, w2 spring top), dead load P lambda(t)
// at the spring top. Energy U(w1) + k_s (w2 - w1)^2 / 2 - P lambda(t) w2, so
//   r = (U'(w1) - k_s (w2 - w1),  k_s (w2 - w1) - P lambda(t)),   K = [U'' + k_s, -k_s; -k_s, k_s],
//   r_t = (0, -P lambda'(t)).
// Analytic path, parametrised by w1: P lambda(t) = U'(w1), w2 = w1 + U'(w1) / k_s. Limit points of t
// at U''(w1) = 0; turning points of w2 at dw2/dw1 = 1 + U''(w1) / k_s = 0, i.e. U''(w1) = -k_s, which exist
// (snap-back) when k_s < -min U'' = 2 k (L0 - 1). det K = k_s U''(w1): one negative eigenvalue exactly
// where U''(w1) < 0.
inline ToySystem make_truss_with_spring(
    const Truss& truss, double spring, double load, std::function<double(double)> curve = [](double t) { return t; },
    std::function<double(double)> curve_derivative = [](double) { return 1.0; }) {
  return ToySystem(
      2,
      [=](const Eigen::VectorXd& q, double t) {
        const double s = spring * (q[1] - q[0]);
        return Eigen::Vector2d(truss.force(q[0]) - s, s - load * curve(t)).eval();
      },
      [=](const Eigen::VectorXd& q, double) {
        Eigen::Matrix2d k;
        k << truss.stiffness(q[0]) + spring, -spring, -spring, spring;
        return Eigen::MatrixXd(k);
      },
      [=](const Eigen::VectorXd&, double t) { return Eigen::Vector2d(0.0, -load * curve_derivative(t)).eval(); });
}

// Negative eigenvalues of a symmetric matrix by a dense eigen-decomposition.
inline int dense_negative_eigenvalues(const Eigen::MatrixXd& k) {
  const Eigen::VectorXd lambda = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(k).eigenvalues();
  return static_cast<int>((lambda.array() < 0).count());
}

// Reports the inertia of every factorised matrix from a dense eigen-decomposition; solves with `inner`.
// Stands in for a solver whose factorisation reports inertia (LinearSolver::negative_eigenvalues).
class InertiaSolver : public LinearSolver {
 public:
  explicit InertiaSolver(std::unique_ptr<LinearSolver> inner) : inner_(std::move(inner)) {}
  void analyze(const Eigen::SparseMatrix<double>& a) override { inner_->analyze(a); }
  bool factorize_numeric(const Eigen::SparseMatrix<double>& a) override {
    negative_ = dense_negative_eigenvalues(Eigen::MatrixXd(a));
    return inner_->factorize(a);
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override { return inner_->solve(b); }
  std::string name() const override { return "inertia " + inner_->name(); }
  long factor_nonzeros() const override { return inner_->factor_nonzeros(); }
  int negative_eigenvalues() const override { return negative_; }

 private:
  std::unique_ptr<LinearSolver> inner_;
  int negative_ = -1;
};

// Refuses every factorisation, as a solver does at an exactly singular tangent; counts the refusals.
class RefusingSolver : public LinearSolver {
 public:
  void analyze(const Eigen::SparseMatrix<double>&) override {}
  bool factorize_numeric(const Eigen::SparseMatrix<double>&) override { return ++refusals, false; }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const override { return b * std::nan(""); }
  std::string name() const override { return "refusing"; }
  long factor_nonzeros() const override { return 0; }
  int refusals = 0;
};

// A converged point of a traced path.
struct PathPoint {
  StepReport report;
  Eigen::VectorXd q;
};

// Runs `method` from q and records every converged point (the starting point excluded).
inline ContinuationResult trace(ContinuationMethod& method, NonlinearSystem& sys, Eigen::VectorXd q,
                                LinearSolver& solver, std::vector<PathPoint>& path) {
  return method.run(sys, q, solver, [&](const StepReport& rep, const Eigen::VectorXd& qs) {
    path.push_back({rep, qs});
    return true;
  });
}

}  // namespace fibrane::solve::testing
