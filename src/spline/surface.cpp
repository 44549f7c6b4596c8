#include "spline/surface.hpp"

#include <algorithm>
#include <stdexcept>

#include "spline/basis.hpp"
#include "spline/refinement.hpp"

namespace fibrane::spline {

NurbsSurface::NurbsSurface(KnotVector u, KnotVector v, std::vector<Eigen::Vector3d> control_points,
                           std::vector<double> weights)
    : knots_u_(std::move(u)), knots_v_(std::move(v)), points_(std::move(control_points)),
      weights_(std::move(weights)) {
  const std::size_t n = static_cast<std::size_t>(knots_u_.num_basis()) * knots_v_.num_basis();
  if (points_.size() != n)
    throw std::invalid_argument("NurbsSurface: " + std::to_string(points_.size()) +
                                " control points given, the knot vectors need " +
                                std::to_string(knots_u_.num_basis()) + " x " +
                                std::to_string(knots_v_.num_basis()));
  if (weights_.empty()) weights_.assign(n, 1.0);
  if (weights_.size() != n)
    throw std::invalid_argument("NurbsSurface: " + std::to_string(weights_.size()) + " weights given, " +
                                std::to_string(n) + " control points");
  for (std::size_t i = 0; i < n; ++i)
    if (!(weights_[i] > 0.0))
      throw std::invalid_argument("NurbsSurface: weight " + std::to_string(i) + " is not positive");
}

const KnotVector& NurbsSurface::knots(int dir) const {
  if (dir != 0 && dir != 1) throw std::invalid_argument("NurbsSurface: direction must be 0 (u) or 1 (v)");
  return dir == 0 ? knots_u_ : knots_v_;
}

bool NurbsSurface::is_rational() const {
  return std::any_of(weights_.begin(), weights_.end(), [&](double w) { return w != weights_.front(); });
}

SurfaceBasis NurbsSurface::basis(double u, double v) const {
  return basis_in(knots_u_.find_span(u), knots_v_.find_span(v), u, v);
}

void NurbsSurface::basis(double u, double v, SurfaceBasis& out, Eigen::MatrixXd& nu, Eigen::MatrixXd& nv) const {
  const int span_u = knots_u_.find_span(u), span_v = knots_v_.find_span(v);
  bspline_basis_derivs(knots_u_, span_u, u, 2, nu);
  bspline_basis_derivs(knots_v_, span_v, v, 2, nv);
  tensor_basis(span_u, span_v, nu, nv, out);
}

// With A_a = w_a N_i M_j and W = sum_a A_a (and likewise for the derivatives), R = A / W and
//   R_u  = (A_u - R W_u) / W
//   R_uu = (A_uu - 2 R_u W_u - R W_uu) / W
//   R_uv = (A_uv - R_u W_v - R_v W_u - R W_uv) / W     (quotient rule, twice)
SurfaceBasis NurbsSurface::basis_in(int span_u, int span_v, double u, double v) const {
  SurfaceBasis result;
  tensor_basis(span_u, span_v, bspline_basis_derivs(knots_u_, span_u, u, 2), bspline_basis_derivs(knots_v_, span_v, v, 2),
               result);
  return result;
}

void NurbsSurface::tensor_basis(int span_u, int span_v, const Eigen::MatrixXd& nu, const Eigen::MatrixXd& nv,
                                SurfaceBasis& out) const {
  const int p = degree(0), q = degree(1);
  const int count = (p + 1) * (q + 1);
  out.indices.resize(count);
  auto& r = out.R;
  r.resize(6, count);  // first the weighted products A, A_u, A_v, ...; then R in place, row by row
  for (int j = 0; j <= q; ++j) {
    for (int i = 0; i <= p; ++i) {
      const int local = i + (p + 1) * j;
      const int global = index(span_u - p + i, span_v - q + j);
      const double w = weights_[global];
      out.indices[local] = global;
      r(0, local) = w * nu(0, i) * nv(0, j);
      r(1, local) = w * nu(1, i) * nv(0, j);
      r(2, local) = w * nu(0, i) * nv(1, j);
      r(3, local) = w * nu(2, i) * nv(0, j);
      r(4, local) = w * nu(1, i) * nv(1, j);
      r(5, local) = w * nu(0, i) * nv(2, j);
    }
  }
  const Eigen::Matrix<double, 6, 1> w = r.rowwise().sum();
  // Each row needs only itself and rows already divided through.
  r.row(0) /= w[0];
  r.row(1) = (r.row(1) - w[1] * r.row(0)) / w[0];
  r.row(2) = (r.row(2) - w[2] * r.row(0)) / w[0];
  r.row(3) = (r.row(3) - 2.0 * w[1] * r.row(1) - w[3] * r.row(0)) / w[0];
  r.row(4) = (r.row(4) - w[2] * r.row(1) - w[1] * r.row(2) - w[4] * r.row(0)) / w[0];
  r.row(5) = (r.row(5) - 2.0 * w[2] * r.row(2) - w[5] * r.row(0)) / w[0];
}

Eigen::Vector3d NurbsSurface::point(double u, double v) const {
  const SurfaceBasis b = basis(u, v);
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  for (std::size_t a = 0; a < b.indices.size(); ++a) x += b.R(0, a) * points_[b.indices[a]];
  return x;
}

std::vector<SurfaceElement> NurbsSurface::elements() const {
  std::vector<SurfaceElement> result;
  const std::vector<double>& tu = knots_u_.knots();
  const std::vector<double>& tv = knots_v_.knots();
  for (int sv : knots_v_.element_spans())
    for (int su : knots_u_.element_spans()) result.push_back({su, sv, tu[su], tu[su + 1], tv[sv], tv[sv + 1]});
  return result;
}

template <typename Op>
void NurbsSurface::refine_rows(int dir, Op op) {
  const KnotVector& along = knots(dir);
  const int n_along = along.num_basis();
  const int n_across = num_control_points(1 - dir);
  auto global = [&](int k_along, int k_across) {
    return dir == 0 ? index(k_along, k_across) : index(k_across, k_along);
  };
  std::vector<HomogeneousCurve> rows;
  for (int c = 0; c < n_across; ++c) {
    HomogeneousPoints row(n_along);
    for (int k = 0; k < n_along; ++k) {
      const int g = global(k, c);
      row[k] << weights_[g] * points_[g], weights_[g];
    }
    rows.push_back(op(HomogeneousCurve{along, std::move(row)}));
  }
  KnotVector new_knots = rows.front().knots;
  const int new_n_along = new_knots.num_basis();
  (dir == 0 ? knots_u_ : knots_v_) = new_knots;  // index() now uses the new sizes
  points_.assign(static_cast<std::size_t>(new_n_along) * n_across, Eigen::Vector3d::Zero());
  weights_.assign(points_.size(), 1.0);
  for (int c = 0; c < n_across; ++c) {
    for (int k = 0; k < new_n_along; ++k) {
      const int g = global(k, c);
      const Eigen::Vector4d& h = rows[c].points[k];
      weights_[g] = h[3];
      points_[g] = h.head<3>() / h[3];
    }
  }
}

void NurbsSurface::insert_knot(int dir, double t, int times) {
  refine_rows(dir, [&](const HomogeneousCurve& row) { return spline::insert_knot(row, t, times); });
}

void NurbsSurface::insert_knots(int dir, const std::vector<double>& values) {
  if (values.empty()) return;
  refine_rows(dir, [&](const HomogeneousCurve& row) { return spline::insert_knots(row, values); });
}

void NurbsSurface::elevate_degree(int dir, int by) {
  refine_rows(dir, [&](const HomogeneousCurve& row) { return spline::elevate_degree(row, by); });
}

void NurbsSurface::refine(int dir, int degree, int continuity, int n_elements) {
  check_refine_request(this->degree(dir), degree, continuity, n_elements);
  elevate_degree(dir, degree - this->degree(dir));
  insert_knots(dir, expand_insertions(uniform_insertions(knots(dir), continuity, n_elements)));
}

void NurbsSurface::refine(int dir, int degree, int continuity, const std::vector<double>& grid) {
  check_refine_request(this->degree(dir), degree, continuity, static_cast<int>(grid.size()) + 1);
  elevate_degree(dir, degree - this->degree(dir));
  insert_knots(dir, expand_insertions(grid_insertions(knots(dir), continuity, grid)));
}

std::vector<int> NurbsSurface::edge_indices(const std::string& edge, int row) const {
  const int nu = num_control_points(0), nv = num_control_points(1);
  const bool along_v = edge == "u0" || edge == "u1";  // u = const edges run along v
  if (!along_v && edge != "v0" && edge != "v1")
    throw std::invalid_argument("edge_indices: unknown edge '" + edge + "' (use u0, u1, v0, v1)");
  const int rows_available = along_v ? nu : nv;
  if (row < 0 || row >= rows_available)
    throw std::invalid_argument("edge_indices: row " + std::to_string(row) + " out of range for edge " + edge);
  std::vector<int> result;
  if (along_v) {
    const int i = edge == "u0" ? row : nu - 1 - row;
    for (int j = 0; j < nv; ++j) result.push_back(index(i, j));
  } else {
    const int j = edge == "v0" ? row : nv - 1 - row;
    for (int i = 0; i < nu; ++i) result.push_back(index(i, j));
  }
  return result;
}

}  // namespace fibrane::spline
