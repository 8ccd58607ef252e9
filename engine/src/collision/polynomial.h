// Private: real roots of polynomials of degree <= 4 on an interval, without closed forms.
//
// Following Yuksel, "High-Performance Polynomial Root Finding for Graphics" (HPG 2022): the real roots of
// the derivative split the interval into pieces on which the polynomial is monotone; each piece holds at
// most one root, which a safeguarded Newton-bisection finds to the last bit. No Ferrari or Cardano
// formulas, whose cancellation makes them unreliable near double roots (docs/numerics.md).
#pragma once

#include <array>
#include <optional>

namespace rattle::detail {

/// c[0] + c[1] t + ... + c[degree] t^degree.
struct Polynomial {
  std::array<double, 5> c{};
  int degree = 0;

  double operator()(double t) const {
    double v = c[degree];
    for (int i = degree - 1; i >= 0; --i) v = v * t + c[i];
    return v;
  }
  Polynomial derivative() const {
    Polynomial d;
    d.degree = degree > 0 ? degree - 1 : 0;
    for (int i = 1; i <= degree; ++i) d.c[i - 1] = c[i] * i;
    return d;
  }
  /// Drops leading zero coefficients so `degree` is the true degree.
  Polynomial trimmed() const {
    Polynomial p = *this;
    while (p.degree > 0 && p.c[p.degree] == 0) --p.degree;
    return p;
  }
};

/// The real roots in [lo, hi], ascending, each once; at most 4. Returns the count. A root where the
/// polynomial only touches zero (even multiplicity) may or may not be listed: callers decide on sign
/// changes, not on roots.
int rootsIn(const Polynomial& p, double lo, double hi, std::array<double, 4>& roots);

/// The first t in [lo, hi] where p crosses from >= 0 to < 0 (p(t) = 0 and p < 0 just after), or nothing.
/// A touch of zero from above (a tangent, a double root) is not a crossing.
std::optional<double> firstDownwardCrossing(const Polynomial& p, double lo, double hi);

}  // namespace rattle::detail
