#include "interaction/soft_distance.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "spline/quadrature.hpp"

namespace fibrane::interaction {
namespace {

// Samples whose normalised weight is below this are left out of the gradient and the Hessian (their share
// of I is below round-off).
constexpr double kNegligible = 1e-18;

// ln I_plate(D) = ln(2 pi) - beta D + ln(D / beta + 1 / beta^2) and its first two derivatives.
struct PlateLog {
  double value, d1, d2;
};
PlateLog plate_log(double beta, double D) {
  const double a = D + 1.0 / beta;
  return {std::log(2.0 * std::numbers::pi) - beta * D + std::log(a / beta), -beta + 1.0 / a, -1.0 / (a * a)};
}

// The D > 0 with ln I_plate(D) = log_integral. ln I_plate falls monotonically (slope between -beta and
// -beta + 1 / D) and is nearly linear, so Newton converges in a few steps from the nearest sample.
double plate_distance(double beta, double log_integral, double start) {
  double D = start;
  for (int it = 0; it < 100; ++it) {
    const PlateLog f = plate_log(beta, D);
    const double step = (f.value - log_integral) / f.d1;
    D = std::max(D - step, 0.5 * D);
    if (std::abs(step) <= 1e-15 * D) return D;
  }
  throw std::runtime_error("soft_distance: the plate-equivalent distance did not converge");
}

// The cells [x0 + c d, x0 + (c + 1) d], 0 <= c < n, that meet [lo, hi]: c in [first, last).
std::pair<int, int> cells_meeting(double x0, double d, int n, double lo, double hi) {
  const int first = static_cast<int>(std::clamp(std::floor((lo - x0) / d), 0.0, static_cast<double>(n)));
  const int last = static_cast<int>(std::clamp(std::floor((hi - x0) / d) + 1.0, 0.0, static_cast<double>(n)));
  return {first, std::max(first, last)};
}

}  // namespace

double soft_window_half_width(double width, double d_ref) { return (std::sqrt(90.0 * width) + 0.2) * d_ref; }
double soft_window_cell(double width, double d_ref) { return 0.5 * d_ref * std::sqrt(width); }

SoftWindow make_soft_window(const spline::NurbsSurface& surface, const Eigen::Vector2d& centre, double half_width,
                            double cell, const std::vector<MirrorPlane>& mirrors) {
  if (!(half_width > 0) || !(cell > 0)) throw std::invalid_argument("make_soft_window: sizes must be positive");
  const auto& X = surface.control_points();
  auto tangents = [&](const spline::SurfaceBasis& b) {
    Eigen::Matrix<double, 3, 3> t = Eigen::Matrix3d::Zero();  // X, X_u, X_v
    for (std::size_t a = 0; a < b.indices.size(); ++a)
      for (int r = 0; r < 3; ++r) t.col(r) += b.R(r, a) * X[b.indices[a]];
    return t;
  };
  const Eigen::Matrix3d at_centre = tangents(surface.basis(centre[0], centre[1]));
  const double hu = half_width / at_centre.col(1).norm(), hv = half_width / at_centre.col(2).norm();

  SoftWindow w;
  w.half_extent = {hu, hv};
  w.basis_size = (surface.degree(0) + 1) * (surface.degree(1) + 1);
  std::vector<int> local_of(surface.num_control_points(), -1);
  const auto gauss = spline::gauss_legendre(3);
  for (const spline::SurfaceElement& e : surface.elements()) {
    if (e.u1 < centre[0] - hu || e.u0 > centre[0] + hu || e.v1 < centre[1] - hv || e.v0 > centre[1] + hv) continue;
    const Eigen::Matrix3d mid =
        tangents(surface.basis_in(e.span_u, e.span_v, 0.5 * (e.u0 + e.u1), 0.5 * (e.v0 + e.v1)));
    const int nu = std::max(1, static_cast<int>(std::ceil((e.u1 - e.u0) * mid.col(1).norm() / cell)));
    const int nv = std::max(1, static_cast<int>(std::ceil((e.v1 - e.v0) * mid.col(2).norm() / cell)));
    const double du = (e.u1 - e.u0) / nu, dv = (e.v1 - e.v0) / nv;
    // Only the element's cells that meet the box: outside it the Gibbs weights are below e^-45.
    const auto [cu0, cu1] = cells_meeting(e.u0, du, nu, centre[0] - hu, centre[0] + hu);
    const auto [cv0, cv1] = cells_meeting(e.v0, dv, nv, centre[1] - hv, centre[1] + hv);
    if (cu0 == cu1 || cv0 == cv1) continue;
    for (int cv = cv0; cv < cv1; ++cv)
      for (int cu = cu0; cu < cu1; ++cu)
        for (std::size_t qv = 0; qv < gauss.points.size(); ++qv)
          for (std::size_t qu = 0; qu < gauss.points.size(); ++qu) {
            const double u = e.u0 + du * (cu + 0.5 * (gauss.points[qu] + 1.0));
            const double v = e.v0 + dv * (cv + 0.5 * (gauss.points[qv] + 1.0));
            const spline::SurfaceBasis b = surface.basis_in(e.span_u, e.span_v, u, v);
            const Eigen::Matrix3d t = tangents(b);
            w.weight.push_back(gauss.weights[qu] * gauss.weights[qv] * 0.25 * du * dv *
                               t.col(1).cross(t.col(2)).norm());
            for (std::size_t a = 0; a < b.indices.size(); ++a) {
              int& l = local_of[b.indices[a]];
              if (l < 0) {
                l = static_cast<int>(w.control_points.size());
                w.control_points.push_back(b.indices[a]);
              }
              w.local.push_back(l);
              w.basis.push_back(b.R(0, a));
            }
          }
    w.element_begin.push_back(w.num_samples());
  }
  // Images: the identity and the mirror images across every subset of the planes near the centre.
  std::vector<MirrorPlane> near;
  for (const MirrorPlane& m : mirrors)
    if (std::abs(at_centre(m.axis, 0) - m.offset) < 2.0 * half_width) near.push_back(m);
  for (unsigned mask = 0; mask < (1u << near.size()); ++mask) {
    ShellImage image;
    for (std::size_t k = 0; k < near.size(); ++k)
      if (mask & (1u << k)) {
        // x -> reflection across x[axis] = offset, composed with the others (distinct planes commute
        // when their normals are coordinate axes).
        Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
        R(near[k].axis, near[k].axis) = -1;
        Eigen::Vector3d c = Eigen::Vector3d::Zero();
        c[near[k].axis] = 2.0 * near[k].offset;
        image.S = R * image.S;
        image.c = R * image.c + c;
      }
    w.images.push_back(image);
  }
  return w;
}

namespace {

// D, m = sum W_q grad d_q (grad ln I = -beta m) and the two coefficients of D's Hessian,
//   grad D = a m,  Hess D = a S + c m m^T,  a = -beta / F'(D),  c = -beta^2 (1 + F''(D) / F'(D)^2) / F'(D),
// with F = ln I_plate and S = sum W_q (Hess d_q - beta grad d_q grad d_q^T), which in (r_B, sample point) is
// [M, -M S_i; -S_i M, S_i M S_i], M = P / d_q - beta n n^T (S_i the image's reflection).
// Everything lives on the support: the beam DOFs and the window control points under a sample of
// non-negligible weight (a few hundred of the window's ~1000 at the bending example's paper mesh; the
// window is larger than the support so that it can stay put while the point slides). S is block-sparse
// (per sample: the beam point and the sample's basis functions) and is added, times scale(D, a), straight
// into *target (support x support, may be null); the dense rank-one part is left to the caller.
struct Parts {
  SoftDistance d;            // distance, nearest, direction, gradient on the support (hessian left empty)
  std::vector<int> support;  // support entry -> local DOF [beam CPs x 4, window CPs x 3]
  Eigen::VectorXd m;
  double a = 0, c = 0;
};

template <class Scale>
Parts soft_parts(double beta, const Eigen::RowVectorXd& beam_basis, const Eigen::Matrix3Xd& beam_x,
                 const SoftWindow& window, const Eigen::Matrix3Xd& window_x, Eigen::MatrixXd* target, Scale scale) {
  const int nb = static_cast<int>(beam_basis.size()), nw = static_cast<int>(window.control_points.size());
  if (beam_x.cols() != nb || window_x.cols() != nw || window.num_samples() == 0)
    throw std::invalid_argument("soft_distance: basis, control point and window sizes differ");
  const int k = window.basis_size;
  const int n_images = static_cast<int>(window.images.size());
  const Eigen::Vector3d rb = beam_x * beam_basis.transpose();

  // Pass 1: the distance of every sample (in every image) and the integral, scaled by the nearest.
  const int ns = window.num_samples() * n_images;
  std::vector<double> dist(ns);
  std::vector<Eigen::Vector3d> unit(ns);
  double nearest = std::numeric_limits<double>::infinity();
  for (int s = 0; s < window.num_samples(); ++s) {
    Eigen::Vector3d r = Eigen::Vector3d::Zero();
    for (int a = 0; a < k; ++a) r += window.basis[s * k + a] * window_x.col(window.local[s * k + a]);
    for (int m = 0; m < n_images; ++m) {
      const Eigen::Vector3d e = rb - (window.images[m].S * r + window.images[m].c);
      const int i = s * n_images + m;
      dist[i] = e.norm();
      unit[i] = e / dist[i];
      nearest = std::min(nearest, dist[i]);
    }
  }
  if (!(nearest > 0)) throw std::domain_error("soft_distance: beam point on the shell mid-surface");
  double Z = 0;
  std::vector<double> W(ns);
  for (int i = 0; i < ns; ++i) Z += W[i] = window.weight[i / n_images] * std::exp(-beta * (dist[i] - nearest));
  for (double& x : W) x /= Z;

  // The support's control points, in window order: slot[la] = their index, or -1.
  std::vector<int> slot(nw, -1);
  for (int i = 0; i < ns; ++i)
    if (W[i] >= kNegligible)
      for (int a = 0; a < k; ++a) slot[window.local[(i / n_images) * k + a]] = 0;
  Parts out;
  for (int j = 0; j < 4 * nb; ++j) out.support.push_back(j);
  int n_cps = 0;
  for (int la = 0; la < nw; ++la)
    if (slot[la] == 0) {
      slot[la] = n_cps++;
      for (int c = 0; c < 3; ++c) out.support.push_back(4 * nb + 3 * la + c);
    }
  const int n = static_cast<int>(out.support.size());
  if (target != nullptr) target->setZero(n, n);

  out.d.nearest = nearest;
  out.d.distance = plate_distance(beta, std::log(Z) - beta * nearest, nearest);
  const PlateLog F = plate_log(beta, out.d.distance);
  out.a = -beta / F.d1;
  out.c = -beta * beta * (1.0 + F.d2 / (F.d1 * F.d1)) / F.d1;
  const double factor = target != nullptr ? scale(out.d.distance, out.a) : 0.0;

  // Pass 2: m, and factor x S into the target (support numbering: beam DOFs, then 3 per support CP), one
  // window element at a time: its samples share their k basis functions, so with N (rows: the element's
  // significant (sample, image) pairs; columns: basis values) the element's shell block
  // sum_i N_a N_b S_i^T M_i S_i is N^T diag(.) N per component of the symmetric 3 x 3, and the beam-shell
  // block sum_i N_a M_i S_i is N^T times the rows of M_i S_i: two matrix products instead of k^2 3 x 3
  // updates per sample (3x faster at the bending example's paper mesh, bench_interaction).
  out.m = Eigen::VectorXd::Zero(n);
  Eigen::Matrix3d Mbb = Eigen::Matrix3d::Zero();
  std::vector<Eigen::Matrix3d> Mbw(target != nullptr ? n_cps : 0, Eigen::Matrix3d::Zero());
  Eigen::Vector3d mb = Eigen::Vector3d::Zero();
  Eigen::MatrixXd N, weighted, ms;  // rows x k, rows x 6k (N scaled by each of the 6 components), rows x 9
  std::vector<int> rows_of;
  for (std::size_t j = 0; j + 1 < window.element_begin.size(); ++j) {
    const int first = window.element_begin[j] * n_images, last = window.element_begin[j + 1] * n_images;
    rows_of.clear();
    for (int i = first; i < last; ++i)
      if (W[i] >= kNegligible) rows_of.push_back(i);
    if (rows_of.empty()) continue;
    const int* cps = window.local.data() + static_cast<std::size_t>(window.element_begin[j]) * k;
    const int rows = static_cast<int>(rows_of.size());
    if (target != nullptr) {
      N.resize(rows, k);
      weighted.resize(rows, 6 * k);
      ms.resize(rows, 9);
    }
    for (int row = 0; row < rows; ++row) {
      const int i = rows_of[row], s = i / n_images;
      const ShellImage& image = window.images[i % n_images];
      const Eigen::Vector3d& nn = unit[i];
      const Eigen::Vector3d sn = image.S.transpose() * nn;
      const double* basis = window.basis.data() + static_cast<std::size_t>(s) * k;
      mb += W[i] * nn;
      for (int a = 0; a < k; ++a) out.m.segment<3>(4 * nb + 3 * slot[cps[a]]) -= (W[i] * basis[a]) * sn;
      if (target == nullptr) continue;
      const Eigen::Matrix3d M =
          (factor * W[i]) * ((Eigen::Matrix3d::Identity() - nn * nn.transpose()) / dist[i] - beta * nn * nn.transpose());
      const Eigen::Matrix3d MS = M * image.S, SMS = image.S.transpose() * MS;
      Mbb += M;
      const double component[6] = {SMS(0, 0), SMS(1, 1), SMS(2, 2), SMS(0, 1), SMS(0, 2), SMS(1, 2)};
      for (int a = 0; a < k; ++a) {
        N(row, a) = basis[a];
        for (int c = 0; c < 6; ++c) weighted(row, c * k + a) = component[c] * basis[a];
      }
      for (int q = 0; q < 9; ++q) ms(row, q) = MS(q % 3, q / 3);
    }
    if (target == nullptr) continue;
    const Eigen::MatrixXd G = N.transpose() * weighted;  // k x 6k: the six component blocks
    const Eigen::MatrixXd NMS = N.transpose() * ms;      // k x 9: sum_i N_a M_i S_i, column-major 3 x 3
    static constexpr int kComponent[3][3] = {{0, 3, 4}, {3, 1, 5}, {4, 5, 2}};
    for (int a = 0; a < k; ++a) {
      const int sa = slot[cps[a]];
      for (int q = 0; q < 9; ++q) Mbw[sa](q % 3, q / 3) -= NMS(a, q);
      for (int b = 0; b < k; ++b) {
        auto block = target->block<3, 3>(4 * nb + 3 * sa, 4 * nb + 3 * slot[cps[b]]);
        for (int c = 0; c < 3; ++c)
          for (int r = 0; r < 3; ++r) block(r, c) += G(a, kComponent[r][c] * k + b);
      }
    }
  }
  for (int j = 0; j < nb; ++j) out.m.segment<3>(4 * j) = beam_basis[j] * mb;
  if (target != nullptr) {
    for (int i = 0; i < nb; ++i) {
      for (int j = 0; j < nb; ++j) target->block<3, 3>(4 * i, 4 * j) += (beam_basis[i] * beam_basis[j]) * Mbb;
      for (int a = 0; a < n_cps; ++a) {
        target->block<3, 3>(4 * i, 4 * nb + 3 * a) += beam_basis[i] * Mbw[a];
        target->block<3, 3>(4 * nb + 3 * a, 4 * i) += beam_basis[i] * Mbw[a].transpose();
      }
    }
  }
  out.d.gradient = out.a * out.m;
  out.d.direction = out.a * mb;
  return out;
}

// A support vector / matrix added into one over all local DOFs.
void expand_into(const std::vector<int>& support, const Eigen::VectorXd& part, Eigen::VectorXd& full) {
  for (std::size_t i = 0; i < support.size(); ++i) full[support[i]] += part[static_cast<Eigen::Index>(i)];
}
void expand_into(const std::vector<int>& support, const Eigen::MatrixXd& part, Eigen::MatrixXd& full) {
  for (std::size_t j = 0; j < support.size(); ++j)
    for (std::size_t i = 0; i < support.size(); ++i)
      full(support[i], support[j]) += part(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
}

// *m is sized n x n and zeroed when empty; throws if it has another size.
void prepare(Eigen::MatrixXd* m, Eigen::Index n, const char* what) {
  if (m->size() == 0) m->setZero(n, n);
  if (m->rows() != n || m->cols() != n) throw std::invalid_argument(what);
}

Eigen::Index local_size(const Eigen::RowVectorXd& beam_basis, const SoftWindow& window) {
  return 4 * beam_basis.size() + 3 * static_cast<Eigen::Index>(window.control_points.size());
}

}  // namespace

SoftDistance soft_distance(double beta, const Eigen::RowVectorXd& beam_basis, const Eigen::Matrix3Xd& beam_x,
                           const SoftWindow& window, const Eigen::Matrix3Xd& window_x, bool with_hessian) {
  const Eigen::Index n = local_size(beam_basis, window);
  Eigen::MatrixXd H;
  Parts p = soft_parts(beta, beam_basis, beam_x, window, window_x, with_hessian ? &H : nullptr,
                       [](double, double a) { return a; });
  SoftDistance d = p.d;
  d.gradient = Eigen::VectorXd::Zero(n);
  expand_into(p.support, p.d.gradient, d.gradient);
  if (with_hessian) {
    H.noalias() += p.c * p.m * p.m.transpose();
    d.hessian = Eigen::MatrixXd::Zero(n, n);
    expand_into(p.support, H, d.hessian);
  }
  return d;
}

double add_soft_rf2_point(const laws::InteractionLaw& law, double beta, const Eigen::RowVectorXd& beam_basis,
                          const Eigen::Matrix3Xd& beam_x, const SoftWindow& window, const Eigen::Matrix3Xd& window_x,
                          double offset, double weight, double* energy, Eigen::VectorXd* residual,
                          Eigen::MatrixXd* tangent, Eigen::Vector3d* force, std::vector<int>* support,
                          RankOneTerm* rank_one) {
  const Eigen::Index n = local_size(beam_basis, window);
  if (support == nullptr) {
    if (tangent != nullptr) prepare(tangent, n, "add_soft_rf2_point: tangent size");
    if (residual != nullptr) {
      if (residual->size() == 0) residual->setZero(n);
      if (residual->size() != n) throw std::invalid_argument("add_soft_rf2_point: residual size");
    }
  }
  // Hessian of weight phi(D + offset): weight (phi_dd grad D grad D^T + phi_d Hess D)
  //   = (weight phi_d a) S + weight (phi_dd a^2 + phi_d c) m m^T.
  laws::LawValue phi{};
  Eigen::MatrixXd k;
  const Parts p = soft_parts(beta, beam_basis, beam_x, window, window_x, tangent != nullptr ? &k : nullptr,
                             [&](double D, double a) {
                               phi = law.evaluate(D + offset, 1.0);
                               return weight * phi.d_d * a;
                             });
  if (tangent == nullptr) phi = law.evaluate(p.d.distance + offset, 1.0);
  if (energy != nullptr) *energy += weight * phi.value;
  const double s = weight * (phi.d_dd * p.a * p.a + phi.d_d * p.c);
  if (tangent != nullptr && rank_one != nullptr) {
    rank_one->coefficient = s;
    if (support != nullptr) {
      rank_one->vector = p.m;
    } else {
      rank_one->vector.setZero(n);
      expand_into(p.support, p.m, rank_one->vector);
    }
  } else if (tangent != nullptr) {
    k.noalias() += s * p.m * p.m.transpose();
  }
  if (support != nullptr) {
    *support = p.support;
    if (residual != nullptr) *residual = (weight * phi.d_d) * p.d.gradient;
    if (tangent != nullptr) *tangent = std::move(k);
  } else {
    if (residual != nullptr) expand_into(p.support, ((weight * phi.d_d) * p.d.gradient).eval(), *residual);
    if (tangent != nullptr) expand_into(p.support, k, *tangent);
  }
  if (force != nullptr) *force = phi.d_d * p.d.direction;
  return p.d.distance + offset;
}

}  // namespace fibrane::interaction
