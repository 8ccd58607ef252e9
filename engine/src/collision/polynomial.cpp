#include "collision/polynomial.h"

#include <algorithm>
#include <cmath>

namespace rattle::detail {
namespace {

// The root of p in [a, b] when p(a) and p(b) differ in sign (or one is zero), with p monotone there.
// Newton steps that stay inside the bracket, bisection otherwise; stops when the bracket cannot shrink.
double rootInBracket(const Polynomial& p, const Polynomial& dp, double a, double b, double pa) {
  const bool increasing = pa < 0;  // monotone piece: sign at a tells the direction
  double t = a + 0.5 * (b - a);
  for (int i = 0; i < 200; ++i) {
    const double v = p(t);
    if (v == 0) return t;
    if ((v < 0) == increasing) {
      a = t;
    } else {
      b = t;
    }
    const double mid = a + 0.5 * (b - a);
    if (mid <= a || mid >= b) break;  // a and b are neighbouring doubles
    const double d = dp(t);
    double next = d != 0 ? t - v / d : mid;
    if (!(next > a && next < b)) next = mid;
    t = next;
  }
  // Of the two ends of the final bracket, the one with the smaller |p|.
  return std::fabs(p(a)) <= std::fabs(p(b)) ? a : b;
}

int rootsRecursive(const Polynomial& p, double lo, double hi, std::array<double, 4>& roots) {
  if (p.degree == 0) return 0;
  if (p.degree == 1) {
    const double t = -p.c[0] / p.c[1];
    if (t >= lo && t <= hi) {
      roots[0] = t;
      return 1;
    }
    return 0;
  }
  // Critical points split [lo, hi] into monotone pieces.
  std::array<double, 4> critical{};
  const Polynomial dp = p.derivative().trimmed();
  const int nc = rootsRecursive(dp, lo, hi, critical);
  std::array<double, 6> ends{};
  int ne = 0;
  ends[ne++] = lo;
  for (int i = 0; i < nc; ++i) {
    if (critical[i] > ends[ne - 1]) ends[ne++] = critical[i];
  }
  if (hi > ends[ne - 1]) ends[ne++] = hi;
  int n = 0;
  double pa = p(ends[0]);
  if (pa == 0) roots[n++] = ends[0];
  for (int i = 0; i + 1 < ne; ++i) {
    const double a = ends[i], b = ends[i + 1];
    const double pb = p(b);
    if (pb == 0) {
      if (n == 0 || roots[n - 1] != b) roots[n++] = b;
    } else if (pa != 0 && (pa < 0) != (pb < 0)) {
      const double r = rootInBracket(p, dp, a, b, pa);
      if (n == 0 || roots[n - 1] != r) roots[n++] = r;
    }
    pa = pb;
    if (n == 4) break;
  }
  return n;
}

// Whether p, as evaluated below (Horner's rule), keeps one strict sign at every t of [lo, hi], by a bound
// that needs no roots: |t| <= m there, so |p(t) - c0| <= S with S = sum |c_k| m^k (k >= 1), and Horner's
// rounding is within gamma_2d (|c0| + S), gamma_2d = 2d u / (1 - 2d u) < 1e-15 for d <= 4 (Higham,
// "Accuracy and Stability of Numerical Algorithms", 2nd ed., eq. 5.3). Most pairs a broad phase hands
// over are far apart for the whole step, and this answers them with a few products instead of every root
// of p and p'. Positive throughout or negative throughout, p has no downward crossing there, and
// firstDownwardCrossing's pieces would all read that one sign: its answer, nothing, is the same bit for
// bit. A non-finite coefficient or end fails the test and takes the exact path.
bool oneSignThroughout(const Polynomial& p, double lo, double hi) {
  const double m = std::max(std::fabs(lo), std::fabs(hi));
  double s = 0;
  for (int k = p.degree; k >= 1; --k) s = (s + std::fabs(p.c[k])) * m;
  return std::fabs(p.c[0]) - s > 1e-12 * (std::fabs(p.c[0]) + s);
}

}  // namespace

int rootsIn(const Polynomial& p, double lo, double hi, std::array<double, 4>& roots) {
  if (!(lo <= hi)) return 0;
  return rootsRecursive(p.trimmed(), lo, hi, roots);
}

std::optional<double> firstDownwardCrossing(const Polynomial& poly, double lo, double hi) {
  if (!(lo <= hi)) return std::nullopt;
  const Polynomial p = poly.trimmed();
  if (p.degree == 0) return std::nullopt;
  if (oneSignThroughout(p, lo, hi)) return std::nullopt;
  // Candidate instants: the ends, the critical points and the roots. Between two consecutive
  // candidates p keeps one sign, so the first piece on which p < 0, entered from p >= 0, begins at the
  // crossing. The sign is read at each piece's midpoint, which is what makes a tangent touch (p >= 0 on
  // both sides) no crossing.
  std::array<double, 4> roots{}, critical{};
  const int nr = rootsIn(p, lo, hi, roots);
  const int nc = rootsIn(p.derivative(), lo, hi, critical);
  std::array<double, 10> ts{};
  int n = 0;
  ts[n++] = lo;
  for (int i = 0; i < nr; ++i) ts[n++] = roots[i];
  for (int i = 0; i < nc; ++i) ts[n++] = critical[i];
  ts[n++] = hi;
  std::sort(ts.begin(), ts.begin() + n);
  bool wasNonNegative = p(lo) >= 0;
  for (int i = 0; i + 1 < n; ++i) {
    if (!(ts[i + 1] > ts[i])) continue;
    const double mid = ts[i] + 0.5 * (ts[i + 1] - ts[i]);
    if (mid == ts[i] || mid == ts[i + 1]) continue;  // neighbouring doubles: no inside to read
    const bool negative = p(mid) < 0;
    if (negative && wasNonNegative) return ts[i];
    wasNonNegative = !negative;
  }
  // A crossing at hi itself (or within an ulp of it) leaves no piece after it to read: p has come down
  // to zero there and is falling.
  if (wasNonNegative && p(hi) <= 0 && p.derivative()(hi) < 0) return nr > 0 ? roots[nr - 1] : hi;
  return std::nullopt;
}

}  // namespace rattle::detail
