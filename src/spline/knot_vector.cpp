#include "spline/knot_vector.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace fibrane::spline {
namespace {

[[noreturn]] void fail(const std::string& what) {
  throw std::invalid_argument("KnotVector: " + what);
}

}  // namespace

KnotVector::KnotVector(int degree, std::vector<double> knots) : degree_(degree), knots_(std::move(knots)) {
  if (degree_ < 1) fail("degree must be >= 1, got " + std::to_string(degree_));
  const std::size_t order = static_cast<std::size_t>(degree_) + 1;
  if (knots_.size() < 2 * order) {
    std::ostringstream msg;
    msg << "too few knots: " << knots_.size() << " given, degree " << degree_ << " needs at least "
        << 2 * order;
    fail(msg.str());
  }
  for (std::size_t i = 0; i < knots_.size(); ++i) {
    if (!std::isfinite(knots_[i])) fail("knot " + std::to_string(i) + " is not finite");
    if (i > 0 && knots_[i] < knots_[i - 1]) {
      std::ostringstream msg;
      msg << "knots decrease at index " << i << " (" << knots_[i - 1] << " > " << knots_[i] << ")";
      fail(msg.str());
    }
  }
  if (!(back() > front())) fail("empty parameter domain (first knot == last knot)");
  const double tol = tolerance();
  // Multiplicity of each run of (numerically) equal knots.
  std::size_t start = 0;
  while (start < knots_.size()) {
    std::size_t end = start + 1;
    while (end < knots_.size() && knots_[end] - knots_[start] <= tol) ++end;
    const std::size_t mult = end - start;
    const bool first = start == 0, last = end == knots_.size();
    if ((first || last) && mult != order) {
      std::ostringstream msg;
      msg << "not an open knot vector: the " << (first ? "first" : "last") << " knot (" << knots_[start]
          << ") appears " << mult << " times, degree " << degree_ << " requires exactly " << order;
      fail(msg.str());
    }
    if (!first && !last && mult > static_cast<std::size_t>(degree_)) {
      std::ostringstream msg;
      msg << "interior knot " << knots_[start] << " (index " << start << ") has multiplicity " << mult
          << " > degree " << degree_;
      fail(msg.str());
    }
    start = end;
  }
}

KnotVector KnotVector::open_uniform(int degree, int n_elements, int continuity, double a, double b) {
  if (degree < 1) fail("open_uniform: degree must be >= 1");
  if (n_elements < 1) fail("open_uniform: n_elements must be >= 1");
  if (continuity < 0 || continuity >= degree)
    fail("open_uniform: continuity must be in [0, degree-1], got " + std::to_string(continuity));
  if (!(b > a)) fail("open_uniform: need a < b");
  std::vector<double> knots(degree + 1, a);
  for (int k = 1; k < n_elements; ++k) {
    const double t = a + (b - a) * k / n_elements;
    knots.insert(knots.end(), degree - continuity, t);
  }
  knots.insert(knots.end(), degree + 1, b);
  return KnotVector(degree, std::move(knots));
}

double KnotVector::tolerance() const { return 1e-12 * (back() - front()); }

int KnotVector::find_span(double u) const {
  const double slack = 1e-10 * (back() - front());
  if (!(u >= front() - slack && u <= back() + slack)) {
    std::ostringstream msg;
    msg << "KnotVector::find_span: parameter " << u << " outside [" << front() << ", " << back() << "]";
    throw std::out_of_range(msg.str());
  }
  const int n = num_basis();
  if (u >= knots_[n]) return n - 1;  // last non-empty span (knots_[n-1] < knots_[n] for open knots)
  if (u <= knots_[degree_]) return degree_;
  // knots_[lo] <= u < knots_[hi] is kept invariant.
  int lo = degree_, hi = n;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (u < knots_[mid]) hi = mid; else lo = mid;
  }
  return lo;
}

std::vector<int> KnotVector::element_spans() const {
  std::vector<int> spans;
  const double tol = tolerance();
  for (int i = degree_; i < num_basis(); ++i)
    if (knots_[i + 1] - knots_[i] > tol) spans.push_back(i);
  return spans;
}

int KnotVector::num_elements() const { return static_cast<int>(element_spans().size()); }

std::vector<double> KnotVector::unique_knots() const {
  std::vector<double> unique;
  const double tol = tolerance();
  for (double k : knots_)
    if (unique.empty() || k - unique.back() > tol) unique.push_back(k);
  return unique;
}

int KnotVector::multiplicity(double u) const {
  // The knots within tol of u are contiguous (the knots increase): a binary search and a walk both ways.
  const double tol = tolerance();
  auto near = [&](double k) { return std::abs(k - u) <= tol; };
  auto first = std::lower_bound(knots_.begin(), knots_.end(), u - tol);
  while (first != knots_.begin() && near(*(first - 1))) --first;
  auto last = first;
  while (last != knots_.end() && near(*last)) ++last;
  return static_cast<int>(last - first);
}

}  // namespace fibrane::spline
