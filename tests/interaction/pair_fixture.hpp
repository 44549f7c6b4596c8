#pragma once
// A beam point paired with a deformed curved shell: the pair DOF vector q (layout of add_sbs_point), the
// closest-point projection redone for every q (so finite differences see theta-hat move), and the kernel.
#include <Eigen/Dense>
#include <cmath>
#include <random>
#include <vector>

#include "laws/lennard_jones.hpp"
#include "interaction/closest_point.hpp"
#include "interaction/sbs_point.hpp"
#include "spline/surface_third.hpp"

namespace fibrane::interaction::test {

// Quartic Bezier beam element on xi in [0, 1] (nB = 5): rows N, N_xi.
inline Eigen::Matrix<double, 2, Eigen::Dynamic> bernstein4(double xi) {
  Eigen::Matrix<double, 2, Eigen::Dynamic> b(2, 5);
  const double binom[5] = {1, 4, 6, 4, 1};
  for (int i = 0; i < 5; ++i) {
    b(0, i) = binom[i] * std::pow(xi, i) * std::pow(1 - xi, 4 - i);
    const double left = i > 0 ? i * std::pow(xi, i - 1) * std::pow(1 - xi, 4 - i) : 0.0;
    const double right = i < 4 ? (4 - i) * std::pow(xi, i) * std::pow(1 - xi, 3 - i) : 0.0;
    b(1, i) = binom[i] * (left - right);
  }
  return b;
}

struct Evaluation {
  PairResult result;
  double energy = 0;
  Eigen::VectorXd residual;
  Eigen::MatrixXd tangent;
  ShellProximity::Projection projection;
  PairPoint pair;  // the kernel's input
};

class PairFixture {
 public:
  // Shell: `reference` with its control points moved by `shell_points`. The beam point xi = 0.4 is placed
  // at distance `distance` above the shell point (u0, v0) (an element interior), its tangent tilted so
  // that t . n = tn, then the beam is bent randomly (which changes d and t_n a little).
  PairFixture(const spline::NurbsSurface& reference, std::vector<Eigen::Vector3d> shell_points, double u0,
              double v0, double distance, double tn, unsigned seed)
      : prox_(reference), points_(std::move(shell_points)) {
    prox_.update(points_);
    const spline::NurbsSurface current(reference.knots(0), reference.knots(1), points_, reference.weights());
    const spline::SurfaceBasis b = current.basis(u0, v0);
    Eigen::Vector3d r = Eigen::Vector3d::Zero(), g1 = r, g2 = r;
    for (std::size_t a = 0; a < b.indices.size(); ++a) {
      r += b.R(0, a) * points_[b.indices[a]];
      g1 += b.R(1, a) * points_[b.indices[a]];
      g2 += b.R(2, a) * points_[b.indices[a]];
    }
    const Eigen::Vector3d n = g1.cross(g2).normalized(), e1 = g1.normalized();
    const Eigen::Vector3d t = std::sqrt(1 - tn * tn) * e1 + tn * n;
    std::mt19937 gen(seed);
    std::uniform_real_distribution<double> bend(-0.03, 0.03);
    beam_x_.resize(3, 5);
    for (int i = 0; i < 5; ++i)
      beam_x_.col(i) = (i / 4.0 - xi_) * 0.8 * t + Eigen::Vector3d(bend(gen), bend(gen), bend(gen));
    const Eigen::Vector3d rb = beam_x_ * bernstein4(xi_).row(0).transpose();
    beam_x_.colwise() += r + distance * n - rb;
    const auto proj = prox_.project(r + distance * n, Eigen::Vector2d(u0, v0));
    element_ = proj.element;
    const auto& e = prox_.elements()[element_];
    const int p = reference.degree(0), q = reference.degree(1);
    for (int j = e.span_v - q; j <= e.span_v; ++j)
      for (int i = e.span_u - p; i <= e.span_u; ++i) shell_ids_.push_back(reference.index(i, j));
    surface_ = &prox_.surface();
  }

  int size() const { return 4 * 5 + 3 * static_cast<int>(shell_ids_.size()); }
  Eigen::VectorXd dofs() const {
    Eigen::VectorXd q = Eigen::VectorXd::Zero(size());
    for (int i = 0; i < 5; ++i) q.segment<3>(4 * i) = beam_x_.col(i);
    for (std::size_t a = 0; a < shell_ids_.size(); ++a) q.segment<3>(20 + 3 * a) = points_[shell_ids_[a]];
    return q;
  }

  // Kernel at the configuration q (projection redone, warm-started at the initial foot point).
  Evaluation evaluate(const laws::LennardJonesDiskPlate& law, Formulation f, FfTangent ft,
                      const Eigen::VectorXd& q, double weight = 0.7) {
    Eigen::Matrix3Xd beam = beam_x_;
    for (int i = 0; i < 5; ++i) beam.col(i) = q.segment<3>(4 * i);
    std::vector<Eigen::Vector3d> pts = points_;
    for (std::size_t a = 0; a < shell_ids_.size(); ++a) pts[shell_ids_[a]] = q.segment<3>(20 + 3 * a);
    prox_.update(pts);
    PairPoint pp;
    pp.beam_basis = bernstein4(xi_);
    pp.beam_x = beam;
    Evaluation ev;
    ev.projection = prox_.project(beam * pp.beam_basis.row(0).transpose());
    const auto& e = prox_.elements()[element_];
    const spline::SurfaceBasis sb = surface_->basis_in(e.span_u, e.span_v, ev.projection.u, ev.projection.v);
    pp.shell_basis = sb.R;
    pp.shell_basis3 = spline::basis3_in(*surface_, e.span_u, e.span_v, ev.projection.u, ev.projection.v).R;
    pp.shell_x.resize(3, static_cast<int>(shell_ids_.size()));
    for (std::size_t a = 0; a < shell_ids_.size(); ++a) pp.shell_x.col(a) = pts[sb.indices[a]];
    pp.weight = weight;
    ev.result = add_sbs_point(law, f, ft, pp, &ev.energy, &ev.residual, &ev.tangent);
    ev.pair = pp;
    return ev;
  }

  int element() const { return element_; }

 private:
  ShellProximity prox_;
  std::vector<Eigen::Vector3d> points_;
  const spline::NurbsSurface* surface_ = nullptr;
  Eigen::Matrix3Xd beam_x_;
  double xi_ = 0.4;
  int element_ = -1;
  std::vector<int> shell_ids_;
};

}  // namespace fibrane::interaction::test
