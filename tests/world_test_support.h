// Shared helpers for the World* tests: closed boxes of static segments, random non-overlapping disks,
// and the conserved quantities (kinetic energy, momentum) and invariants (gaps, overlaps, finiteness)
// the tests check. Header-only; everything is inline.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "rattle/rattle.h"

namespace rattle_test {

using rattle::BodyDef;
using rattle::BodyId;
using rattle::BodyType;
using rattle::FixtureDef;
using rattle::FixtureId;
using rattle::Vec2;
using rattle::World;

/// Definitions without designated initializers (which GCC's -Wextra flags when fields are left out).
inline BodyDef bodyDef(BodyType type, Vec2 position = {}, Vec2 velocity = {}, uint64_t userData = 0) {
  BodyDef d;
  d.type = type;
  d.position = position;
  d.velocity = velocity;
  d.userData = userData;
  return d;
}

inline rattle::Filter filterOf(uint32_t categoryBits = 0x0001, uint32_t maskBits = 0xFFFFFFFF, int32_t group = 0) {
  rattle::Filter f;
  f.categoryBits = categoryBits;
  f.maskBits = maskBits;
  f.group = group;
  return f;
}

inline rattle::WorldDef worldDefWithBudget(int maxEventsPerStep) {
  rattle::WorldDef d;
  d.maxEventsPerStep = maxEventsPerStep;
  return d;
}

/// A closed box: one static body at the origin holding four Segment fixtures on the inner walls.
/// `walls` is ordered left (x = xmin), right (x = xmax), bottom (y = ymin), top (y = ymax).
struct ClosedBox {
  BodyId body;
  std::array<FixtureId, 4> walls;
  double xmin = 0, ymin = 0, xmax = 0, ymax = 0;

  /// Unit normal of wall w pointing into the box.
  static Vec2 inwardNormal(int w) {
    switch (w) {
      case 0:
        return {1, 0};
      case 1:
        return {-1, 0};
      case 2:
        return {0, 1};
      default:
        return {0, -1};
    }
  }
};

inline ClosedBox makeClosedBox(World& world, double xmin, double ymin, double xmax, double ymax,
                               double restitution = 0.0) {
  ClosedBox box;
  box.xmin = xmin;
  box.ymin = ymin;
  box.xmax = xmax;
  box.ymax = ymax;
  box.body = world.createBody(bodyDef(BodyType::Static));
  const Vec2 c00{xmin, ymin}, c10{xmax, ymin}, c11{xmax, ymax}, c01{xmin, ymax};
  const rattle::Segment segments[4] = {{c00, c01}, {c10, c11}, {c00, c10}, {c01, c11}};
  for (int i = 0; i < 4; ++i) {
    FixtureDef fd;
    fd.geometry = segments[i];
    fd.restitution = restitution;
    box.walls[i] = world.createFixture(box.body, fd);
  }
  return box;
}

/// One disk to be created as a dynamic body with one Circle fixture centred on the body.
struct DiskSpec {
  Vec2 position;
  Vec2 velocity;
  double radius = 0.5;
  double density = 1.0;
  double restitution = 1.0;
};

/// A disk in a world.
struct Disk {
  BodyId body;
  FixtureId fixture;
  double radius = 0;
  double mass = 0;  ///< as the world reports it
};

struct RandomDiskOptions {
  int count = 100;
  uint64_t seed = 1;
  /// Every disk lies entirely inside this region, `minGap` away from its edges.
  double xmin = 0, ymin = 0, xmax = 10, ymax = 10;
  double minRadius = 0.5, maxRadius = 0.5;
  double minDensity = 1.0, maxDensity = 1.0;
  /// Velocity: uniform direction, speed uniform in [minSpeed, maxSpeed].
  double minSpeed = 0.0, maxSpeed = 1.0;
  double minRestitution = 1.0, maxRestitution = 1.0;
  /// Clearance between any two disks and between a disk and the region's edges.
  double minGap = 1e-3;
  int maxAttemptsPerDisk = 100000;
};

/// The elastic gas several suites use: `count` disks (radii 0.35-0.65, densities 0.5-2, speeds 0.5-1.5,
/// restitution 1) in the square [0, size]^2, seed 20240611.
inline RandomDiskOptions gasDiskOptions(int count, double size) {
  RandomDiskOptions o;
  o.count = count;
  o.seed = 20240611;
  o.xmin = 0;
  o.ymin = 0;
  o.xmax = size;
  o.ymax = size;
  o.minRadius = 0.35;
  o.maxRadius = 0.65;
  o.minDensity = 0.5;
  o.maxDensity = 2.0;
  o.minSpeed = 0.5;
  o.maxSpeed = 1.5;
  o.minRestitution = 1.0;
  o.maxRestitution = 1.0;
  o.minGap = 1e-3;
  return o;
}

/// Random non-overlapping disks by rejection sampling, reproducible from the seed
/// (std::mt19937_64 with values drawn by our own mapping, not by std distributions, whose
/// algorithms differ between standard libraries).
inline std::vector<DiskSpec> randomDisks(const RandomDiskOptions& o) {
  std::mt19937_64 rng(o.seed);
  auto uniform = [&rng](double lo, double hi) {
    const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;  // [0, 1)
    return lo + (hi - lo) * u;
  };
  std::vector<DiskSpec> disks;
  disks.reserve(static_cast<size_t>(o.count));
  for (int i = 0; i < o.count; ++i) {
    DiskSpec d;
    d.radius = uniform(o.minRadius, o.maxRadius);
    d.density = uniform(o.minDensity, o.maxDensity);
    d.restitution = uniform(o.minRestitution, o.maxRestitution);
    const double angle = uniform(0.0, 2.0 * std::numbers::pi);
    const double speed = uniform(o.minSpeed, o.maxSpeed);
    d.velocity = Vec2{speed * std::cos(angle), speed * std::sin(angle)};
    bool placed = false;
    for (int attempt = 0; attempt < o.maxAttemptsPerDisk && !placed; ++attempt) {
      const double lo = d.radius + o.minGap;
      if (o.xmin + lo > o.xmax - lo || o.ymin + lo > o.ymax - lo) break;
      d.position = Vec2{uniform(o.xmin + lo, o.xmax - lo), uniform(o.ymin + lo, o.ymax - lo)};
      placed = true;
      for (const DiskSpec& e : disks) {
        const double reach = e.radius + d.radius + o.minGap;
        if (rattle::lengthSquared(e.position - d.position) < reach * reach) {
          placed = false;
          break;
        }
      }
    }
    if (!placed) throw std::runtime_error("randomDisks: could not place disk " + std::to_string(i));
    disks.push_back(d);
  }
  return disks;
}

inline Disk addDisk(World& world, const DiskSpec& s) {
  Disk d;
  d.body = world.createBody(bodyDef(BodyType::Dynamic, s.position, s.velocity));
  FixtureDef fd;
  fd.geometry = rattle::Circle{{0, 0}, s.radius};
  fd.density = s.density;
  fd.restitution = s.restitution;
  d.fixture = world.createFixture(d.body, fd);
  d.radius = s.radius;
  d.mass = world.mass(d.body);
  return d;
}

inline std::vector<Disk> addDisks(World& world, const std::vector<DiskSpec>& specs) {
  std::vector<Disk> disks;
  disks.reserve(specs.size());
  for (const DiskSpec& s : specs) disks.push_back(addDisk(world, s));
  return disks;
}

/// Sum of m v^2 / 2, accumulated in long double.
inline long double kineticEnergy(const World& world, const std::vector<Disk>& disks) {
  long double e = 0;
  for (const Disk& d : disks) {
    const Vec2 v = world.velocity(d.body);
    e += 0.5L * d.mass * (static_cast<long double>(v.x) * v.x + static_cast<long double>(v.y) * v.y);
  }
  return e;
}

struct LongVec2 {
  long double x = 0, y = 0;
};

/// Total momentum, accumulated in long double.
inline LongVec2 momentum(const World& world, const std::vector<Disk>& disks) {
  LongVec2 p;
  for (const Disk& d : disks) {
    const Vec2 v = world.velocity(d.body);
    p.x += static_cast<long double>(d.mass) * v.x;
    p.y += static_cast<long double>(d.mass) * v.y;
  }
  return p;
}

/// Sum of |m v|: the scale against which a momentum error is relative.
inline long double momentumScale(const World& world, const std::vector<Disk>& disks) {
  long double s = 0;
  for (const Disk& d : disks) s += static_cast<long double>(d.mass) * rattle::length(world.velocity(d.body));
  return s;
}

/// Smallest |ci - cj| - ri - rj over all pairs (negative when some pair overlaps). O(N^2).
inline double minPairwiseGap(const World& world, const std::vector<Disk>& disks) {
  std::vector<Vec2> p(disks.size());
  for (size_t i = 0; i < disks.size(); ++i) p[i] = world.position(disks[i].body);
  double gap = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < disks.size(); ++i)
    for (size_t j = i + 1; j < disks.size(); ++j)
      gap = std::min(gap, rattle::length(p[i] - p[j]) - disks[i].radius - disks[j].radius);
  return gap;
}

/// Largest overlap of a pair relative to the smaller radius: max (ri + rj - |ci - cj|) / min(ri, rj).
/// Negative when no pair touches. O(N^2).
inline double maxRelativeOverlap(const World& world, const std::vector<Disk>& disks) {
  std::vector<Vec2> p(disks.size());
  for (size_t i = 0; i < disks.size(); ++i) p[i] = world.position(disks[i].body);
  double worst = -std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < disks.size(); ++i)
    for (size_t j = i + 1; j < disks.size(); ++j) {
      const double overlap = disks[i].radius + disks[j].radius - rattle::length(p[i] - p[j]);
      worst = std::max(worst, overlap / std::min(disks[i].radius, disks[j].radius));
    }
  return worst;
}

/// Largest penetration of a disk into a wall of the box, relative to its radius (negative: none).
inline double maxRelativeWallPenetration(const World& world, const std::vector<Disk>& disks, const ClosedBox& box) {
  double worst = -std::numeric_limits<double>::infinity();
  for (const Disk& d : disks) {
    const Vec2 p = world.position(d.body);
    const double gaps[4] = {p.x - box.xmin, box.xmax - p.x, p.y - box.ymin, box.ymax - p.y};
    for (double g : gaps) worst = std::max(worst, (d.radius - g) / d.radius);
  }
  return worst;
}

inline bool centreInside(Vec2 p, const ClosedBox& box) {
  return p.x >= box.xmin && p.x <= box.xmax && p.y >= box.ymin && p.y <= box.ymax;
}

/// True when every disk's position and velocity are finite.
inline bool allFinite(const World& world, const std::vector<Disk>& disks) {
  for (const Disk& d : disks)
    if (!rattle::isFinite(world.position(d.body)) || !rattle::isFinite(world.velocity(d.body))) return false;
  return true;
}

/// Maps fixture indices to small integers: disk i -> i, wall w of a box -> -1 - w, anything else -> a
/// large sentinel. Lets event lists be compared as lists of (low, high) pairs.
struct FixtureLabels {
  std::vector<int> byIndex;
  static constexpr int kUnknown = std::numeric_limits<int>::max();

  void set(FixtureId f, int label) {
    if (f.index >= byIndex.size()) byIndex.resize(f.index + 1, kUnknown);
    byIndex[f.index] = label;
  }
  int of(FixtureId f) const { return f.index < byIndex.size() ? byIndex[f.index] : kUnknown; }

  static FixtureLabels forScene(const std::vector<Disk>& disks, const ClosedBox* box = nullptr) {
    FixtureLabels l;
    for (size_t i = 0; i < disks.size(); ++i) l.set(disks[i].fixture, static_cast<int>(i));
    if (box)
      for (int w = 0; w < 4; ++w) l.set(box->walls[w], -1 - w);
    return l;
  }
};

}  // namespace rattle_test
