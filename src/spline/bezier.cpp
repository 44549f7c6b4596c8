#include "spline/bezier.hpp"

#include <stdexcept>
#include <string>

namespace fibrane::spline {

static_assert(sizeof(Eigen::Vector3d) == 3 * sizeof(double), "extract_points maps std::vector<Vector3d> as 3 x n");

namespace {

// De Boor's algorithm evaluated as a blossom: the p arguments x_1..x_p replace the single parameter of
// the ordinary algorithm, one per level. `rows` holds the p+1 control vectors of span s (local j =
// global s-p+j) and is overwritten; the result is its last row. For x_r in [t_s, t_{s+1}] every
// alpha lies in [0, 1] and the denominators are at least t_{s+1} - t_s > 0.
Eigen::RowVectorXd blossom(const std::vector<double>& t, int p, int s, const std::vector<double>& x,
                           Eigen::MatrixXd rows) {
  for (int r = 1; r <= p; ++r) {
    for (int j = p; j >= r; --j) {
      const int i = s - p + j;
      const double alpha = (x[r - 1] - t[i]) / (t[i + p + 1 - r] - t[i]);
      rows.row(j) = (1.0 - alpha) * rows.row(j - 1) + alpha * rows.row(j);
    }
  }
  return rows.row(p);
}

// Bezier weights wb = (C_u (x) C_v)^T w, laid out b = k + (p+1) l.
std::vector<double> bezier_weights(const BezierElement& e) {
  const Eigen::Map<const Eigen::MatrixXd> w(e.nurbs_weights.data(), e.degree_u + 1, e.degree_v + 1);
  const Eigen::MatrixXd wb = e.extraction_u.transpose() * w * e.extraction_v;
  return {wb.data(), wb.data() + wb.size()};
}

}  // namespace

Eigen::MatrixXd bezier_extraction_operator(const KnotVector& kv, int span) {
  const int p = kv.degree();
  const std::vector<double>& t = kv.knots();
  if (span < p || span >= kv.num_basis())
    throw std::invalid_argument("bezier_extraction_operator: span " + std::to_string(span) + " out of range");
  if (!(t[span + 1] > t[span]))
    throw std::invalid_argument("bezier_extraction_operator: span " + std::to_string(span) + " is empty");
  Eigen::MatrixXd c(p + 1, p + 1);
  std::vector<double> x(p);
  for (int k = 0; k <= p; ++k) {
    for (int r = 0; r < p; ++r) x[r] = r < p - k ? t[span] : t[span + 1];
    // Control vectors e_i: the blossom of N_{span-p+i} for all i at once.
    c.col(k) = blossom(t, p, span, x, Eigen::MatrixXd::Identity(p + 1, p + 1)).transpose();
  }
  return c;
}

Eigen::MatrixXd BezierElement::extract(const Eigen::Ref<const Eigen::MatrixXd>& values) const {
  const int nu = degree_u + 1, nv = degree_v + 1;
  Eigen::MatrixXd result(values.rows(), num_points());
  Eigen::MatrixXd local(nu, nv);
  for (Eigen::Index c = 0; c < values.rows(); ++c) {
    for (int a = 0; a < nu * nv; ++a) {
      const int global = nurbs_indices[a];
      if (global < 0 || global >= values.cols())
        throw std::invalid_argument("BezierElement::extract: control point " + std::to_string(global) +
                                    " but only " + std::to_string(values.cols()) + " columns given");
      local(a % nu, a / nu) = nurbs_weights[a] * values(c, global);
    }
    const Eigen::MatrixXd homogeneous = extraction_u.transpose() * local * extraction_v;
    for (int b = 0; b < nu * nv; ++b) result(c, b) = homogeneous(b % nu, b / nu) / weights[b];
  }
  return result;
}

std::vector<Eigen::Vector3d> BezierElement::extract_points(const std::vector<Eigen::Vector3d>& points) const {
  // std::vector<Vector3d> stores the coordinates contiguously (Vector3d has no padding).
  const Eigen::Map<const Eigen::Matrix3Xd> columns(reinterpret_cast<const double*>(points.data()), 3,
                                                   static_cast<Eigen::Index>(points.size()));
  const Eigen::MatrixXd bezier = extract(columns);
  std::vector<Eigen::Vector3d> result(bezier.cols());
  for (Eigen::Index b = 0; b < bezier.cols(); ++b) result[b] = bezier.col(b);
  return result;
}

std::vector<BezierElement> bezier_elements(const NurbsCurve& curve) {
  const KnotVector& kv = curve.knots();
  const int p = kv.degree();
  std::vector<BezierElement> result;
  for (const int span : kv.element_spans()) {
    BezierElement e;
    e.degree_u = p;
    e.span_u = span;
    e.u0 = kv.knots()[span];
    e.u1 = kv.knots()[span + 1];
    for (int i = 0; i <= p; ++i) {
      e.nurbs_indices.push_back(span - p + i);
      e.nurbs_weights.push_back(curve.weights()[span - p + i]);
    }
    e.extraction_u = bezier_extraction_operator(kv, span);
    e.extraction_v = Eigen::MatrixXd::Identity(1, 1);
    e.weights = bezier_weights(e);
    result.push_back(std::move(e));
  }
  return result;
}

std::vector<BezierElement> bezier_elements(const NurbsSurface& surface) {
  const int p = surface.degree(0), q = surface.degree(1);
  std::vector<Eigen::MatrixXd> cu, cv;  // operators per span, computed once per element column / row
  const std::vector<int> spans_u = surface.knots(0).element_spans(), spans_v = surface.knots(1).element_spans();
  for (const int s : spans_u) cu.push_back(bezier_extraction_operator(surface.knots(0), s));
  for (const int s : spans_v) cv.push_back(bezier_extraction_operator(surface.knots(1), s));
  std::vector<BezierElement> result;
  for (std::size_t ev = 0; ev < spans_v.size(); ++ev) {
    for (std::size_t eu = 0; eu < spans_u.size(); ++eu) {
      BezierElement e;
      e.degree_u = p;
      e.degree_v = q;
      e.span_u = spans_u[eu];
      e.span_v = spans_v[ev];
      e.u0 = surface.knots(0).knots()[e.span_u];
      e.u1 = surface.knots(0).knots()[e.span_u + 1];
      e.v0 = surface.knots(1).knots()[e.span_v];
      e.v1 = surface.knots(1).knots()[e.span_v + 1];
      for (int j = 0; j <= q; ++j) {
        for (int i = 0; i <= p; ++i) {
          const int global = surface.index(e.span_u - p + i, e.span_v - q + j);
          e.nurbs_indices.push_back(global);
          e.nurbs_weights.push_back(surface.weights()[global]);
        }
      }
      e.extraction_u = cu[eu];
      e.extraction_v = cv[ev];
      e.weights = bezier_weights(e);
      result.push_back(std::move(e));
    }
  }
  return result;
}

}  // namespace fibrane::spline
