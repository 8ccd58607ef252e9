// Helpers for the Gravity* and HardCase* suites (test_gravity.cpp, test_hard_cases.cpp): long double
// vectors for independent references, the step mode as a test parameter, energy under gravity, an O(N)
// overlap check for big scenes, and exact distances from a straight piece of path to each geometry.
// Header-only; everything is inline. Builds on world_test_support.h, whose functions it does not change.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "rattle/rattle.h"
#include "world_test_support.h"

namespace hard_case {

using rattle::StepMode;
using rattle::Vec2;
using LD = long double;

// ---- Long double vectors ------------------------------------------------------------------------

struct LV {
  LD x = 0, y = 0;
};
inline LV lv(Vec2 v) { return {v.x, v.y}; }
inline Vec2 toVec(LV v) { return {static_cast<double>(v.x), static_cast<double>(v.y)}; }
inline LV operator+(LV a, LV b) { return {a.x + b.x, a.y + b.y}; }
inline LV operator-(LV a, LV b) { return {a.x - b.x, a.y - b.y}; }
inline LV operator-(LV a) { return {-a.x, -a.y}; }
inline LV operator*(LD s, LV a) { return {s * a.x, s * a.y}; }
inline LD dotL(LV a, LV b) { return a.x * b.x + a.y * b.y; }
inline LD crossL(LV a, LV b) { return a.x * b.y - a.y * b.x; }
inline LD lenL(LV a) { return std::sqrt(dotL(a, a)); }
inline LV perpL(LV a) { return {-a.y, a.x}; }

inline std::string str(Vec2 v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.17g, %.17g)", v.x, v.y);
  return buf;
}
inline std::string str(LV v) { return str(toVec(v)); }

/// |a - b| <= tol on each axis.
inline ::testing::AssertionResult near(Vec2 a, LV b, LD tol) {
  const LD dx = std::fabs(a.x - b.x), dy = std::fabs(a.y - b.y);
  if (dx <= tol && dy <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << str(a) << " vs expected " << str(b) << " (differences "
                                       << static_cast<double>(dx) << ", " << static_cast<double>(dy)
                                       << ", tolerance " << static_cast<double>(tol) << ")";
}

// ---- The step mode as a parameter ---------------------------------------------------------------

inline const char* modeName(StepMode m) {
  switch (m) {
    case StepMode::Hybrid: return "Hybrid";
    case StepMode::Discrete: return "Discrete";
    case StepMode::Predictive: return "Predictive";
  }
  return "Unknown";
}

/// Test name suffix: "/Hybrid" and so on.
struct ModeParamName {
  std::string operator()(const ::testing::TestParamInfo<StepMode>& info) const { return modeName(info.param); }
};

/// Base fixture of the mode-parameterized suites: a WorldDef in the mode under test.
class ModeTest : public ::testing::TestWithParam<StepMode> {
 protected:
  rattle::WorldDef def() const {
    rattle::WorldDef d;
    d.mode = GetParam();
    return d;
  }
};

// ---- Energy under gravity -----------------------------------------------------------------------

/// The energy a step may gain by design: a contact that would bounce off slower than restingSpeed bounces
/// off at restingSpeed instead (resting.cpp), which can add up to m restingSpeed^2 / 2, and its impulse is
/// then at most about 3 m restingSpeed. `m` is the disks' mass (equal disks).
inline LD minimumBounceAllowance(std::span<const rattle::ContactEvent> events, double m, double restingSpeed) {
  int slow = 0;
  for (const rattle::ContactEvent& ev : events) slow += ev.impulse <= 3 * m * restingSpeed * (1 + 1e-9) ? 1 : 0;
  return slow * 0.5L * m * restingSpeed * restingSpeed;
}

/// Kinetic plus potential energy, sum of m v^2/2 - m g.p, in long double. The potential's zero is at
/// the origin; pass a `reference` point to move it.
inline LD totalEnergy(const rattle::World& world, const std::vector<rattle_test::Disk>& disks, Vec2 gravity,
                      Vec2 reference = {}) {
  LD e = 0;
  for (const rattle_test::Disk& d : disks) {
    const Vec2 v = world.velocity(d.body);
    const Vec2 p = world.position(d.body);
    const LD kinetic = 0.5L * d.mass * (static_cast<LD>(v.x) * v.x + static_cast<LD>(v.y) * v.y);
    const LD potential =
        -static_cast<LD>(d.mass) * (static_cast<LD>(gravity.x) * (static_cast<LD>(p.x) - reference.x) +
                                    static_cast<LD>(gravity.y) * (static_cast<LD>(p.y) - reference.y));
    e += kinetic + potential;
  }
  return e;
}

// ---- Overlaps in big scenes ---------------------------------------------------------------------

/// Largest (ri + rj - |ci - cj|) / min(ri, rj) over pairs of disks, through a uniform grid (cells of the
/// largest diameter), so O(N) for scenes of similar disks. Negative when no pair touches. `worstPair`
/// receives the indices of the worst pair.
inline double maxRelativeOverlapGrid(const rattle::World& world, const std::vector<rattle_test::Disk>& disks,
                                     std::pair<size_t, size_t>* worstPair = nullptr) {
  double rmax = 0;
  for (const auto& d : disks) rmax = std::max(rmax, d.radius);
  const double cell = std::max(2 * rmax, 1e-300);
  std::vector<Vec2> p(disks.size());
  std::unordered_map<uint64_t, std::vector<size_t>> grid;
  auto key = [](int64_t i, int64_t j) { return (static_cast<uint64_t>(i) << 32) ^ static_cast<uint64_t>(j & 0xffffffff); };
  for (size_t i = 0; i < disks.size(); ++i) {
    p[i] = world.position(disks[i].body);
    grid[key(static_cast<int64_t>(std::floor(p[i].x / cell)), static_cast<int64_t>(std::floor(p[i].y / cell)))]
        .push_back(i);
  }
  double worst = -std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < disks.size(); ++i) {
    const int64_t ci = static_cast<int64_t>(std::floor(p[i].x / cell));
    const int64_t cj = static_cast<int64_t>(std::floor(p[i].y / cell));
    for (int64_t di = -1; di <= 1; ++di)
      for (int64_t dj = -1; dj <= 1; ++dj) {
        auto it = grid.find(key(ci + di, cj + dj));
        if (it == grid.end()) continue;
        for (size_t j : it->second) {
          if (j <= i) continue;
          const double overlap = disks[i].radius + disks[j].radius - rattle::length(p[i] - p[j]);
          const double rel = overlap / std::min(disks[i].radius, disks[j].radius);
          if (rel > worst) {
            worst = rel;
            if (worstPair) *worstPair = {i, j};
          }
        }
      }
  }
  return worst;
}

// ---- Exact distances (long double) ---------------------------------------------------------------

/// The closest point of segment [a, b] to p; `param` gets its parameter along a -> b, clamped to [0, 1].
inline LV closestOnSegmentL(LV p, LV a, LV b, LD* param = nullptr) {
  const LV d = b - a;
  const LD dd = dotL(d, d);
  LD t = dd > 0 ? dotL(p - a, d) / dd : 0;
  t = std::clamp<LD>(t, 0, 1);
  if (param) *param = t;
  return a + t * d;
}

inline LD pointSegmentDistanceL(LV p, LV a, LV b) { return lenL(p - closestOnSegmentL(p, a, b)); }

/// Distance between segments [p, q] and [a, b]: 0 when they cross.
inline LD segmentSegmentDistanceL(LV p, LV q, LV a, LV b) {
  const LD d1 = crossL(q - p, a - p), d2 = crossL(q - p, b - p);
  const LD d3 = crossL(b - a, p - a), d4 = crossL(b - a, q - a);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return 0;
  return std::min({pointSegmentDistanceL(p, a, b), pointSegmentDistanceL(q, a, b), pointSegmentDistanceL(a, p, q),
                   pointSegmentDistanceL(b, p, q)});
}

/// Whether p lies inside (or on) a polygon given in either winding.
inline bool insidePolygonL(LV p, const std::vector<LV>& poly) {
  bool pos = false, neg = false;
  for (size_t i = 0; i < poly.size(); ++i) {
    const LD c = crossL(poly[(i + 1) % poly.size()] - poly[i], p - poly[i]);
    pos = pos || c > 0;
    neg = neg || c < 0;
  }
  return !(pos && neg);
}

/// Smallest distance from the straight piece [p, q] to a geometry placed at `at` (0 when the piece
/// enters a polygon or a circle). A Segment's ends count here: this measures the closed set.
inline LD pathDistanceL(LV p, LV q, const rattle::Geometry& g, LV at) {
  if (const auto* s = std::get_if<rattle::Point>(&g)) return pointSegmentDistanceL(at + lv(s->position), p, q);
  if (const auto* s = std::get_if<rattle::Circle>(&g))
    return std::max<LD>(0, pointSegmentDistanceL(at + lv(s->center), p, q) - s->radius);
  if (const auto* s = std::get_if<rattle::Segment>(&g))
    return segmentSegmentDistanceL(p, q, at + lv(s->a), at + lv(s->b));
  std::vector<LV> pts;
  bool closed = false;
  if (const auto* s = std::get_if<rattle::Polyline>(&g)) {
    for (Vec2 v : s->points) pts.push_back(at + lv(v));
  } else {
    for (Vec2 v : std::get<rattle::Polygon>(g).points) pts.push_back(at + lv(v));
    closed = true;
    if (insidePolygonL(p, pts) || insidePolygonL(q, pts)) return 0;
  }
  LD best = std::numeric_limits<LD>::infinity();
  const size_t n = pts.size();
  for (size_t i = 0; i + 1 < n + (closed ? 1 : 0); ++i)
    best = std::min(best, segmentSegmentDistanceL(p, q, pts[i], pts[(i + 1) % n]));
  return best;
}

}  // namespace hard_case
