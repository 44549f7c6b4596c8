#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "spline/knot_vector.hpp"

namespace fibrane::spline {
namespace {

// Expects construction to throw std::invalid_argument whose message contains `fragment`.
void expect_rejected(int degree, std::vector<double> knots, const std::string& fragment) {
  try {
    KnotVector kv(degree, std::move(knots));
    FAIL() << "accepted an invalid knot vector (expected a message containing '" << fragment << "')";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << "message: " << e.what();
  }
}

TEST(KnotVector, RejectsDecreasingKnots) {
  expect_rejected(2, {0, 0, 0, 0.5, 0.25, 1, 1, 1}, "knots decrease at index 4 (0.5 > 0.25)");
}

TEST(KnotVector, RejectsWrongMultiplicity) {
  expect_rejected(2, {0, 0, 0.5, 1, 1, 1}, "first knot");          // end not repeated p+1 times
  expect_rejected(2, {0, 0, 0, 0.5, 1, 1}, "last knot");
  expect_rejected(2, {0, 0, 0, 0, 1, 1, 1}, "first knot");         // end repeated too often
  expect_rejected(2, {0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1}, "multiplicity 3 > degree 2");
}

TEST(KnotVector, RejectsTooFewKnotsAndBadDegree) {
  expect_rejected(3, {0, 0, 0, 1, 1, 1}, "too few knots");
  expect_rejected(0, {0, 1}, "degree must be >= 1");
  expect_rejected(1, {1, 1, 1, 1}, "empty parameter domain");
}

TEST(KnotVector, OpenUniformHasRequestedStructure) {
  const KnotVector kv = KnotVector::open_uniform(4, 5, 1, -2.0, 3.0);
  EXPECT_EQ(kv.degree(), 4);
  EXPECT_EQ(kv.num_elements(), 5);
  EXPECT_EQ(kv.multiplicity(-2.0), 5);
  EXPECT_EQ(kv.multiplicity(3.0), 5);
  for (double t : {-1.0, 0.0, 1.0, 2.0}) EXPECT_EQ(kv.multiplicity(t), 3) << t;  // p - continuity
  EXPECT_EQ(kv.multiplicity(0.5), 0);
  EXPECT_EQ(kv.num_basis(), static_cast<int>(kv.knots().size()) - 5);
  EXPECT_EQ(kv.unique_knots(), (std::vector<double>{-2, -1, 0, 1, 2, 3}));
  EXPECT_THROW(KnotVector::open_uniform(2, 3, 2), std::invalid_argument);
}

TEST(KnotVector, FindSpanAndElements) {
  const KnotVector kv(2, {0, 0, 0, 0.25, 0.5, 0.5, 1, 1, 1});
  EXPECT_EQ(kv.num_basis(), 6);
  EXPECT_EQ(kv.find_span(0.0), 2);
  EXPECT_EQ(kv.find_span(0.1), 2);
  EXPECT_EQ(kv.find_span(0.25), 3);
  EXPECT_EQ(kv.find_span(0.4999), 3);
  EXPECT_EQ(kv.find_span(0.5), 5);  // knots[5] = 0.5 <= u < knots[6]
  EXPECT_EQ(kv.find_span(0.75), 5);
  EXPECT_EQ(kv.find_span(1.0), 5);  // last knot -> last non-empty span
  EXPECT_THROW(kv.find_span(1.1), std::out_of_range);
  EXPECT_EQ(kv.element_spans(), (std::vector<int>{2, 3, 5}));
  EXPECT_EQ(kv.num_elements(), 3);
  EXPECT_EQ(kv.multiplicity(0.5), 2);
  EXPECT_EQ(kv.multiplicity(0.5 + 1e-14), 2);  // within the 1e-12 relative tolerance
}

}  // namespace
}  // namespace fibrane::spline
