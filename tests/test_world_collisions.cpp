// World collision tests: two-disk collisions against the closed form, conservation in a large gas, an
// independent event-driven reference for random scenes, fast disks against thin walls, mid-step
// re-queries and the per-step event budget.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "rattle/rattle.h"
#include "world_test_support.h"

namespace {

using namespace rattle_test;
using rattle::Circle;
using rattle::ContactEvent;
using rattle::WorldDef;

using LD = long double;

struct LVec {
  LD x = 0, y = 0;
};
LVec lv(Vec2 v) { return {v.x, v.y}; }
LVec operator+(LVec a, LVec b) { return {a.x + b.x, a.y + b.y}; }
LVec operator-(LVec a, LVec b) { return {a.x - b.x, a.y - b.y}; }
LVec operator*(LD s, LVec a) { return {s * a.x, s * a.y}; }
LD ldot(LVec a, LVec b) { return a.x * b.x + a.y * b.y; }
LD llen(LVec a) { return std::sqrt(ldot(a, a)); }

std::string str(Vec2 v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.17g, %.17g)", v.x, v.y);
  return buf;
}

::testing::AssertionResult vecNear(const char* what, Vec2 a, LVec e, double tol) {
  const double dx = std::fabs(a.x - static_cast<double>(e.x)), dy = std::fabs(a.y - static_cast<double>(e.y));
  if (dx <= tol && dy <= tol) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << what << " = " << str(a) << ", expected "
                                       << str(Vec2{double(e.x), double(e.y)}) << " (difference " << dx << ", " << dy
                                       << ", tolerance " << tol << ")";
}
#define EXPECT_VEC_NEAR(actual, expected, tol) EXPECT_TRUE(vecNear(#actual, (actual), (expected), (tol)))

// ------------------------------------------------------------------------------------------------
// Two disks against the closed form.

struct TwoDiskCase {
  const char* name;
  Vec2 p1, v1;
  double r1, rho1;
  Vec2 p2, v2;
  double r2, rho2;
};

void checkTwoDisk(const TwoDiskCase& c, double e, bool restitutionOnFirst, bool createSecondFirst) {
  SCOPED_TRACE(std::string(c.name) + " e=" + std::to_string(e) +
               (restitutionOnFirst ? " (on disk 1)" : " (on disk 2)") +
               (createSecondFirst ? " created 2,1" : " created 1,2"));
  World world;
  const DiskSpec s1{c.p1, c.v1, c.r1, c.rho1, restitutionOnFirst ? e : 0.0};
  const DiskSpec s2{c.p2, c.v2, c.r2, c.rho2, restitutionOnFirst ? 0.0 : e};
  Disk d1, d2;
  if (createSecondFirst) {
    d2 = addDisk(world, s2);
    d1 = addDisk(world, s1);
  } else {
    d1 = addDisk(world, s1);
    d2 = addDisk(world, s2);
  }
  const LD pi = std::numbers::pi_v<long double>;
  const LD m1 = static_cast<LD>(c.rho1) * pi * c.r1 * c.r1;
  const LD m2 = static_cast<LD>(c.rho2) * pi * c.r2 * c.r2;
  EXPECT_NEAR(d1.mass, static_cast<double>(m1), 1e-14 * static_cast<double>(m1));
  EXPECT_NEAR(d2.mass, static_cast<double>(m2), 1e-14 * static_cast<double>(m2));

  // Closed form, in long double: time of impact of |r + v t| = r1 + r2, then the impulse along n.
  const LVec r = lv(c.p2) - lv(c.p1), v = lv(c.v2) - lv(c.v1);
  const LD b = ldot(r, v), A = ldot(v, v), dsum = static_cast<LD>(c.r1) + c.r2;
  const LD cc = ldot(r, r) - dsum * dsum;
  const LD disc = b * b - A * cc;
  ASSERT_LT(b, 0);
  ASSERT_GT(disc, 0);
  const LD tc = cc / (-b + std::sqrt(disc));
  const LVec q1 = lv(c.p1) + tc * lv(c.v1), q2 = lv(c.p2) + tc * lv(c.v2);
  const LVec n = (1 / llen(q2 - q1)) * (q2 - q1);  // from disk 1 to disk 2
  const LD vn = ldot(lv(c.v1) - lv(c.v2), n);      // > 0: approaching
  ASSERT_GT(vn, 0);
  const LD J = (1 + static_cast<LD>(e)) * vn * m1 * m2 / (m1 + m2);
  const LVec v1p = lv(c.v1) - (1 + static_cast<LD>(e)) * (m2 / (m1 + m2)) * vn * n;
  const LVec v2p = lv(c.v2) + (1 + static_cast<LD>(e)) * (m1 / (m1 + m2)) * vn * n;
  const LVec point = q1 + static_cast<LD>(c.r1) * n;

  const double dt = 2.0;
  ASSERT_LT(tc, dt);
  world.step(dt);
  const LVec f1 = q1 + (dt - tc) * v1p, f2 = q2 + (dt - tc) * v2p;

  const auto events = world.contactEvents();
  ASSERT_EQ(events.size(), 1u);
  const ContactEvent& ev = events[0];
  EXPECT_LT(ev.fixtureA.index, ev.fixtureB.index);
  EXPECT_EQ(world.body(ev.fixtureA), ev.bodyA);
  EXPECT_EQ(world.body(ev.fixtureB), ev.bodyB);
  const bool oneIsA = ev.bodyA == d1.body;
  EXPECT_EQ(oneIsA ? ev.bodyB : ev.bodyA, d2.body);
  EXPECT_EQ(oneIsA ? ev.fixtureA : ev.fixtureB, d1.fixture);
  EXPECT_NEAR(ev.time, static_cast<double>(tc), 1e-13);
  EXPECT_VEC_NEAR(ev.normal, (oneIsA ? 1.0L : -1.0L) * n, 1e-13);
  EXPECT_VEC_NEAR(ev.point, point, 1e-12);
  EXPECT_NEAR(ev.impulse, static_cast<double>(J), 1e-13 * static_cast<double>(J));
  EXPECT_GE(ev.impulse, 0.0);

  EXPECT_VEC_NEAR(world.velocity(d1.body), v1p, 1e-13);
  EXPECT_VEC_NEAR(world.velocity(d2.body), v2p, 1e-13);
  EXPECT_VEC_NEAR(world.position(d1.body), f1, 1e-12);
  EXPECT_VEC_NEAR(world.position(d2.body), f2, 1e-12);

  // Afterwards nothing more happens: the pair separates (e > 0) or stays in contact without approaching
  // (e = 0). Round-off may at most produce contacts with negligible impulse.
  for (int i = 0; i < 3; ++i) {
    world.step(0.5);
    for (const ContactEvent& later : world.contactEvents())
      EXPECT_LE(later.impulse, 1e-12 * static_cast<double>(J)) << "spurious contact after the collision";
    const double gap = rattle::length(world.position(d2.body) - world.position(d1.body)) - c.r1 - c.r2;
    EXPECT_GE(gap, -1e-12);
  }
}

TEST(WorldTwoDisk, HeadOnAndObliqueMatchClosedForm) {
  const TwoDiskCase cases[] = {
      {"head-on", {0, 0}, {3, 0}, 1.0, 2.0, {5, 0}, {-1, 0}, 0.5, 0.75},
      {"oblique", {0, 0}, {3, 0}, 1.0, 2.0, {5, 0.8}, {-1, 0.25}, 0.5, 0.75},
      {"oblique, general direction", {-2.5, 1.25}, {1.75, -0.5}, 0.5, 3.0, {1.5, -0.75}, {-0.25, 0.625}, 1.0, 0.5},
  };
  for (const TwoDiskCase& c : cases)
    for (double e : {0.0, 0.5, 1.0})
      for (bool onFirst : {true, false})
        for (bool reversed : {false, true}) checkTwoDisk(c, e, onFirst, reversed);
}

// ------------------------------------------------------------------------------------------------
// Conservation in a large gas.

RandomDiskOptions thousandDiskOptions() { return gasDiskOptions(1000, 50); }

TEST(WorldGas, ThousandDisksInClosedBoxConserveEnergy) {
  const auto specs = randomDisks(thousandDiskOptions());
  World world;
  const ClosedBox box = makeClosedBox(world, 0, 0, 50, 50, 1.0);
  const auto disks = addDisks(world, specs);
  const FixtureLabels labels = FixtureLabels::forScene(disks, &box);
  const long double e0 = kineticEnergy(world, disks);

  const double dt = 0.1;
  const auto start = std::chrono::steady_clock::now();
  long long diskDisk = 0, diskWall = 0;
  int steps = 0;
  double worstEnergyError = 0;
  while (diskDisk < 100000 && steps < 20000) {
    world.step(dt);
    ++steps;
    for (const ContactEvent& ev : world.contactEvents()) {
      const bool wall = labels.of(ev.fixtureA) < 0 || labels.of(ev.fixtureB) < 0;
      (wall ? diskWall : diskDisk) += 1;
    }
    const double err = static_cast<double>(std::fabs(kineticEnergy(world, disks) - e0) / e0);
    worstEnergyError = std::max(worstEnergyError, err);
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "[ WorldGas ] 1000 disks in a box: %lld disk-disk and %lld disk-wall collisions in %d steps "
      "(%.1f s simulated) in %.2f s; worst relative energy error %.3g\n",
      diskDisk, diskWall, steps, steps * dt, seconds, worstEnergyError);
  EXPECT_GE(diskDisk, 100000);
  EXPECT_LE(worstEnergyError, 1e-12);
  EXPECT_TRUE(allFinite(world, disks));
  EXPECT_LE(maxRelativeOverlap(world, disks), 1e-9);
  EXPECT_LE(maxRelativeWallPenetration(world, disks, box), 1e-9);
  for (const Disk& d : disks) EXPECT_TRUE(centreInside(world.position(d.body), box));
}

TEST(WorldGas, ThousandDisksInOpenSpaceConserveMomentum) {
  // The same disks with no walls, sent inward so that they meet in the middle, then fly apart.
  auto specs = randomDisks(thousandDiskOptions());
  const Vec2 centre{25, 25};
  for (DiskSpec& s : specs) {
    const Vec2 toCentre = centre - s.position;
    const double speed = 1.0 + 0.5 * rattle::length(s.velocity);
    s.velocity = (speed / rattle::length(toCentre)) * toCentre + 0.3 * s.velocity;
  }
  World world;
  const auto disks = addDisks(world, specs);
  const LongVec2 p0 = momentum(world, disks);
  const long double scale = momentumScale(world, disks);
  const long double e0 = kineticEnergy(world, disks);

  const double dt = 0.5;
  long long collisions = 0;
  double worstMomentumError = 0, worstEnergyError = 0;
  for (int step = 0; step < 160; ++step) {
    world.step(dt);
    collisions += static_cast<long long>(world.contactEvents().size());
    const LongVec2 p = momentum(world, disks);
    const double err = static_cast<double>(std::hypot(p.x - p0.x, p.y - p0.y) / scale);
    worstMomentumError = std::max(worstMomentumError, err);
    worstEnergyError =
        std::max(worstEnergyError, static_cast<double>(std::fabs(kineticEnergy(world, disks) - e0) / e0));
  }
  std::printf(
      "[ WorldGas ] 1000 disks in open space: %lld collisions; worst relative momentum error %.3g, "
      "energy error %.3g\n",
      collisions, worstMomentumError, worstEnergyError);
  EXPECT_GE(collisions, 1000);
  EXPECT_LE(worstMomentumError, 1e-12);
  EXPECT_LE(worstEnergyError, 1e-12);
  EXPECT_TRUE(allFinite(world, disks));
  EXPECT_LE(maxRelativeOverlap(world, disks), 1e-9);
}

// ------------------------------------------------------------------------------------------------
// An independent, brute-force, event-driven reference for disks in a closed box.
//
// At each event every disk-disk and disk-wall pair is scanned for its time of impact (long double),
// everything is advanced to the earliest one, and the impulse rule is applied:
//   disk-disk: v1' = v1 - (1+e) m2/(m1+m2) ((v1-v2).n) n, v2' = v2 + (1+e) m1/(m1+m2) ((v1-v2).n) n,
//   disk-wall: v' = v - (1+e) (v.n) n,
// with e the larger of the two restitutions. Disks inside the box only ever touch the walls' insides,
// so the walls are the four lines of the box.

struct RefDisk {
  LD x, y, vx, vy, r, m, e;
};

struct RefEvent {
  LD time;
  int lo, hi;  // labels as in FixtureLabels: disk i -> i, wall w -> -1 - w
};

class ReferenceGas {
 public:
  ReferenceGas(const std::vector<DiskSpec>& specs, const ClosedBox& box, double wallRestitution)
      : xmin_(box.xmin), ymin_(box.ymin), xmax_(box.xmax), ymax_(box.ymax), wallE_(wallRestitution) {
    for (const DiskSpec& s : specs)
      disks_.push_back({s.position.x, s.position.y, s.velocity.x, s.velocity.y, s.radius,
                        static_cast<LD>(s.density) * std::numbers::pi_v<long double> * s.radius * s.radius,
                        s.restitution});
  }

  /// Runs from the current time to tEnd, appending the events.
  void runUntil(LD tEnd, std::vector<RefEvent>& out, size_t maxEvents = 1000000) {
    const int n = static_cast<int>(disks_.size());
    for (size_t count = 0; count < maxEvents; ++count) {
      LD best = std::numeric_limits<LD>::infinity();
      int bi = -1, bj = -1;  // bj < 0: wall -1 - bj
      for (int i = 0; i < n; ++i) {
        for (int w = 0; w < 4; ++w) {
          const LD t = wallTime(disks_[i], w);
          if (t < best) best = t, bi = i, bj = -1 - w;
        }
        for (int j = i + 1; j < n; ++j) {
          const LD t = pairTime(disks_[i], disks_[j]);
          if (t < best) best = t, bi = i, bj = j;
        }
      }
      if (bi < 0 || now_ + best > tEnd) break;
      advance(best);
      now_ += best;
      if (bj < 0) {
        resolveWall(disks_[bi], -1 - bj);
        out.push_back({now_, std::min(bi, bj), std::max(bi, bj)});
      } else {
        resolvePair(disks_[bi], disks_[bj]);
        out.push_back({now_, bi, bj});
      }
    }
    advance(tEnd - now_);
    now_ = tEnd;
  }

  const std::vector<RefDisk>& disks() const { return disks_; }

 private:
  static LD pairTime(const RefDisk& a, const RefDisk& b) {
    const LD rx = b.x - a.x, ry = b.y - a.y, vx = b.vx - a.vx, vy = b.vy - a.vy;
    const LD bb = rx * vx + ry * vy;
    if (bb >= 0) return std::numeric_limits<LD>::infinity();  // not approaching
    const LD A = vx * vx + vy * vy, d = a.r + b.r;
    const LD c = rx * rx + ry * ry - d * d;
    const LD disc = bb * bb - A * c;
    if (disc <= 0) return std::numeric_limits<LD>::infinity();  // misses or grazes
    if (c <= 0) return 0;                                       // touching and approaching
    return c / (-bb + std::sqrt(disc));
  }

  LD wallTime(const RefDisk& d, int w) const {
    LD gap, speed;
    switch (w) {
      case 0:
        gap = d.x - d.r - xmin_, speed = -d.vx;
        break;
      case 1:
        gap = xmax_ - d.x - d.r, speed = d.vx;
        break;
      case 2:
        gap = d.y - d.r - ymin_, speed = -d.vy;
        break;
      default:
        gap = ymax_ - d.y - d.r, speed = d.vy;
        break;
    }
    if (speed <= 0) return std::numeric_limits<LD>::infinity();
    if (gap <= 0) return 0;
    return gap / speed;
  }

  void advance(LD t) {
    for (RefDisk& d : disks_) d.x += d.vx * t, d.y += d.vy * t;
  }

  static void resolvePair(RefDisk& a, RefDisk& b) {
    const LD rx = b.x - a.x, ry = b.y - a.y, len = std::sqrt(rx * rx + ry * ry);
    const LD nx = rx / len, ny = ry / len;
    const LD vn = (a.vx - b.vx) * nx + (a.vy - b.vy) * ny;
    const LD e = std::max(a.e, b.e);
    const LD J = (1 + e) * vn * a.m * b.m / (a.m + b.m);
    a.vx -= J / a.m * nx, a.vy -= J / a.m * ny;
    b.vx += J / b.m * nx, b.vy += J / b.m * ny;
  }

  void resolveWall(RefDisk& d, int w) const {
    const LD e = std::max(d.e, static_cast<LD>(wallE_));
    if (w < 2)
      d.vx = -e * d.vx;
    else
      d.vy = -e * d.vy;
  }

  std::vector<RefDisk> disks_;
  LD xmin_, ymin_, xmax_, ymax_, wallE_;
  LD now_ = 0;
};

std::string describe(const std::vector<RefEvent>& list, size_t around) {
  std::ostringstream os;
  const size_t from = around >= 3 ? around - 3 : 0;
  for (size_t i = from; i < std::min(list.size(), around + 4); ++i) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "  #%zu t=%.17Lg (%d, %d)\n", i, list[i].time, list[i].lo, list[i].hi);
    os << buf;
  }
  return os.str();
}

struct PropertyScene {
  std::vector<DiskSpec> specs;
  int mode;  // 0: all restitution 1; 1: uniform per disk in [0.05, 1]; 2: all 0.5
};

PropertyScene propertyScene(uint64_t seed) {
  RandomDiskOptions o;
  o.seed = seed * 7919 + 13;
  o.count = 20 + static_cast<int>((seed * 17) % 41);  // 20..60
  o.xmin = 0;
  o.ymin = 0;
  o.xmax = 10;
  o.ymax = 10;
  o.minRadius = 0.2;
  o.maxRadius = 0.6;
  o.minDensity = 0.25;
  o.maxDensity = 4.0;
  o.minSpeed = 0.5;
  o.maxSpeed = 3.0;
  const int mode = static_cast<int>(seed % 3);
  o.minRestitution = mode == 0 ? 1.0 : mode == 1 ? 0.05 : 0.5;
  o.maxRestitution = mode == 0 ? 1.0 : mode == 1 ? 1.0 : 0.5;
  o.minGap = 1e-3;
  return {randomDisks(o), mode};
}

TEST(WorldGasProperty, RandomScenesMatchReferenceAndKeepInvariants) {
  const int kSeeds = 30;
  const double dt = 0.05;
  const int referenceSteps = 10;  // 0.5 s compared with the reference
  const int totalSteps = 60;      // 3 s of invariant checks
  long long totalEvents = 0, comparedEvents = 0;
  long double worstTimeDifference = 0;
  for (uint64_t seed = 1; seed <= kSeeds; ++seed) {
    const PropertyScene scene = propertyScene(seed);
    SCOPED_TRACE("seed " + std::to_string(seed) + ", " + std::to_string(scene.specs.size()) +
                 " disks, restitution mode " + std::to_string(scene.mode));
    World world;
    const ClosedBox box = makeClosedBox(world, 0, 0, 10, 10, 0.0);
    const auto disks = addDisks(world, scene.specs);
    const FixtureLabels labels = FixtureLabels::forScene(disks, &box);
    ReferenceGas reference(scene.specs, box, 0.0);
    const long double e0 = kineticEnergy(world, disks);
    long double previousEnergy = e0;

    std::vector<RefEvent> engineEvents, referenceEvents;
    bool stop = false;
    for (int step = 0; step < totalSteps && !stop; ++step) {
      world.step(dt);
      EXPECT_FALSE(world.stats().eventBudgetReached) << "step " << step << " hit the event budget";
      const auto events = world.contactEvents();
      totalEvents += static_cast<long long>(events.size());
      double previousTime = 0;
      for (const ContactEvent& ev : events) {
        EXPECT_GE(ev.time, previousTime);
        EXPECT_LE(ev.time, dt);
        previousTime = ev.time;
        EXPECT_GE(ev.impulse, 0.0);
        EXPECT_NEAR(rattle::length(ev.normal), 1.0, 1e-12);
        EXPECT_LT(ev.fixtureA.index, ev.fixtureB.index);
        const int a = labels.of(ev.fixtureA), b = labels.of(ev.fixtureB);
        ASSERT_NE(a, FixtureLabels::kUnknown);
        ASSERT_NE(b, FixtureLabels::kUnknown);
        if (step < referenceSteps)
          engineEvents.push_back({static_cast<LD>(step) * dt + ev.time, std::min(a, b), std::max(a, b)});
      }

      // Invariants after every step.
      if (!allFinite(world, disks)) {
        ADD_FAILURE() << "non-finite state after step " << step;
        break;
      }
      const double overlap = maxRelativeOverlap(world, disks);
      EXPECT_LE(overlap, 1e-9) << "after step " << step;
      const double penetration = maxRelativeWallPenetration(world, disks, box);
      EXPECT_LE(penetration, 1e-9) << "after step " << step;
      for (const Disk& d : disks)
        if (!centreInside(world.position(d.body), box)) {
          ADD_FAILURE() << "centre outside the box after step " << step << ": " << str(world.position(d.body));
          stop = true;
          break;
        }
      const long double energy = kineticEnergy(world, disks);
      if (scene.mode == 0) {
        EXPECT_LE(std::fabs(static_cast<double>((energy - e0) / e0)), 1e-12) << "after step " << step;
      } else {
        EXPECT_LE(static_cast<double>(energy), static_cast<double>(previousEnergy * (1 + 1e-12L)))
            << "energy grew in step " << step;
      }
      previousEnergy = energy;
      if (overlap > 1e-9 || penetration > 1e-9) stop = true;

      if (step + 1 == referenceSteps) {
        reference.runUntil(static_cast<LD>(referenceSteps) * dt, referenceEvents);
        // Same sequence of colliding pairs, same times.
        const size_t common = std::min(engineEvents.size(), referenceEvents.size());
        size_t firstMismatch = common;
        for (size_t i = 0; i < common; ++i) {
          const RefEvent& e = engineEvents[i];
          const RefEvent& r = referenceEvents[i];
          if (e.lo != r.lo || e.hi != r.hi || std::fabs(e.time - r.time) > 1e-9L) {
            firstMismatch = i;
            break;
          }
          worstTimeDifference = std::max(worstTimeDifference, std::fabs(e.time - r.time));
        }
        EXPECT_EQ(engineEvents.size(), referenceEvents.size());
        if (firstMismatch < common || engineEvents.size() != referenceEvents.size()) {
          const size_t at = std::min(firstMismatch, common);
          ADD_FAILURE() << "event lists differ at #" << at << " of " << engineEvents.size() << " (engine) / "
                        << referenceEvents.size() << " (reference)\nengine:\n"
                        << describe(engineEvents, at) << "reference:\n"
                        << describe(referenceEvents, at);
        } else {
          // Same events: the states must agree too.
          for (size_t i = 0; i < disks.size(); ++i) {
            const RefDisk& r = reference.disks()[i];
            EXPECT_VEC_NEAR(world.position(disks[i].body), (LVec{r.x, r.y}), 1e-8) << "disk " << i;
            EXPECT_VEC_NEAR(world.velocity(disks[i].body), (LVec{r.vx, r.vy}), 1e-8) << "disk " << i;
          }
        }
        comparedEvents += static_cast<long long>(referenceEvents.size());
      }
    }
  }
  std::printf(
      "[ WorldGasProperty ] %d seeds: %lld contact events, %lld compared with the reference "
      "(largest time difference %.3Lg s)\n",
      kSeeds, totalEvents, comparedEvents, worstTimeDifference);
  EXPECT_GT(comparedEvents, 20 * kSeeds);
}

// ------------------------------------------------------------------------------------------------
// Fast disks against thin walls.

Vec2 rotate(Vec2 p, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return {c * p.x - s * p.y, s * p.x + c * p.y};
}
LVec rotateL(LVec p, double angle) {
  const LD c = std::cos(static_cast<LD>(angle)), s = std::sin(static_cast<LD>(angle));
  return {c * p.x - s * p.y, s * p.x + c * p.y};
}

enum class WallKind { Segment, Polyline, Polygon };

const char* nameOf(WallKind k) {
  switch (k) {
    case WallKind::Segment:
      return "Segment";
    case WallKind::Polyline:
      return "Polyline";
    default:
      return "Polygon";
  }
}

// In the canonical frame every wall presents the line y = 10 (for |x| < 10^7) to a disk coming from
// below. The flat part is long enough that a disk sliding along it for the whole test never reaches a
// corner (corners are covered by the wedge tests below).
rattle::Geometry canonicalWall(WallKind k, double angle) {
  std::vector<Vec2> pts;
  switch (k) {
    case WallKind::Segment:
      pts = {{-1e7, 10}, {1e7, 10}};
      break;
    case WallKind::Polyline:
      pts = {{-3e7, 30}, {-1e7, 10}, {1e7, 10}, {3e7, 30}};
      break;
    case WallKind::Polygon:
      pts = {{-1e7, 10}, {-1e7, 50}, {1e7, 50}, {1e7, 10}};
      break;  // clockwise
  }
  for (Vec2& p : pts) p = rotate(p, angle);
  switch (k) {
    case WallKind::Segment:
      return rattle::Segment{pts[0], pts[1]};
    case WallKind::Polyline:
      return rattle::Polyline{pts};
    default:
      return rattle::Polygon{pts};
  }
}

TEST(WorldFastDisk, NeverCrossesThinWallAtAnyAngle) {
  const double radius = 1.0, speed = 1e6, dt = 1.0;  // 10^6 radii per step
  int scenes = 0;
  for (WallKind kind : {WallKind::Segment, WallKind::Polyline, WallKind::Polygon})
    for (double angle : {0.0, 0.7, 1.9, 3.5, 5.1})
      for (double incidence : {0.0, 0.1, -0.7})
        for (double e : {1.0, 0.0}) {
          SCOPED_TRACE(std::string(nameOf(kind)) + " angle " + std::to_string(angle) + " incidence " +
                       std::to_string(incidence) + " e " + std::to_string(e));
          ++scenes;
          World world;
          const BodyId wall = world.createBody(bodyDef(BodyType::Static));
          FixtureDef wd;
          wd.geometry = canonicalWall(kind, angle);
          wd.restitution = 0.0;
          world.createFixture(wall, wd);
          const Vec2 v0{speed * std::sin(incidence), speed * std::cos(incidence)};
          const Disk d = addDisk(world, {{0, 0}, rotate(v0, angle), radius, 1.0, e});

          // Canonical frame: contact when the centre reaches y = 9.
          const LD vx = static_cast<LD>(speed) * std::sin(static_cast<LD>(incidence));
          const LD vy = static_cast<LD>(speed) * std::cos(static_cast<LD>(incidence));
          const LD tc = 9 / vy;
          const LD xc = vx * tc;
          world.step(dt);
          const auto events = world.contactEvents();
          ASSERT_EQ(events.size(), 1u);
          const ContactEvent& ev = events[0];
          EXPECT_EQ(ev.bodyA, wall);  // the wall's fixture was created first
          EXPECT_EQ(ev.bodyB, d.body);
          EXPECT_NEAR(ev.time, static_cast<double>(tc), 1e-8 * static_cast<double>(tc));
          EXPECT_VEC_NEAR(ev.normal, rotateL({0, -1}, angle), 1e-9);
          EXPECT_VEC_NEAR(ev.point, rotateL({xc, 10}, angle), 1e-6);
          EXPECT_NEAR(ev.impulse, static_cast<double>((1 + e) * d.mass * vy), 1e-9 * (1 + e) * d.mass * speed);

          const LD rest = dt - tc;
          const LVec expectedPos = rotateL({xc + vx * rest, 9 - e * vy * rest}, angle);
          const LVec expectedVel = rotateL({vx, -e * vy}, angle);
          EXPECT_VEC_NEAR(world.position(d.body), expectedPos, 1e-6);
          EXPECT_VEC_NEAR(world.velocity(d.body), expectedVel, 1e-6);

          // A few more steps: the disk stays on its side (sliding along the wall when e = 0).
          for (int step = 0; step < 3; ++step) {
            const Vec2 p = rotate(world.position(d.body), -angle);
            EXPECT_LE(p.y, 9 + 1e-6) << "crossed or entered the wall: canonical position " << str(p);
            if (e == 0) {
              EXPECT_NEAR(p.y, 9, 1e-6);
            }
            world.step(dt);
            for (const ContactEvent& later : world.contactEvents())
              EXPECT_LE(later.impulse, 1e-9 * d.mass * speed) << "unexpected later contact";
          }
        }
  EXPECT_EQ(scenes, 90);
}

struct WedgeScene {
  World world;
  BodyId wall;
  Disk disk;
  double angle;
  // A V-shaped polyline, opening up; a disk with restitution 0 falls at 10^6 radii per step onto the right
  // arm, slides down it into the wedge, hits the left arm and stops at (0, sqrt(2)) touching both arms.
  explicit WedgeScene(double angle_) : angle(angle_) {
    wall = world.createBody(bodyDef(BodyType::Static));
    FixtureDef wd;
    wd.geometry = rattle::Polyline{{rotate({-100, 100}, angle), {0, 0}, rotate({100, 100}, angle)}};
    world.createFixture(wall, wd);
    disk = addDisk(world, {rotate({5, 50}, angle), rotate({0, -1e6}, angle), 1.0, 1.0, 0.0});
  }
};

TEST(WorldFastDisk, SlidesIntoPolylineWedgeAndStops) {
  for (double angle : {0.0, 0.4, 2.2, 4.0}) {
    SCOPED_TRACE("angle " + std::to_string(angle));
    WedgeScene w(angle);
    w.world.step(1.0);
    const auto events = w.world.contactEvents();
    ASSERT_GE(events.size(), 2u);
    const LD s2 = std::sqrt(2.0L);
    const double mainImpulse = w.disk.mass * 1e6 / std::sqrt(2.0);
    EXPECT_NEAR(events[0].time, static_cast<double>((45 - s2) / 1e6L), 1e-14);
    EXPECT_NEAR(events[1].time, static_cast<double>((45 - s2) / 1e6L + 1e-5L), 1e-14);
    EXPECT_VEC_NEAR(events[0].normal, rotateL({-1 / s2, 1 / s2}, angle), 1e-9);
    EXPECT_VEC_NEAR(events[1].normal, rotateL({1 / s2, 1 / s2}, angle), 1e-9);
    EXPECT_NEAR(events[0].impulse, mainImpulse, 1e-9 * mainImpulse);
    EXPECT_NEAR(events[1].impulse, mainImpulse, 1e-9 * mainImpulse);
    // Round-off may leave a residual approach worth a few negligible contacts at the same instant.
    for (size_t i = 2; i < events.size(); ++i) EXPECT_LE(events[i].impulse, 1e-9 * mainImpulse);
    EXPECT_LE(events.size(), 100u);
    for (int step = 0; step < 3; ++step) {
      const Vec2 p = rotate(w.world.position(w.disk.body), -angle);
      EXPECT_NEAR(p.x, 0, 1e-6) << str(p);
      EXPECT_NEAR(p.y, std::sqrt(2.0), 1e-6) << str(p);
      EXPECT_GE(p.y - std::fabs(p.x), std::sqrt(2.0) - 1e-6) << "entered an arm: " << str(p);
      EXPECT_LE(rattle::length(w.world.velocity(w.disk.body)), 1e-6);
      w.world.step(1.0);
      for (const ContactEvent& later : w.world.contactEvents()) EXPECT_LE(later.impulse, 1e-9 * mainImpulse);
    }
  }
}

TEST(WorldFastDisk, DiskRestingInWedgeReportsNoFurtherContacts) {
  // Once the disk of the test above has come to rest in the wedge, nothing approaches anything: a step
  // should resolve no collision (a contact with a round-off impulse every step is a repeated collision).
  for (double angle : {0.0, 0.4, 2.2, 4.0}) {
    SCOPED_TRACE("angle " + std::to_string(angle));
    WedgeScene w(angle);
    w.world.step(1.0);
    for (int step = 0; step < 3; ++step) {
      w.world.step(1.0);
      const auto events = w.world.contactEvents();
      EXPECT_EQ(events.size(), 0u) << "step " << step + 1 << ": first impulse "
                                   << (events.empty() ? 0.0 : events[0].impulse)
                                   << " at t = " << (events.empty() ? 0.0 : events[0].time);
    }
  }
}

TEST(WorldFastDisk, DiskPassingConvexPolylineCornerTangentiallyIsNotDeflected) {
  // A disk slides along the first segment of a polyline, touching it (exactly, or overlapping it by one
  // ulp of round-off), towards a corner where the polyline bends away. At the corner the gap to the
  // corner point only touches zero: a tangent pass, not an impact (time_of_impact.h). A round-off overlap
  // of d must not turn into a real kick (which would be of order speed * sqrt(2 d / r)).
  for (double y0 : {9.0, std::nextafter(9.0, 10.0), std::nextafter(std::nextafter(9.0, 10.0), 10.0)}) {
    for (double e : {0.0, 1.0}) {
      SCOPED_TRACE("y0 = 9 + " + std::to_string((y0 - 9) / 0x1p-49) + " ulp, e = " + std::to_string(e));
      World world;
      const BodyId wall = world.createBody(bodyDef(BodyType::Static));
      FixtureDef wd;
      wd.geometry = rattle::Polyline{{{-100, 10}, {0, 10}, {100, 30}}};
      wd.restitution = e;
      world.createFixture(wall, wd);
      const double speed = 10;
      const Disk d = addDisk(world, {{-50, y0}, {speed, 0}, 1.0, 1.0, e});
      world.step(10.0);  // passes the corner at t = 5
      for (const ContactEvent& ev : world.contactEvents())
        EXPECT_LE(ev.impulse, 1e-12 * d.mass * speed)
            << "contact at t = " << ev.time << " point " << str(ev.point) << " normal " << str(ev.normal);
      const Vec2 v = world.velocity(d.body);
      EXPECT_LE(std::fabs(v.y), 1e-12 * speed) << "deflected: velocity " << str(v);
      EXPECT_NEAR(world.position(d.body).x, 50, 1e-9);
    }
  }
}

TEST(WorldFastDisk, DiskSlidingOffPolylineEndOfFlatPartIsNotDeflected) {
  // The same, with the sliding set up by the engine itself: a disk with restitution 0 hits the flat part
  // (y = 10, x in [-20, 20]) of a polyline, keeps only its tangential velocity, slides along y = 9 and
  // passes under the corner at x = +-20, where the polyline bends up and away. Its normal velocity was
  // zeroed exactly and must stay zero: passing the corner is a tangent touch, not an impact.
  for (double speed : {10.0, 1e6})
    for (double incidence : {0.6, 0.3, -0.5}) {
      SCOPED_TRACE("speed " + std::to_string(speed) + " incidence " + std::to_string(incidence));
      World world;
      const BodyId wall = world.createBody(bodyDef(BodyType::Static));
      FixtureDef wd;
      wd.geometry = rattle::Polyline{{{-1e7, 30}, {-20, 10}, {20, 10}, {1e7, 30}}};
      world.createFixture(wall, wd);
      const Vec2 v0{speed * std::sin(incidence), speed * std::cos(incidence)};
      const Disk d = addDisk(world, {{0, 0}, v0, 1.0, 1.0, 0.0});
      world.step(100.0 / speed);  // reaches the corner at about 20 / (speed sin 0.3) < 70 / speed
      const auto events = world.contactEvents();
      ASSERT_GE(events.size(), 1u);
      EXPECT_NEAR(events[0].time, 9 / v0.y, 1e-12 * 9 / v0.y);
      EXPECT_NEAR(events[0].impulse, d.mass * v0.y, 1e-12 * d.mass * v0.y);
      for (size_t i = 1; i < events.size(); ++i)
        EXPECT_LE(events[i].impulse, 1e-12 * d.mass * speed)
            << "contact at t = " << events[i].time << ", point " << str(events[i].point) << ", normal "
            << str(events[i].normal) << ", impulse " << events[i].impulse;
      const Vec2 v = world.velocity(d.body);
      EXPECT_EQ(v.x, v0.x);
      EXPECT_LE(std::fabs(v.y), 1e-12 * speed) << "deflected: velocity " << str(v);
      EXPECT_NEAR(world.position(d.body).y, 9, 1e-9);
    }
}

// A disk of radius 1 between walls at x = 0 and x = 3: its centre moves in [1, 2].
struct RattleScene {
  World world;
  BodyId walls;
  FixtureId left, right;
  Disk disk;
  static constexpr double kVx = 50.3, kVy = 0.1, kX0 = 1.5, kY0 = 0.0;

  explicit RattleScene(const WorldDef& def = {}) : world(def) {
    walls = world.createBody(bodyDef(BodyType::Static));
    FixtureDef fd;
    fd.geometry = rattle::Segment{{0, -100}, {0, 100}};
    left = world.createFixture(walls, fd);
    fd.geometry = rattle::Segment{{3, -100}, {3, 100}};
    right = world.createFixture(walls, fd);
    disk = addDisk(world, {{kX0, kY0}, {kVx, kVy}, 1.0, 1.0, 1.0});
  }
  /// Time of the k-th bounce (k >= 1), by unfolding: u = x - 1 moves freely on a line and bounces at integers.
  static LD bounceTime(int k) { return (k - (static_cast<LD>(kX0) - 1)) / static_cast<LD>(kVx); }
};

TEST(WorldFastDisk, RattleBetweenWallsMatchesUnfolding) {
  RattleScene s;
  const double dt = 1.0;
  s.world.step(dt);
  const auto events = s.world.contactEvents();

  // Unfolded coordinate u = x - 1 runs from 0.5 to 0.5 + 50.3 = 50.8: bounces at u = 1..50.
  const LD U = (static_cast<LD>(RattleScene::kX0) - 1) + static_cast<LD>(RattleScene::kVx) * dt;
  const int bounces = static_cast<int>(std::floor(U));
  ASSERT_EQ(bounces, 50);
  ASSERT_EQ(static_cast<int>(events.size()), bounces);
  EXPECT_EQ(s.world.stats().eventsProcessed, bounces);
  EXPECT_FALSE(s.world.stats().eventBudgetReached);
  const double impulse = 2 * s.disk.mass * RattleScene::kVx;
  for (int k = 1; k <= bounces; ++k) {
    const ContactEvent& ev = events[static_cast<size_t>(k - 1)];
    SCOPED_TRACE("bounce " + std::to_string(k));
    if (k > 1) {
      EXPECT_GT(ev.time, events[static_cast<size_t>(k - 2)].time);
    }
    EXPECT_NEAR(ev.time, static_cast<double>(RattleScene::bounceTime(k)), 1e-12);
    const bool rightWall = k % 2 == 1;
    EXPECT_EQ(ev.fixtureA, rightWall ? s.right : s.left);
    EXPECT_EQ(ev.fixtureB, s.disk.fixture);
    EXPECT_VEC_NEAR(ev.normal, (LVec{rightWall ? -1.0L : 1.0L, 0}), 1e-15);
    EXPECT_NEAR(ev.point.x, rightWall ? 3.0 : 0.0, 1e-12);
    EXPECT_NEAR(ev.point.y, RattleScene::kVy * static_cast<double>(RattleScene::bounceTime(k)), 1e-12);
    EXPECT_NEAR(ev.impulse, impulse, 1e-12 * impulse);
  }
  // Fold back: an even number of bounces leaves the disk moving right at u = frac(U).
  const LD frac = U - bounces;
  const bool even = bounces % 2 == 0;
  const Vec2 p = s.world.position(s.disk.body), v = s.world.velocity(s.disk.body);
  EXPECT_NEAR(p.x, static_cast<double>(1 + (even ? frac : 1 - frac)), 1e-11);
  EXPECT_NEAR(p.y, RattleScene::kY0 + RattleScene::kVy * dt, 1e-12);
  EXPECT_DOUBLE_EQ(v.x, even ? RattleScene::kVx : -RattleScene::kVx);
  EXPECT_DOUBLE_EQ(v.y, RattleScene::kVy);
}

// ------------------------------------------------------------------------------------------------
// Simultaneous collisions.

TEST(WorldSimultaneous, ThreeDisksMeetingAtOnceSettle) {
  // Two outer disks close in on a middle one from both sides and touch it at the same instant (t = 2).
  // Treated as a sequence of binary collisions the velocities converge geometrically; in exact arithmetic
  // the approach speeds fall below 1e-15 of the initial ones after 52 collisions (equal masses, e = 0),
  // 3 (equal, e = 0.5 or 0.9), and 35251, 11936, 1537 (outer disks 1000 times heavier than the middle one,
  // e = 0, 0.5, 0.9). Whatever the order, it must end well within the default budget, with no pair
  // approaching, momentum (zero) kept and energy not gained; with e = 0 all three end at rest.
  struct Case {
    double outerDensity, middleDensity, e;
    int maxEvents;
  };
  const Case cases[] = {{1, 1, 0.0, 2000},       {1, 1, 0.5, 100},        {1, 1, 0.9, 100},
                        {1, 1, 1.0, 100},        {10, 0.01, 0.0, 100000}, {10, 0.01, 0.5, 100000},
                        {10, 0.01, 0.9, 100000}, {10, 0.01, 1.0, 1000}};
  for (const Case& c : cases) {
    SCOPED_TRACE("densities " + std::to_string(c.outerDensity) + "/" + std::to_string(c.middleDensity) +
                 ", e = " + std::to_string(c.e));
    World world;
    const Disk a = addDisk(world, {{0, 0}, {1, 0}, 0.5, c.outerDensity, c.e});
    const Disk b = addDisk(world, {{3, 0}, {0, 0}, 0.5, c.middleDensity, c.e});
    const Disk d = addDisk(world, {{6, 0}, {-1, 0}, 0.5, c.outerDensity, c.e});
    const std::vector<Disk> disks{a, b, d};
    const long double e0 = kineticEnergy(world, disks);
    world.step(5.0);
    EXPECT_FALSE(world.stats().eventBudgetReached);
    EXPECT_LE(world.stats().eventsProcessed, c.maxEvents);
    ASSERT_FALSE(world.contactEvents().empty());
    EXPECT_NEAR(world.contactEvents()[0].time, 2.0, 1e-12);
    const double va = world.velocity(a.body).x, vb = world.velocity(b.body).x, vd = world.velocity(d.body).x;
    const LongVec2 p = momentum(world, disks);
    EXPECT_NEAR(static_cast<double>(p.x), 0.0, 1e-12 * 2 * a.mass);
    EXPECT_LE(static_cast<double>(kineticEnergy(world, disks)), static_cast<double>(e0) * (1 + 1e-12));
    EXPECT_GE(vb - va, -1e-12) << "a still approaches b";
    EXPECT_GE(vd - vb, -1e-12) << "b still approaches d";
    EXPECT_LE(maxRelativeOverlap(world, disks), 1e-9);
    if (c.e == 0.0) {
      EXPECT_NEAR(va, 0, 1e-12);
      EXPECT_NEAR(vb, 0, 1e-12);
      EXPECT_NEAR(vd, 0, 1e-12);
    }
  }
}

// ------------------------------------------------------------------------------------------------
// A path changed mid-step must be checked against bodies outside the original swept box.

TEST(WorldRequery, BounceBackHitsDiskOutsideSweptBox) {
  World world;
  const BodyId wallBody = world.createBody(bodyDef(BodyType::Static));
  FixtureDef wd;
  wd.geometry = rattle::Segment{{10, -100}, {10, 100}};
  const FixtureId wall = world.createFixture(wallBody, wd);
  // A moves right at 30 and its swept box over the step is about [-1, 31] x [-1, 1]. B rests at x = -6,
  // its box [-7, -5] x [-1, 1], 4 units away. A bounces off the wall at t = 0.3 and reaches B at
  // t = 0.3 + 13/30.
  const Disk a = addDisk(world, {{0, 0}, {30, 0}, 1.0, 1.0, 1.0});
  const Disk b = addDisk(world, {{-6, 0}, {0, 0}, 1.0, 1.0, 1.0});
  world.step(1.0);
  const auto events = world.contactEvents();
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].fixtureA, wall);
  EXPECT_EQ(events[0].fixtureB, a.fixture);
  EXPECT_NEAR(events[0].time, 0.3, 1e-14);
  EXPECT_EQ(events[1].fixtureA, a.fixture);
  EXPECT_EQ(events[1].fixtureB, b.fixture);
  const double t2 = 0.3 + 13.0 / 30.0;
  EXPECT_NEAR(events[1].time, t2, 1e-14);
  EXPECT_VEC_NEAR(events[1].normal, (LVec{-1, 0}), 1e-15);
  EXPECT_VEC_NEAR(events[1].point, (LVec{-5, 0}), 1e-12);
  EXPECT_NEAR(events[1].impulse, 30 * a.mass, 1e-12 * 30 * a.mass);
  // Equal masses, e = 1: they exchange velocities.
  EXPECT_VEC_NEAR(world.velocity(a.body), (LVec{0, 0}), 1e-12);
  EXPECT_VEC_NEAR(world.velocity(b.body), (LVec{-30, 0}), 1e-12);
  EXPECT_VEC_NEAR(world.position(a.body), (LVec{-4, 0}), 1e-12);
  EXPECT_VEC_NEAR(world.position(b.body), (LVec{-6 - 30 * (1 - t2), 0}), 1e-12);
  EXPECT_GT(world.stats().requeries, 0);
  EXPECT_EQ(world.stats().eventsProcessed, 2);
}

// Two slow disks meet head-on within a step and turn back: each new path runs behind where the disk
// started, out of the box of its path. A plain disk's box without gravity has room for a turn at 1.5
// times its speed (HybridStep::kPlainSlack in hybrid_step.cpp: here 0.15 of the radius of 1, within
// kPlainSlackLimit), so the broad phase is not asked again; with a second, inner circle the disks are
// not plain, and each of their fixtures is looked up again. The events are the same: closing at 2 across
// a gap of 0.04, they meet at t = 0.02 and swap velocities (equal masses, e = 1).
TEST(WorldRequery, SlowDisksTurningBackStayInsideTheirRoomOnlyWhenPlain) {
  for (bool plainDisks : {true, false}) {
    SCOPED_TRACE(plainDisks ? "plain disks" : "disks with a second circle");
    World world;
    const Disk a = addDisk(world, {{0, 0}, {1, 0}, 1.0, 1.0, 1.0});
    const Disk c = addDisk(world, {{2.04, 0}, {-1, 0}, 1.0, 1.0, 1.0});
    if (!plainDisks) {
      FixtureDef inner;
      inner.geometry = rattle::Circle{{0, 0}, 0.5};
      inner.restitution = 1.0;
      world.createFixture(a.body, inner);
      world.createFixture(c.body, inner);
    }
    world.step(0.1);
    const auto events = world.contactEvents();
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].fixtureA, a.fixture);
    EXPECT_EQ(events[0].fixtureB, c.fixture);
    EXPECT_NEAR(events[0].time, 0.02, 1e-14);
    EXPECT_VEC_NEAR(world.velocity(a.body), (LVec{-1, 0}), 1e-12);
    EXPECT_VEC_NEAR(world.velocity(c.body), (LVec{1, 0}), 1e-12);
    EXPECT_VEC_NEAR(world.position(a.body), (LVec{-0.06, 0}), 1e-12);
    EXPECT_VEC_NEAR(world.position(c.body), (LVec{2.1, 0}), 1e-12);
    EXPECT_EQ(world.stats().requeries, plainDisks ? 0 : 4);
  }
}

// ------------------------------------------------------------------------------------------------
// The event budget.

TEST(WorldEventBudget, RattleStopsAtBudgetAndReportsIt) {
  RattleScene s(worldDefWithBudget(10));
  EXPECT_EQ(s.world.definition().maxEventsPerStep, 10);
  s.world.step(1.0);
  const auto& stats = s.world.stats();
  EXPECT_TRUE(stats.eventBudgetReached);
  EXPECT_EQ(stats.eventsProcessed, 10);
  const auto events = s.world.contactEvents();
  ASSERT_EQ(events.size(), 10u);
  for (int k = 1; k <= 10; ++k)
    EXPECT_NEAR(events[static_cast<size_t>(k - 1)].time, static_cast<double>(RattleScene::bounceTime(k)), 1e-12);
  EXPECT_DOUBLE_EQ(s.world.time(), 1.0);
  const Vec2 p = s.world.position(s.disk.body), v = s.world.velocity(s.disk.body);
  EXPECT_TRUE(rattle::isFinite(p)) << str(p);
  EXPECT_TRUE(rattle::isFinite(v)) << str(v);
  // The disk still had a collision due: it is held where it was rather than moved through the right wall
  // (types.h, StepStats::eventBudgetReached). Either way it must not leave the gap between the walls.
  EXPECT_GE(p.x, 1.0 - 1e-9);
  EXPECT_LE(p.x, 2.0 + 1e-9);
  EXPECT_GE(p.y, 0.0);
  EXPECT_LE(p.y, RattleScene::kVy + 1e-12);

  // The next step starts afresh (the flag is per step) and returns too.
  s.world.step(1.0);
  EXPECT_LE(s.world.stats().eventsProcessed, 10);
  EXPECT_TRUE(rattle::isFinite(s.world.position(s.disk.body)));
  EXPECT_TRUE(rattle::isFinite(s.world.velocity(s.disk.body)));
  EXPECT_DOUBLE_EQ(s.world.time(), 2.0);

  // With the default budget the same step is not cut short.
  RattleScene full;
  full.world.step(1.0);
  EXPECT_FALSE(full.world.stats().eventBudgetReached);
  EXPECT_EQ(full.world.stats().eventsProcessed, 50);
}

TEST(WorldEventBudget, BodiesStopAtTheLastCollisionBeforeTheBudget) {
  // types.h, WorldDef::maxEventsPerStep: the step out of budget leaves every body where it was after the
  // last collision it resolved (bounce 10, at the left wall), not at the 11th bounce's instant, where the
  // disk touches the right wall and still moves into it. By the unfolding above: after an even bounce
  // the disk is at x = 1 moving right.
  for (const rattle::StepMode mode : {rattle::StepMode::Hybrid, rattle::StepMode::Predictive}) {
    rattle::WorldDef def = worldDefWithBudget(10);
    def.mode = mode;
    RattleScene s(def);
    s.world.step(1.0);
    ASSERT_TRUE(s.world.stats().eventBudgetReached);
    const Vec2 p = s.world.position(s.disk.body), v = s.world.velocity(s.disk.body);
    const double t10 = static_cast<double>(RattleScene::bounceTime(10));
    EXPECT_NEAR(p.x, 1.0, 1e-12) << "mode " << static_cast<int>(mode);
    EXPECT_NEAR(p.y, RattleScene::kY0 + RattleScene::kVy * t10, 1e-12) << "mode " << static_cast<int>(mode);
    EXPECT_DOUBLE_EQ(v.x, RattleScene::kVx) << "mode " << static_cast<int>(mode);
  }
}

TEST(WorldEventBudget, HeldBodyIsNotRunInto) {
  // Budget 1, spent on an unrelated pair at t = 0.1. Disk B (starting at (5, 0.3), moving up) has a
  // collision with C due at t = 0.47, so B is held. A runs along y = 0 to (5, 0): with B moving it would
  // pass behind B, but B held at (5, 0.3) is in its way. A must not end inside (or pass through) B.
  World world(worldDefWithBudget(1));
  const Disk a = addDisk(world, {{0, 0}, {5, 0}, 0.5, 1.0, 1.0});
  const Disk b = addDisk(world, {{5, 0.3}, {0, 10}, 0.5, 1.0, 1.0});
  const Disk c = addDisk(world, {{5, 6}, {0, 0}, 0.5, 1.0, 1.0});
  const Disk d = addDisk(world, {{100, 0}, {1, 0}, 0.5, 1.0, 1.0});
  const Disk e = addDisk(world, {{101.2, 0}, {-1, 0}, 0.5, 1.0, 1.0});
  const std::vector<Disk> disks{a, b, c, d, e};
  world.step(1.0);
  EXPECT_TRUE(world.stats().eventBudgetReached);
  ASSERT_EQ(world.contactEvents().size(), 1u);
  EXPECT_EQ(world.contactEvents()[0].bodyA, d.body);
  EXPECT_LE(maxRelativeOverlap(world, disks), 1e-9)
      << "A at " << str(world.position(a.body)) << ", B at " << str(world.position(b.body));
  // Wherever B was held, A did not cross it: A is still on B's left or was stopped by it.
  EXPECT_LE(world.position(a.body).x, world.position(b.body).x - std::sqrt(1 - 0.09) + 1e-9);
}

TEST(WorldEventBudget, GasCutShortByBudgetKeepsDisksApart) {
  // A small budget in a busy gas: most steps are cut short. Bodies that still had a collision due are held
  // (types.h, StepStats::eventBudgetReached), so no disk may end a step inside another or in a wall.
  RandomDiskOptions o = thousandDiskOptions();
  o.count = 300;
  o.xmax = o.ymax = 30;
  o.minSpeed = 2;
  o.maxSpeed = 4;
  const auto specs = randomDisks(o);
  World world(worldDefWithBudget(25));
  const ClosedBox box = makeClosedBox(world, 0, 0, 30, 30, 1.0);
  const auto disks = addDisks(world, specs);
  int cutShort = 0;
  for (int step = 0; step < 40; ++step) {
    world.step(0.25);
    EXPECT_LE(world.stats().eventsProcessed, 25);
    cutShort += world.stats().eventBudgetReached ? 1 : 0;
    ASSERT_TRUE(allFinite(world, disks));
    const double overlap = maxRelativeOverlap(world, disks);
    const double penetration = maxRelativeWallPenetration(world, disks, box);
    EXPECT_LE(overlap, 1e-9) << "after step " << step;
    EXPECT_LE(penetration, 1e-9) << "after step " << step;
    if (overlap > 1e-9 || penetration > 1e-9) break;
  }
  EXPECT_GT(cutShort, 30);
}

}  // namespace
