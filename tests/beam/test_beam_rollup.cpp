// Roll-up of a straight cantilever under an end moment, with a small dense Newton driver (fixed DOFs
// eliminated, load stepping, incremental frame update after each converged step). Analytical solution:
// the beam bends into a circle of radius EI / M, so M = pi EI / L gives a half circle with the tip at
// height 2L/pi above the root, and M = 2 pi EI / L closes the circle (tip back at the root). This
// checks the strain definitions, which finite-difference checks cannot.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <string>

#include "beam/beam.hpp"
#include "beam_test_geometry.hpp"

namespace fibrane::beam {
namespace {

using namespace testing;

struct QuadraturePoint {
  int first;  // first control point of the support
  BasisDerivs R;
  double weight;
  BeamPointState state;
};

class Cantilever {
 public:
  Cantilever(int degree, int elements, double length, const BeamSection& section)
      : p_(degree), section_(section), n_cp_(elements + degree) {
    const std::vector<double> u = open_knots(degree, elements);
    X_.resize(3, n_cp_);
    for (int i = 0; i < n_cp_; ++i) {  // Greville abscissae give a uniform (linear) parametrisation
      double g = 0;
      for (int k = 1; k <= degree; ++k) g += u[i + k] / degree;
      X_.col(i) = Eigen::Vector3d(length * g, 0, 0);
    }
    std::vector<double> gp, gw;
    gauss_legendre(degree + 1, gp, gw);
    for (int e = 0; e < elements; ++e)
      for (size_t k = 0; k < gp.size(); ++k) {
        const double xi = (e + gp[k]) / elements;
        QuadraturePoint qp;
        qp.R = bspline_basis(u, degree, xi, &qp.first);
        qp.weight = gw[k] / elements;
        qp.state = make_point_state(qp.R, X_.middleCols(qp.first, degree + 1), Eigen::Vector3d::UnitY());
        points_.push_back(qp);
      }
    tip_.R = bspline_basis(u, degree, 1.0, &tip_.first);
    tip_.state = make_point_state(tip_.R, X_.middleCols(tip_.first, degree + 1), Eigen::Vector3d::UnitY());
    q_ = reference_dofs(X_);
  }

  // Solves for the end moment M; returns the number of Newton iterations (-1: no convergence).
  int solve(const Eigen::Vector3d& M) {
    const std::vector<int> free = free_dofs();
    for (int it = 0; it < 30; ++it) {
      Eigen::VectorXd r = Eigen::VectorXd::Zero(4 * n_cp_);
      Eigen::MatrixXd K = Eigen::MatrixXd::Zero(4 * n_cp_, 4 * n_cp_);
      assemble(M, r, K);
      Eigen::VectorXd rf(free.size());
      Eigen::MatrixXd Kf(free.size(), free.size());
      for (size_t a = 0; a < free.size(); ++a) {
        rf[a] = r[free[a]];
        for (size_t b = 0; b < free.size(); ++b) Kf(a, b) = K(free[a], free[b]);
      }
      // Residual scale: the applied moment; converged well below what the geometry checks resolve.
      if (rf.norm() < 1e-9 * std::max(1.0, M.norm())) return it;
      const Eigen::VectorXd dq = Kf.partialPivLu().solve(-rf);
      for (size_t a = 0; a < free.size(); ++a) q_.data()[free[a]] += dq[a];
    }
    return -1;
  }

  void update_frames() {
    for (QuadraturePoint& qp : points_) update_point_state(qp.state, qp.R, q_.middleCols(qp.first, p_ + 1));
    update_point_state(tip_.state, tip_.R, q_.middleCols(tip_.first, p_ + 1));
  }

  Eigen::Vector3d tip() const { return q_.col(n_cp_ - 1).head<3>(); }

 private:
  // Clamp: position and twist of the first control point, position of the second (fixes the tangent).
  std::vector<int> free_dofs() const {
    std::vector<int> free;
    for (int i = 0; i < 4 * n_cp_; ++i)
      if (i >= 8 || i == 7) free.push_back(i);
    return free;
  }

  void assemble(const Eigen::Vector3d& M, Eigen::VectorXd& r, Eigen::MatrixXd& K) const {
    const int m = 4 * (p_ + 1);
    for (const QuadraturePoint& qp : points_) {
      Eigen::VectorXd re;
      Eigen::MatrixXd Ke;
      add_beam_point(section_, qp.R, q_.middleCols(qp.first, p_ + 1), qp.state, qp.weight, nullptr, &re, &Ke);
      r.segment(4 * qp.first, m) += re;
      K.block(4 * qp.first, 4 * qp.first, m, m) += Ke;
    }
    Eigen::VectorXd re;
    Eigen::MatrixXd Ke;
    add_point_moment(M, tip_.R, q_.middleCols(tip_.first, p_ + 1), tip_.state, &re, &Ke);
    r.segment(4 * tip_.first, m) += re;
    K.block(4 * tip_.first, 4 * tip_.first, m, m) += Ke;
  }

  int p_;
  BeamSection section_;
  int n_cp_;
  Eigen::Matrix3Xd X_;
  std::vector<QuadraturePoint> points_;
  QuadraturePoint tip_;
  BeamDofs q_;
};

TEST(BeamRollUp, CantileverUnderEndMomentRollsIntoCircle) {
  const double L = 1.0, radius = 0.01;
  // E chosen so that E I = 1; slender (L / radius = 100), so axial stretching is negligible.
  const BeamSection s = BeamSection::circular(4.0 / (M_PI * std::pow(radius, 4)), 0.3, radius);
  const double EI = s.young * s.inertia3;
  Cantilever beam(3, 24, L, s);
  const int steps = 16;
  const double full = 2 * M_PI * EI / L;
  for (int k = 1; k <= steps; ++k) {
    const int iterations = beam.solve(Eigen::Vector3d(0, 0, full * k / steps));
    ASSERT_GE(iterations, 0) << "Newton failed at step " << k;
    beam.update_frames();
    if (k == steps / 2) {
      // Half circle: tip at (0, 2L/pi, 0); 0.5% of L as required.
      RecordProperty("half_circle_tip_error", std::to_string((beam.tip() - Eigen::Vector3d(0, 2 * L / M_PI, 0)).norm()));
      EXPECT_LT((beam.tip() - Eigen::Vector3d(0, 2 * L / M_PI, 0)).norm(), 0.005 * L) << beam.tip().transpose();
    }
  }
  RecordProperty("full_circle_tip_error", std::to_string(beam.tip().norm()));
  EXPECT_LT(beam.tip().norm(), 0.005 * L) << beam.tip().transpose();
}

}  // namespace
}  // namespace fibrane::beam
