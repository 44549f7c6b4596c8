#pragma once
// Test model for the solver layer: a plane network of bars with a nonlinear axial law, assembled through
// the real ConstraintSet and SparseAssembler. Axial force N(e) of a bar with elongation e = L - L0:
//   linear:     N = k e                        energy  k e^2 / 2
//   saturating: N = k d tanh(e / d)            energy  k d^2 log cosh(e / d)   (max force k d: limit point)
#include <cmath>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "linalg/assembler.hpp"
#include "linalg/constraints.hpp"
#include "path/nonlinear.hpp"

namespace fibrane::solve::testing {

struct Bar {
  int a, b;                 // node indices
  double stiffness = 1.0;
  double saturation = 0.0;  // d of the tanh law; 0 = linear
};

struct PointLoad {
  int dof;
  double value;
  int curve = -1;
};

// Axial force, its derivative and the energy for elongation e.
struct AxialLaw {
  double force, stiffness, energy;
};
inline AxialLaw axial_law(const Bar& bar, double e) {
  if (bar.saturation <= 0) return {bar.stiffness * e, bar.stiffness, 0.5 * bar.stiffness * e * e};
  const double d = bar.saturation, th = std::tanh(e / d);
  return {bar.stiffness * d * th, bar.stiffness * (1 - th * th), bar.stiffness * d * d * std::log(std::cosh(e / d))};
}

// Bar energy W(L) with L = |xb - xa|: gradient W' n on [xa, xb] with opposite signs, and Hessian of the
// relative vector: W'' n n^T + W'/L (I - n n^T). Returns the energy.
inline double bar_response(const Bar& bar, double rest_length, const Eigen::Vector2d& xa, const Eigen::Vector2d& xb,
                           Eigen::VectorXd& r, Eigen::MatrixXd* k) {
  const Eigen::Vector2d d = xb - xa;
  const double length = d.norm();
  const Eigen::Vector2d n = d / length;
  const AxialLaw law = axial_law(bar, length - rest_length);
  r.resize(4);
  r << -law.force * n, law.force * n;
  if (k) {
    const Eigen::Matrix2d h = law.stiffness * n * n.transpose() +
                              law.force / length * (Eigen::Matrix2d::Identity() - n * n.transpose());
    k->resize(4, 4);
    *k << h, -h, -h, h;
  }
  return law.energy;
}

// Nodes carry 2 DOFs (x, y): dof = 2 * node + component.
class SpringNetwork : public NonlinearSystem {
 public:
  SpringNetwork(std::vector<Eigen::Vector2d> nodes, std::vector<Bar> bars, ConstraintSet constraints,
                std::vector<PointLoad> loads, CurveEval curves = [](int, double t) { return t; })
      : nodes_(std::move(nodes)), bars_(std::move(bars)), constraints_(std::move(constraints)),
        loads_(std::move(loads)), curves_(std::move(curves)) {
    constraints_.finalize(2 * static_cast<int>(nodes_.size()));
    for (const Bar& bar : bars_) rest_.push_back((nodes_[static_cast<size_t>(bar.b)] - nodes_[static_cast<size_t>(bar.a)]).norm());
    rebuild_pattern();
  }

  void rebuild_pattern() {
    std::vector<std::vector<int>> element_dofs;
    for (const Bar& bar : bars_) element_dofs.push_back({2 * bar.a, 2 * bar.a + 1, 2 * bar.b, 2 * bar.b + 1});
    assembler_.set_pattern(constraints_, element_dofs);
  }

  int size() const override { return constraints_.num_free(); }
  void evaluate(const Eigen::VectorXd& q, double t, bool with_tangent) override {
    u_ = constraints_.expand(q, t, curves_);
    assembler_.begin(with_tangent);
    const int n_bars = static_cast<int>(bars_.size());
#pragma omp parallel for schedule(static) if (n_bars > parallel_threshold_)
    for (int e = 0; e < n_bars; ++e) {
      const Bar& bar = bars_[static_cast<size_t>(e)];
      Eigen::VectorXd r;
      Eigen::MatrixXd k;
      bar_response(bar, rest_[static_cast<size_t>(e)], position(bar.a), position(bar.b), r,
                   with_tangent ? &k : nullptr);
      assembler_.add(e, r, with_tangent ? &k : nullptr);
    }
    for (const PointLoad& load : loads_) {  // r = internal - external
      const int dof[1] = {load.dof};
      assembler_.add_vector(dof, Eigen::VectorXd::Constant(1, -load.value * curve(load.curve, t)));
    }
    assembler_.end();
  }
  const Eigen::VectorXd& residual() const override { return assembler_.reduced_residual(); }
  const Eigen::SparseMatrix<double>& tangent() const override { return assembler_.matrix(); }
  int pattern_version() const override { return assembler_.pattern_version(); }
  void accept(const Eigen::VectorXd&, double) override { ++accepted_; }
  void reject() override { ++rejected_; }

  double energy(const Eigen::VectorXd& q, double t) {  // total potential, for residual checks
    u_ = constraints_.expand(q, t, curves_);
    double w = 0;
    Eigen::VectorXd r;
    for (size_t e = 0; e < bars_.size(); ++e)
      w += bar_response(bars_[e], rest_[e], position(bars_[e].a), position(bars_[e].b), r, nullptr);
    for (const PointLoad& load : loads_) w -= load.value * curve(load.curve, t) * u_[load.dof];
    return w;
  }

  const ConstraintSet& constraints() const { return constraints_; }
  SparseAssembler& assembler() { return assembler_; }
  const Eigen::VectorXd& displacements() const { return u_; }  // full u at the last evaluate
  int accepted() const { return accepted_; }
  int rejected() const { return rejected_; }
  void set_parallel_threshold(int bars) { parallel_threshold_ = bars; }

 private:
  double curve(int id, double t) const { return id < 0 ? 1.0 : curves_(id, t); }
  Eigen::Vector2d position(int node) const {
    return nodes_[static_cast<size_t>(node)] + u_.segment<2>(2 * node);
  }

  std::vector<Eigen::Vector2d> nodes_;
  std::vector<Bar> bars_;
  std::vector<double> rest_;
  ConstraintSet constraints_;
  std::vector<PointLoad> loads_;
  CurveEval curves_;
  SparseAssembler assembler_;
  Eigen::VectorXd u_;
  int accepted_ = 0, rejected_ = 0;
  int parallel_threshold_ = 64;  // tiny networks: thread start-up costs more than the work
};

}  // namespace fibrane::solve::testing
