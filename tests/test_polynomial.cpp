// The roots under every time of impact (collision/polynomial.h), against analytic roots and a dense
// sampling of the sign.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "collision/polynomial.h"

namespace {

using rattle::detail::firstDownwardCrossing;
using rattle::detail::Polynomial;

// The coefficients of (t - r) * q(t) * s: downward through r when s * q(r) < 0.
Polynomial timesRoot(const Polynomial& q, double r, double s) {
  Polynomial p;
  p.degree = q.degree + 1;
  for (int k = 0; k <= q.degree; ++k) {
    p.c[k + 1] += s * q.c[k];
    p.c[k] -= s * r * q.c[k];
  }
  return p;
}

TEST(Polynomial, FirstDownwardCrossingOfAQuarticIsItsFirstFallingRoot) {
  // (t - 0.25)(t - 0.5)(t - 0.75)(t - 2): positive at 0, falls through 0.25, rises at 0.5, falls at 0.75.
  Polynomial q;
  q.degree = 0;
  q.c[0] = 1;
  Polynomial p = timesRoot(timesRoot(timesRoot(timesRoot(q, 0.25, 1), 0.5, 1), 0.75, 1), 2.0, 1);
  ASSERT_EQ(p.degree, 4);
  EXPECT_NEAR(*firstDownwardCrossing(p, 0, 1), 0.25, 1e-15);
  EXPECT_NEAR(*firstDownwardCrossing(p, 0.3, 1), 0.75, 1e-15);
  EXPECT_FALSE(firstDownwardCrossing(p, 0.3, 0.7).has_value());  // negative, then rising: no fall
  EXPECT_FALSE(firstDownwardCrossing(p, 0.8, 1.9).has_value());  // negative throughout
}

TEST(Polynomial, AFarPairHasNoCrossingAndANearOneKeepsIt) {
  // A gap that stays far above zero over the step: nothing. The same gap with its constant lowered so
  // that it reaches zero just before the step's end: the root, to round-off, however little the other
  // terms weigh against the constant (where a bound on the other terms nearly decides the sign).
  Polynomial far;
  far.degree = 2;
  far.c = {49.5, -40.0, -4.905, 0, 0};
  EXPECT_FALSE(firstDownwardCrossing(far, 0, 1.0 / 60).has_value());
  const double h = 1.0 / 60;
  Polynomial near = far;
  near.c[0] = 40.0 * h + 4.905 * h * h - 1e-13;
  const auto t = firstDownwardCrossing(near, 0, h);
  ASSERT_TRUE(t.has_value());
  EXPECT_NEAR(*t, h, 1e-13);
}

TEST(Polynomial, FirstDownwardCrossingAgreesWithADenseSampling) {
  // Random quartics, some with a falling root placed in the interval: the answer is the first falling
  // root that a sampling of the sign on 20,001 points sees, or nothing when the sampling sees none.
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(-1, 1);
  int crossings = 0, none = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    Polynomial p;
    p.degree = 4;
    const double scale = std::pow(10.0, 4 * unit(random));
    for (double& c : p.c) c = unit(random);
    p.c[0] = scale * std::fabs(p.c[0]) * (trial % 3 == 0 ? -1 : 1);
    if (trial % 2 == 0) {
      Polynomial q;
      q.degree = 3;
      for (int k = 0; k < 4; ++k) q.c[k] = p.c[k + 1];
      q.c[0] = 1 + std::fabs(q.c[0]);
      p = timesRoot(q, 0.1 + 0.8 * std::fabs(unit(random)), -1);
    }
    const double lo = 0, hi = 1;
    const int samples = 20000;
    std::optional<double> sampled;
    bool wasNonNegative = p(lo) >= 0;
    bool marginal = false;
    for (int i = 1; i <= samples && !sampled; ++i) {
      const double t = lo + (hi - lo) * i / samples;
      const double v = p(t);
      // Within round-off of zero the sampling cannot tell: such a trial is left out.
      double size = 0;
      for (int k = p.degree; k >= 0; --k) size = size * t + std::fabs(p.c[k]);
      if (std::fabs(v) <= 1e-9 * size) marginal = true;
      if (v < 0 && wasNonNegative) sampled = t;
      wasNonNegative = v >= 0;
    }
    if (marginal) continue;
    const auto found = firstDownwardCrossing(p, lo, hi);
    ASSERT_EQ(found.has_value(), sampled.has_value()) << "trial " << trial;
    if (sampled) {
      EXPECT_LE(*found, *sampled) << "trial " << trial;
      EXPECT_GE(*found, *sampled - (hi - lo) / samples) << "trial " << trial;
      ++crossings;
    } else {
      ++none;
    }
  }
  // Both kinds were asked about, often.
  EXPECT_GT(crossings, 1000);
  EXPECT_GT(none, 1000);
}

}  // namespace
