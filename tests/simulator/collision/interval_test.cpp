#include "simulator/collision/interval.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace arphys::collision {
namespace {

// long double (64-bit mantissa) holds the exact sum and product of two doubles of
// similar magnitude, so it can judge whether an enclosure really contains the result.
bool contains(const Interval& x, long double exact) { return x.lo <= exact && exact <= x.hi; }

TEST(Interval, SumOfPointOneAndPointTwoEnclosesTheExactSum) {
  const Interval s = Interval(0.1) + Interval(0.2);
  const long double exact = static_cast<long double>(0.1) + static_cast<long double>(0.2);
  EXPECT_TRUE(contains(s, exact));
  // Round-to-nearest alone gives a point that is not the exact sum.
  EXPECT_NE(static_cast<long double>(0.1 + 0.2), exact);
  EXPECT_LT(s.width(), 1e-15);
}

TEST(Interval, RandomOperationsEncloseLongDoubleResults) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-10, 10), frac(0, 1);
  for (int i = 0; i < 20000; ++i) {
    double a = u(rng), b = u(rng), c = u(rng), d = u(rng);
    if (a > b) std::swap(a, b);
    if (c > d) std::swap(c, d);
    const Interval X{a, b}, Y{c, d};
    const long double x = a + (b - a) * frac(rng), y = c + (d - c) * frac(rng);
    // Points inside the intervals, checked against the exact long double operations.
    const long double xd = static_cast<double>(x), yd = static_cast<double>(y);
    ASSERT_TRUE(contains(X + Y, xd + yd));
    ASSERT_TRUE(contains(X - Y, xd - yd));
    ASSERT_TRUE(contains(X * Y, xd * yd));
    ASSERT_TRUE(contains(square(X), xd * xd));
    if (!Y.contains_zero()) {
      ASSERT_TRUE(contains(X / Y, xd / yd)) << a << " " << b << " / " << c << " " << d;
    }
    ASSERT_TRUE(contains(sin(X), std::sin(xd)));
    ASSERT_TRUE(contains(cos(X), std::cos(xd)));
  }
}

TEST(Interval, SinAndCosReachTheirExtremaInsideTheInterval) {
  EXPECT_EQ(sin(Interval(1.5, 1.6)).hi, 1.0);         // pi/2 inside
  EXPECT_EQ(cos(Interval(3.1, 3.2)).lo, -1.0);        // pi inside
  EXPECT_EQ(sin(Interval(-1.6, -1.5)).lo, -1.0);      // -pi/2 inside
  EXPECT_EQ(cos(Interval(2 * M_PI - 0.01, 2 * M_PI + 0.01)).hi, 1.0);
  const Interval s = sin(Interval(0.1, 0.2));         // monotone: end values only
  EXPECT_NEAR(s.lo, std::sin(0.1), 1e-15);
  EXPECT_NEAR(s.hi, std::sin(0.2), 1e-15);
  EXPECT_LT(s.hi, 0.2);
  const Interval wide = cos(Interval(0, 7));
  EXPECT_EQ(wide.lo, -1.0);
  EXPECT_EQ(wide.hi, 1.0);
}

TEST(Interval, MignitudeAndMagnitude) {
  EXPECT_EQ(Interval(-2, 3).mig(), 0.0);
  EXPECT_EQ(Interval(-2, 3).mag(), 3.0);
  EXPECT_EQ(Interval(-5, -2).mig(), 2.0);
  EXPECT_TRUE(std::isinf(reciprocal(Interval(-1, 1)).hi));
}

TEST(Interval, MidRadRoundTripEnclosesTheOriginal) {
  IVec3 v{{Interval(0.1, 0.3), Interval(-1e-300, 1e-300), Interval(1e10, 1e10 + 1)}};
  const IVec3 back = MidRadVector::from(v).to_interval();
  for (int i = 0; i < 3; ++i) {
    EXPECT_LE(back[i].lo, v[i].lo);
    EXPECT_GE(back[i].hi, v[i].hi);
  }
}

}  // namespace
}  // namespace arphys::collision
