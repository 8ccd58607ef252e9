// Hard cases (suites HardCase*): Newton's cradle, acute wedges and concave corners, gliding along
// polylines and walls, grazing passes, bodies created overlapping, coordinates far from the origin, radii
// 10^4 apart, simultaneous collisions on a lattice, fast bodies against every geometry, and a body squeezed
// by a kinematic wall. Each has an answer derived independently of the engine (closed forms, unfolding,
// symmetry), written next to it.
//
// Every suite is parameterized over rattle::StepMode and instantiated for the modes listed in the comment
// above its INSTANTIATE line: the modes whose contract (types.h, StepMode) covers the property tested:
//  - exact event times and outcomes, the overlap rules, "never through": Hybrid and Predictive. Discrete
//    moves every body a whole step, then pushes overlapping pairs apart and reflects them once per pair per
//    step, so it gives approximate answers, responds to round-off overlaps and may tunnel.
//  - properties every mode promises (no contact on an exactly tangent pass, determinism, momentum, no
//    energy gain or storm of events from overlapping starts, a step that returns with finite state): all
//    three.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "hard_case_support.h"
#include "rattle/rattle.h"
#include "world_test_support.h"

namespace {

using namespace rattle_test;
using hard_case::crossL;
using hard_case::dotL;
using hard_case::LD;
using hard_case::lenL;
using hard_case::LV;
using hard_case::lv;
using hard_case::ModeParamName;
using hard_case::ModeTest;
using hard_case::near;
using hard_case::perpL;
using hard_case::str;
using hard_case::toVec;
using rattle::ContactEvent;
using rattle::StepMode;
using rattle::WorldDef;

constexpr LD kPi = std::numbers::pi_v<long double>;

FixtureId addFixture(World& world, BodyId body, const rattle::Geometry& g, double restitution = 0.0) {
  FixtureDef fd;
  fd.geometry = g;
  fd.restitution = restitution;
  return world.createFixture(body, fd);
}

// A static body at the origin holding one fixture.
FixtureId addStatic(World& world, const rattle::Geometry& g, double restitution = 0.0) {
  return addFixture(world, world.createBody(bodyDef(BodyType::Static)), g, restitution);
}

// =====================================================================================================
// Newton's cradle.

class HardCaseCradle : public ModeTest {};

TEST_P(HardCaseCradle, OnlyTheLastDiskMovesOnAtTheIncomingSpeed) {
  // Five equal disks (radius 0.5, restitution 1) touching in a row along a direction d: centres k d,
  // k = 0..4. Either a sixth equal disk (the striker) comes in along d at speed 2 from -2.7 d, or the
  // first disk of the row is itself given the speed. Equal masses exchange their velocities in a head-on
  // elastic collision, so the collisions pass the velocity down the row at one instant (the independent
  // collision model) and afterwards only the last disk moves, at 2 d, the others at rest. Along (1, 0)
  // the row touches exactly; along (0.6, 0.8) and (-0.28, 0.96) the centres are rounded, so neighbours
  // touch only up to round-off (apart or overlapping by an ulp), which must not change the outcome.
  struct Case {
    Vec2 d;
    bool striker;
  };
  for (const Case& c : {Case{{1, 0}, true}, Case{{1, 0}, false}, Case{{0.6, 0.8}, true}, Case{{0.6, 0.8}, false},
                        Case{{-0.28, 0.96}, true}}) {
    SCOPED_TRACE("direction " + str(c.d) + (c.striker ? ", striker" : ", first disk pushed"));
    World world(def());
    const double speed = 2;
    std::vector<Disk> disks;
    if (c.striker) disks.push_back(addDisk(world, {-2.7 * c.d, speed * c.d, 0.5, 1.0, 1.0}));
    for (int k = 0; k < 5; ++k)
      disks.push_back(
          addDisk(world, {Vec2{k * c.d.x, k * c.d.y}, (!c.striker && k == 0) ? speed * c.d : Vec2{}, 0.5, 1.0, 1.0}));
    std::vector<Vec2> start;
    for (const Disk& d : disks) start.push_back(world.position(d.body));
    const LD e0 = kineticEnergy(world, disks);
    const double tImpact = c.striker ? 0.85 : 0.0;  // the striker closes a gap of 1.7 at speed 2
    const size_t expectedEvents = disks.size() - 1;
    std::vector<double> eventTimes;
    const double dt = 0.25;
    for (int step = 0; step < 12; ++step) {
      const double t0 = world.time();
      world.step(dt);
      for (const ContactEvent& ev : world.contactEvents()) eventTimes.push_back(t0 + ev.time);
    }
    ASSERT_EQ(eventTimes.size(), expectedEvents);
    for (double t : eventTimes) EXPECT_NEAR(t, tImpact, 1e-12);
    const double T = world.time();
    for (size_t i = 0; i + 1 < disks.size(); ++i) {
      EXPECT_LE(rattle::length(world.velocity(disks[i].body)), 1e-12 * speed) << "disk " << i << " still moves";
      // At rest where it was, except the striker, which stopped where it met the row, at -d.
      const LV expected = c.striker && i == 0 ? -lv(c.d) : lv(start[i]);
      EXPECT_TRUE(near(world.position(disks[i].body), expected, 1e-12)) << "disk " << i;
    }
    const Disk& last = disks.back();
    EXPECT_TRUE(near(world.velocity(last.body), speed * lv(c.d), 1e-12));
    EXPECT_TRUE(near(world.position(last.body), lv(start.back()) + (speed * (T - tImpact)) * lv(c.d), 1e-11));
    EXPECT_NEAR(static_cast<double>(kineticEnergy(world, disks) / e0), 1.0, 1e-13);
  }
}

// Modes: Hybrid, Predictive (one instant, in event order). Not Discrete (one response per pair per step).
INSTANTIATE_TEST_SUITE_P(, HardCaseCradle, ::testing::Values(StepMode::Hybrid, StepMode::Predictive), ModeParamName());

// =====================================================================================================
// Wedges and concave corners, against the billiard unfolding.
//
// A disk of radius r inside a wedge whose two walls meet at angle theta: its centre moves in a smaller
// wedge with the same walls moved in by r, whose apex A' lies on the bisector at r / sin(theta/2) from
// the apex. Reflecting that wedge across its walls over and over tiles the plane around A' with copies
// k = ..., -1, 0, 1, ... (copy k spans polar angles k theta +- theta/2 about the bisector), and the
// centre's path, unfolded, is the straight line U(t) = U0 + V t (elastic bounces, constant speed). So:
//  - the polar angle phi(t) = phi0 + angle from U0 to U(t) (a straight line sweeps less than pi);
//  - copy k = round(phi / theta); folding back, the true centre is at polar angle (-1)^k (phi - k theta)
//    and the same distance from A', and the velocity's angle alpha becomes alpha - k theta (k even) or
//    k theta - alpha (k odd);
//  - bounce j happens when phi crosses the boundary theta/2 + (j - 1) theta (or its mirror when phi
//    decreases): at t = -cross(e, U0) / cross(e, V) with e the boundary's direction;
//  - the total number of bounces is the number of boundaries strictly between phi0 and phi0 + the angle
//    from U0 to V (the limit of phi). For a path parallel to the bisector, heading in, the limit is pi
//    more than the start angle, and with theta = pi / 18 (10 degrees) that is 18 boundaries, at
//    theta/2 + j theta for j = 0..17 (17.5 theta = 175 degrees < 180 < 18.5 theta).

struct Wedge {
  LV apex;      // where the walls meet
  LV d1, d2;    // unit directions of the two walls, from the apex (d1 counter-clockwise of d2)
  LD r = 0.5;   // disk radius
  LV bisector;  // unit
  LD half = 0;  // theta / 2
  LV apexC;     // A': the apex of the centre's wedge

  Wedge(LV apex_, LV d1_, LV d2_, LD r_) : apex(apex_), d1(d1_), d2(d2_), r(r_) {
    const LV s = d1 + d2;
    bisector = (1 / lenL(s)) * s;
    half = std::acos(std::clamp<LD>(dotL(d1, bisector), -1, 1));
    apexC = apex + (r / std::sin(half)) * bisector;
  }
  LD theta() const { return 2 * half; }
  // To and from coordinates along (bisector, its perpendicular).
  LV toLocal(LV w) const { return {dotL(w, bisector), crossL(bisector, w)}; }
  LV toWorld(LV l) const { return l.x * bisector + l.y * perpL(bisector); }
  // Signed distance of p from each wall's line, positive inside the wedge.
  LD insideDistance(LV p) const {
    const LV q = p - apex;
    return std::min(crossL(d2, q), crossL(q, d1));
  }
};

struct Unfolded {
  LV position, velocity;
  int copy = 0;  // |copy| bounces so far
  LD phi = 0;
};

Unfolded unfold(const Wedge& w, LV p0, LV v, LD t) {
  const LV u0 = w.toLocal(p0 - w.apexC), vl = w.toLocal(v);
  const LV u = u0 + t * vl;
  const LD phi0 = std::atan2(u0.y, u0.x);
  const LD phi = phi0 + std::atan2(crossL(u0, u), dotL(u0, u));
  const LD theta = w.theta();
  const int k = static_cast<int>(std::lround(phi / theta));
  const bool odd = (k % 2) != 0;
  const LD folded = odd ? k * theta - phi : phi - k * theta;
  const LD alpha = std::atan2(vl.y, vl.x);
  const LD beta = odd ? k * theta - alpha : alpha - k * theta;
  const LD rho = lenL(u), speed = lenL(vl);
  Unfolded out;
  out.position = w.apexC + w.toWorld({rho * std::cos(folded), rho * std::sin(folded)});
  out.velocity = w.toWorld({speed * std::cos(beta), speed * std::sin(beta)});
  out.copy = k;
  out.phi = phi;
  return out;
}

// The bounce times of the whole unfolded path, in order.
std::vector<LD> bounceTimes(const Wedge& w, LV p0, LV v) {
  const LV u0 = w.toLocal(p0 - w.apexC), vl = w.toLocal(v);
  const LD phi0 = std::atan2(u0.y, u0.x);
  const LD phiEnd = phi0 + std::atan2(crossL(u0, vl), dotL(u0, vl));
  const LD theta = w.theta();
  std::vector<LD> times;
  for (int j = 0;; ++j) {
    const LD boundary = phiEnd > phi0 ? w.half + j * theta : -w.half - j * theta;
    if (phiEnd > phi0 ? boundary >= phiEnd : boundary <= phiEnd) break;
    const LV e{std::cos(boundary), std::sin(boundary)};
    times.push_back(-crossL(e, u0) / crossL(e, vl));
  }
  return times;
}

struct WedgeRun {
  int events = 0, expected = 0;  // bounces seen, and the unfolding's bounces up to the end of the run
  double worstPosition = 0, worstVelocity = 0;
};

// Runs a disk (restitution 1, no gravity) from p0 with velocity v inside the wedge made of the given walls
// and compares every step with the unfolding and every event with the bounce times.
WedgeRun runWedge(const WorldDef& def, const Wedge& w, const std::vector<rattle::Geometry>& walls, Vec2 p0, Vec2 v,
                  double dt, int steps) {
  World world(def);
  const BodyId wallBody = world.createBody(bodyDef(BodyType::Static));
  for (const auto& g : walls) addFixture(world, wallBody, g, 1.0);
  const Disk disk = addDisk(world, {p0, v, static_cast<double>(w.r), 1.0, 1.0});
  const std::vector<LD> bounces = bounceTimes(w, lv(p0), lv(v));
  const LD speed = lenL(lv(v));
  WedgeRun run;
  for (int step = 0; step < steps; ++step) {
    const double t0 = world.time();
    world.step(dt);
    for (const ContactEvent& ev : world.contactEvents()) {
      if (run.events < static_cast<int>(bounces.size())) {
        EXPECT_NEAR(t0 + ev.time, static_cast<double>(bounces[static_cast<size_t>(run.events)]), 1e-9)
            << "bounce " << run.events + 1;
      }
      ++run.events;
    }
    const LD t = world.time();
    const Unfolded u = unfold(w, lv(p0), lv(v), t);
    const Vec2 p = world.position(disk.body), vel = world.velocity(disk.body);
    run.worstPosition = std::max(run.worstPosition, static_cast<double>(lenL(lv(p) - u.position)));
    run.worstVelocity = std::max(run.worstVelocity, static_cast<double>(lenL(lv(vel) - u.velocity) / speed));
    // Bounces so far, and the velocity, unless the step ended within round-off of a bounce.
    bool nearBounce = false;
    for (LD b : bounces) nearBounce = nearBounce || std::fabs(b - t) < 1e-9L;
    EXPECT_TRUE(near(p, u.position, 1e-9L * (1 + lenL(u.position)))) << "position at t = " << (double)t;
    if (!nearBounce) {
      EXPECT_TRUE(near(vel, u.velocity, 1e-9L * speed)) << "velocity at t = " << (double)t;
      EXPECT_EQ(run.events, std::abs(u.copy)) << "bounces by t = " << (double)t;
    }
    EXPECT_NEAR(static_cast<double>(lenL(lv(vel)) / speed), 1.0, 1e-12) << "speed at t = " << (double)t;
    EXPECT_GE(static_cast<double>(w.insideDistance(lv(p))), static_cast<double>(w.r) * (1 - 1e-9))
        << "past a wall (towards the apex) at t = " << (double)t << ": " << str(p);
    if (::testing::Test::HasFailure() && step > 0 && run.worstPosition > 1e-6) break;
  }
  run.expected =
      static_cast<int>(std::count_if(bounces.begin(), bounces.end(), [&](LD b) { return b <= world.time(); }));
  EXPECT_EQ(run.events, run.expected) << "total bounces";
  return run;
}

class HardCaseWedge : public ModeTest {};

TEST_P(HardCaseWedge, DiskDrivenIntoATenDegreeWedgeComesBackOutAfterTheUnfoldingCount) {
  // Walls of length 40 from the apex at the origin, opening towards +x, 10 degrees apart: as a Polyline
  // (apex corner included) or as two Segments. Disk radius 0.5, so A' = (0.5 / sin 5 deg, 0) = (5.74, 0).
  const LD h = kPi / 36;  // half of 10 degrees
  const LV d1{std::cos(h), std::sin(h)}, d2{std::cos(h), -std::sin(h)};
  const Wedge w({0, 0}, d1, d2, 0.5L);
  const Vec2 e1 = toVec(40.0L * d1), e2 = toVec(40.0L * d2);
  const std::vector<rattle::Geometry> polyline{rattle::Polyline{{e1, {0, 0}, e2}}};
  const std::vector<rattle::Geometry> segments{rattle::Segment{{0, 0}, e1}, rattle::Segment{{0, 0}, e2}};
  struct Case {
    Vec2 p0, v;
    int expected;  // -1: take the unfolding's count
  };
  const double a = 2 * std::numbers::pi / 180;
  for (const Case& c : {Case{{30, 0.3}, {-1, 0}, 18}, Case{{30, 1.0}, {-1, 0}, 18}, Case{{30, -0.7}, {-1, 0}, 18},
                        Case{{30, 0.5}, {-std::cos(a), std::sin(a)}, -1}, Case{{25, -1}, {-3, 0.05}, -1}})
    for (bool asPolyline : {true, false}) {
      SCOPED_TRACE("p0 " + str(c.p0) + ", v " + str(c.v) + (asPolyline ? ", polyline" : ", two segments"));
      const auto bounces = bounceTimes(w, lv(c.p0), lv(c.v));
      if (c.expected >= 0) {
        EXPECT_EQ(static_cast<int>(bounces.size()), c.expected) << "the unfolding itself";
      }
      // Heading in and back out takes about 2 (30 - 5.7) / |v|; stop before the disk reaches the mouth.
      const double duration = 50.0 / rattle::length(c.v);
      const WedgeRun run =
          runWedge(def(), w, asPolyline ? polyline : segments, c.p0, c.v, 0.25, static_cast<int>(duration / 0.25));
      EXPECT_EQ(run.expected, static_cast<int>(bounces.size())) << "the run should see every bounce";
      std::printf(
          "[ wedge 10 deg ] p0 %s v %s %s: %d bounces (unfolding %zu); worst position error %.3g, "
          "velocity %.3g\n",
          str(c.p0).c_str(), str(c.v).c_str(), asPolyline ? "polyline" : "segments", run.events, bounces.size(),
          run.worstPosition, run.worstVelocity);
    }
}

// Modes: Hybrid, Predictive. Not Discrete (one response per pair per step; deep in the wedge the disk
// bounces many times per step).
INSTANTIATE_TEST_SUITE_P(, HardCaseWedge, ::testing::Values(StepMode::Hybrid, StepMode::Predictive), ModeParamName());

class HardCaseConcaveCorner : public ModeTest {};

TEST_P(HardCaseConcaveCorner, DiskIntoARightAngleCornerOnTheDiagonalComesStraightBack) {
  // Polyline (0, 10) - (0, 0) - (10, 0): a right-angle concave corner. A disk (radius 0.5, restitution 1)
  // moving along the diagonal from (5, 5) with velocity (-1, -1) touches both arms at once when its centre
  // reaches (0.5, 0.5), at t = 4.5. The two reflections (x and y velocity components) commute, so in either
  // order it leaves with (1, 1): back along the way it came. Exactly two events, both at t = 4.5.
  World world(def());
  const FixtureId corner = addStatic(world, rattle::Polyline{{{0, 10}, {0, 0}, {10, 0}}});
  const Disk d = addDisk(world, {{5, 5}, {-1, -1}, 0.5, 1.0, 1.0});
  std::vector<ContactEvent> events;
  for (int step = 0; step < 32; ++step) {
    const double t0 = world.time();
    world.step(0.25);
    for (ContactEvent ev : world.contactEvents()) {
      ev.time += t0;
      events.push_back(ev);
    }
  }
  ASSERT_EQ(events.size(), 2u);
  for (const ContactEvent& ev : events) {
    EXPECT_EQ(ev.fixtureA, corner);
    EXPECT_NEAR(ev.time, 4.5, 1e-12);
    EXPECT_NEAR(ev.impulse, 2 * d.mass, 1e-12 * d.mass);
  }
  EXPECT_TRUE(near(world.velocity(d.body), {1, 1}, 1e-15));
  EXPECT_TRUE(near(world.position(d.body), {0.5 + 3.5, 0.5 + 3.5}, 1e-12));
}

TEST_P(HardCaseConcaveCorner, DiskIntoPolylineCornersOfSeveralAnglesFollowsTheUnfolding) {
  // Concave corners of 60, 90, 120 and 135 degrees (a Polyline with the corner at the origin, opening
  // towards +x), entered off the bisector; the unfolding (above) gives every bounce and the whole path.
  for (double degrees : {60.0, 90.0, 120.0, 135.0}) {
    const LD h = static_cast<LD>(degrees) * kPi / 360;
    const LV d1{std::cos(h), std::sin(h)}, d2{std::cos(h), -std::sin(h)};
    const Wedge w({0, 0}, d1, d2, 0.5L);
    const std::vector<rattle::Geometry> walls{rattle::Polyline{{toVec(30.0L * d1), {0, 0}, toVec(30.0L * d2)}}};
    for (const Vec2& v : {Vec2{-1, 0.1}, Vec2{-1, -0.35}, Vec2{-2, 0.02}}) {
      SCOPED_TRACE(std::to_string(degrees) + " degrees, v " + str(v));
      const Vec2 p0{12, 0.4};
      const auto bounces = bounceTimes(w, lv(p0), lv(v));
      EXPECT_GE(bounces.size(), 1u);
      const WedgeRun run = runWedge(def(), w, walls, p0, v, 0.25, static_cast<int>(20.0 / rattle::length(v) / 0.25));
      std::printf(
          "[ corner %.0f deg ] v %s: %d bounces (unfolding: %d in the run, %zu in all); worst position "
          "error %.3g\n",
          degrees, str(v).c_str(), run.events, run.expected, bounces.size(), run.worstPosition);
    }
  }
}

// Modes: Hybrid, Predictive.
INSTANTIATE_TEST_SUITE_P(, HardCaseConcaveCorner, ::testing::Values(StepMode::Hybrid, StepMode::Predictive),
                         ModeParamName());

// =====================================================================================================
// Gliding along polylines and walls, grazing passes.

class HardCaseGlide : public ModeTest {};

TEST_P(HardCaseGlide, DiskAlongACollinearPolylineIsNeverDeflectedAtItsCorners) {
  // A polyline of 20 collinear points along a direction u (points s_k u with random gaps 0.3..2.5), and a
  // disk (radius 0.5, restitution 1 or 0) touching it, centre at distance r from the line, moving along u at
  // speed 3 past every interior corner and off the far end. The disk touches each corner only tangentially
  // (a double root): no contact, no deflection. Along a slanted u the points and the start are rounded, so
  // the disk may overlap the line by an ulp; in the "collinear-ish" variant every point is also moved off
  // the line by up to 4e-16 of its distance from the origin, towards or away from the disk: round-off, not
  // a bump, so still no contact. Expected: no contact events, velocity unchanged, distance from the line r.
  std::mt19937_64 rng(42);
  auto uniform = [&rng](double lo, double hi) {
    return lo + (hi - lo) * (static_cast<double>(rng() >> 11) * 0x1.0p-53);
  };
  for (double phi : {0.0, 0.3, std::numbers::pi / 4, 1.1, 2.5, -2.0})
    for (int side : {1, -1})
      for (bool perturbed : {false, true})
        for (double e : {1.0, 0.0}) {
          SCOPED_TRACE("phi " + std::to_string(phi) + " side " + std::to_string(side) +
                       (perturbed ? " collinear-ish" : " collinear") + " e " + std::to_string(e));
          const Vec2 u{std::cos(phi), std::sin(phi)};
          const Vec2 n = side * rattle::perpendicular(u);
          std::vector<Vec2> points;
          double s = -1;
          for (int k = 0; k < 20; ++k) {
            Vec2 p = s * u;
            if (perturbed) p = p + (uniform(-4e-16, 4e-16) * std::max(1.0, std::fabs(s))) * n;
            points.push_back(p);
            s += uniform(0.3, 2.5);
          }
          World world(def());
          addStatic(world, rattle::Polyline{points}, e);
          const double r = 0.5;
          const Vec2 v0 = 3.0 * u;
          const Disk d = addDisk(world, {0.0 * u + r * n, v0, r, 1.0, e});
          int events = 0;
          const double length = s + 2;  // past the last point
          const int steps = static_cast<int>(length / 3 / 0.1) + 1;
          double worstDistance = 0;
          for (int step = 0; step < steps; ++step) {
            world.step(0.1);
            events += static_cast<int>(world.contactEvents().size());
            const Vec2 p = world.position(d.body);
            worstDistance = std::max(worstDistance, std::fabs(rattle::dot(p, n) - r));
          }
          EXPECT_EQ(events, 0);
          const Vec2 v = world.velocity(d.body);
          // Collinear: untouched. Collinear-ish: a corner off the line by up to 1.2e-14 may have its
          // round-off approach absorbed (hybrid_step.cpp), a deflection of that order, never more.
          EXPECT_LE(rattle::length(v - v0), (perturbed ? 1e-12 : 1e-15) * 3) << "deflected: " << str(v);
          EXPECT_LE(worstDistance, 1e-12) << "drifted off the line";
        }
}

TEST_P(HardCaseGlide, DiskAlongAWallTouchingItNeverCollidesWithItNorDrifts) {
  // (a) A closed box [0, 10]^2 of static segments (restitution 1); a disk (radius 0.5) at (1, 0.5) moving
  // (3, 0): it runs along the floor, touching it, and bounces between the side walls. Unfolding along x
  // (u = x - 0.5 runs freely, bounces at multiples of 9): floor((0.5 + 3 * 10) / 9) = 3 bounces in 10 s,
  // all with the side walls; y stays exactly 0.5 and the vertical velocity exactly 0.
  {
    World world(def());
    const ClosedBox box = makeClosedBox(world, 0, 0, 10, 10, 1.0);
    const Disk d = addDisk(world, {{1, 0.5}, {3, 0}, 0.5, 1.0, 1.0});
    int events = 0;
    for (int step = 0; step < 100; ++step) {
      world.step(0.1);
      for (const ContactEvent& ev : world.contactEvents()) {
        ++events;
        EXPECT_TRUE(ev.fixtureA == box.walls[0] || ev.fixtureA == box.walls[1]) << "touched the floor or ceiling";
      }
      EXPECT_EQ(world.position(d.body).y, 0.5);
      EXPECT_EQ(world.velocity(d.body).y, 0.0);
    }
    EXPECT_EQ(events, 3);
    // u = 0.5 + 30 = 30.5 = 3 * 9 + 3.5: moving left (odd count) at x = 9.5 - 3.5 = 6.
    EXPECT_NEAR(world.position(d.body).x, 6.0, 1e-12);
    EXPECT_EQ(world.velocity(d.body).x, -3.0);
  }
  // (b) The same along a slanted wall: a static Segment from -50 u to 50 u (u at 0.7 rad) and end walls
  // across it at +-20 u; the disk touches the long wall, centre at r n, moving 4 u. Rounded coordinates:
  // the distance from the wall must stay r within round-off, and only the end walls are hit
  // (at t = 4.875, 14.875, 24.875, ...: 19.5 / 4, then every 39 / 4).
  {
    const double phi = 0.7;
    const Vec2 u{std::cos(phi), std::sin(phi)}, n = rattle::perpendicular(u);
    World world(def());
    const BodyId walls = world.createBody(bodyDef(BodyType::Static));
    const FixtureId longWall = addFixture(world, walls, rattle::Segment{-50.0 * u, 50.0 * u}, 1.0);
    addFixture(world, walls, rattle::Segment{20.0 * u - 5.0 * n, 20.0 * u + 5.0 * n}, 1.0);
    addFixture(world, walls, rattle::Segment{-20.0 * u - 5.0 * n, -20.0 * u + 5.0 * n}, 1.0);
    const Disk d = addDisk(world, {0.5 * n, 4.0 * u, 0.5, 1.0, 1.0});
    std::vector<double> times;
    double worstDistance = 0, worstNormalSpeed = 0;
    for (int step = 0; step < 300; ++step) {
      const double t0 = world.time();
      world.step(0.1);
      for (const ContactEvent& ev : world.contactEvents()) {
        EXPECT_NE(ev.fixtureA, longWall) << "touched the long wall at t = " << t0 + ev.time;
        times.push_back(t0 + ev.time);
      }
      worstDistance = std::max(worstDistance, std::fabs(rattle::dot(world.position(d.body), n) - 0.5));
      worstNormalSpeed = std::max(worstNormalSpeed, std::fabs(rattle::dot(world.velocity(d.body), n)));
    }
    ASSERT_EQ(times.size(), 3u);
    for (size_t k = 0; k < times.size(); ++k) EXPECT_NEAR(times[k], 4.875 + 9.75 * static_cast<double>(k), 1e-9);
    EXPECT_LE(worstDistance, 1e-12);
    EXPECT_LE(worstNormalSpeed, 1e-14 * 4);
  }
}

// Modes: Hybrid, Predictive. Not Discrete: it responds to every overlap found at a step's end, so a path
// that touches a wall with a round-off overlap is a contact there.
TEST_P(HardCaseGlide, PointOnAFloorNeverPassesUnderAWallStandingOnIt) {
  // A floor polygon and a wall polygon standing on it, the wall's bottom edge on the floor's top line (a
  // seam with no gap), under gravity; a point starts on the floor or dropped from below the wall's top,
  // and moves toward the wall at 0.1 to 30 units/s, with restitution 0 or up to 1. Its path along the
  // floor runs along the wall's bottom edge and meets the wall's face at its corner. It must never end
  // up inside the wall, below the floor, or past the wall without having gone over it. 400 random
  // scenes (floor height, wall place and size, start, speed, direction, restitution).
  std::mt19937_64 rng(2026);
  auto uniform = [&rng](double lo, double hi) {
    return lo + (hi - lo) * (static_cast<double>(rng() >> 11) * 0x1.0p-53);
  };
  for (int trial = 0; trial < 400; ++trial) {
    const double y0 = uniform(-10, 10), wx = uniform(-5, 5), ww = uniform(0.2, 2.2), wh = uniform(1, 4);
    const double dir = uniform(0, 1) < 0.5 ? -1 : 1;
    const double x0 = dir > 0 ? wx - uniform(0.5, 5.5) : wx + ww + uniform(0.5, 5.5);
    const double vx = dir * uniform(0.1, 30);
    const double h = uniform(0, 1) < 0.5 ? 0 : uniform(0, 0.9 * wh);
    const double e = uniform(0, 1) < 0.5 ? 0 : uniform(0, 1);
    SCOPED_TRACE("trial " + std::to_string(trial));
    WorldDef def;
    def.mode = GetParam();
    def.gravity = {0, -9.81};
    rattle::World w(def);
    const rattle::BodyId ground = w.createBody({.type = rattle::BodyType::Static});
    w.createFixture(ground, {.geometry = rattle::Polygon{{{-100, y0 - 1}, {100, y0 - 1}, {100, y0}, {-100, y0}}}});
    w.createFixture(ground, {.geometry = rattle::Polygon{{{wx, y0}, {wx + ww, y0}, {wx + ww, y0 + wh}, {wx, y0 + wh}}}});
    const rattle::BodyId point = w.createBody({.type = rattle::BodyType::Dynamic, .position = {x0, y0 + h}, .velocity = {vx, 0}});
    w.createFixture(point, {.geometry = rattle::Point{{0, 0}}, .restitution = e});
    for (int i = 0; i < 120; ++i) {
      w.step(1.0 / 60);
      const rattle::Vec2 p = w.position(point);
      const double slack = 1e-9;
      ASSERT_FALSE(p.x > wx + slack && p.x < wx + ww - slack && p.y < y0 + wh - slack && p.y > y0 - 1 + slack)
          << "inside the wall at step " << i << ": (" << p.x << ", " << p.y << ")";
      ASSERT_FALSE(p.y < y0 - slack && p.x > -100 && p.x < 100) << "below the floor at step " << i << ": (" << p.x << ", " << p.y << ")";
      const bool past = dir > 0 ? p.x > wx + ww : p.x < wx;
      ASSERT_FALSE(past && p.y < y0 + wh) << "past the wall at step " << i << ": (" << p.x << ", " << p.y << ")";
    }
  }
}

INSTANTIATE_TEST_SUITE_P(, HardCaseGlide, ::testing::Values(StepMode::Hybrid, StepMode::Predictive), ModeParamName());

class HardCaseGrazing : public ModeTest {};

TEST_P(HardCaseGrazing, PassAtExactlyTheSumOfRadiiIsNoContact) {
  // Each pair's closest approach is exactly the contact distance (exact in binary): a tangent touch, a
  // double root, not an impact (time_of_impact.h). No event, velocities unchanged bit for bit.
  struct Case {
    const char* name;
    rattle::Geometry target;  // static, at the origin; or a disk when `moving` is set
    bool dynamicTarget;
    Vec2 targetVelocity;
    double targetRadius;
    Vec2 p0, v0;
    double r;
  };
  const std::vector<Case> cases{
      {"two disks, both moving", rattle::Circle{{0, 0}, 0.5}, true, {-1, 0}, 0.5, {-10, 1}, {1, 0}, 0.5},
      {"disks of radii 0.25 and 0.75", rattle::Circle{{0, 0}, 0.75}, true, {0, 0}, 0.75, {-5, -1}, {2, 0}, 0.25},
      {"disk past a static point", rattle::Point{{0, 0}}, false, {}, 0, {-5, 0.5}, {2, 0}, 0.5},
      {"disk past a static circle", rattle::Circle{{0, 0}, 1.0}, false, {}, 0, {-5, 1.5}, {1, 0}, 0.5},
      {"disk over a polyline apex",
       rattle::Polyline{{{-2, -2}, {0, 0}, {2, -2}}},
       false,
       {},
       0,
       {-5, 0.5},
       {1, 0},
       0.5},
      {"disk past a polygon corner",
       rattle::Polygon{{{-2, -1}, {0, -1}, {0, 0}, {-1, 1}}},
       false,
       {},
       0,
       {0.5, -6},
       {0, 1.5},
       0.5},
      {"disk past a kinematic disk", rattle::Circle{{0, 0}, 0.5}, false, {0, -2}, 0, {0.875, -10}, {0, 2}, 0.375},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    World world(def());
    BodyId target;
    if (c.dynamicTarget) {
      target = addDisk(world, {{0, 0}, c.targetVelocity, c.targetRadius, 1.0, 1.0}).body;
    } else {
      const bool kinematic = c.targetVelocity.x != 0 || c.targetVelocity.y != 0;
      target = world.createBody(bodyDef(kinematic ? BodyType::Kinematic : BodyType::Static, {0, 0}, c.targetVelocity));
      addFixture(world, target, c.target, 1.0);
    }
    const Disk d = addDisk(world, {c.p0, c.v0, c.r, 1.0, 1.0});
    int events = 0;
    for (int step = 0; step < 100; ++step) {
      world.step(0.125);
      events += static_cast<int>(world.contactEvents().size());
    }
    EXPECT_EQ(events, 0);
    EXPECT_EQ(world.velocity(d.body), c.v0);
    EXPECT_EQ(world.velocity(target), c.targetVelocity);
    EXPECT_TRUE(near(world.position(d.body), lv(c.p0) + 12.5L * lv(c.v0), 1e-12));
  }
}

TEST_P(HardCaseGrazing, PassAtTheSumOfRadiiUpToRoundOffIsNoContact) {
  // The same passes along directions that do not round exactly: a disk of radius 0.5 moving along w past a
  // static point, circle (radius 1) or disk (radius 0.5) whose offset across the path is computed in
  // doubles, so the closest approach is the contact distance give or take an ulp. A sub-ulp overlap is
  // round-off, not a collision: no event, and the velocity unchanged.
  for (double angle : {0.1, 0.7, 2.0, -1.3, 3.0})
    for (int kind = 0; kind < 3; ++kind) {
      SCOPED_TRACE("angle " + std::to_string(angle) + " kind " + std::to_string(kind));
      const Vec2 w{std::cos(angle), std::sin(angle)};
      const Vec2 n = rattle::perpendicular(w);
      World world(def());
      double reach = 0.5;
      if (kind == 0) {
        addStatic(world, rattle::Point{{0, 0}});
      } else if (kind == 1) {
        addStatic(world, rattle::Circle{{0, 0}, 1.0});
        reach = 1.5;
      } else {
        addDisk(world, {{0, 0}, {0, 0}, 0.5, 1.0, 1.0});
        reach = 1.0;
      }
      const Vec2 v0 = 3.0 * w;
      const Disk d = addDisk(world, {-10.0 * w + reach * n, v0, 0.5, 1.0, 1.0});
      int events = 0;
      for (int step = 0; step < 80; ++step) {
        world.step(0.1);
        events += static_cast<int>(world.contactEvents().size());
      }
      EXPECT_EQ(events, 0);
      EXPECT_LE(rattle::length(world.velocity(d.body) - v0), 1e-15 * 3);
    }
}

// Modes: Hybrid, Predictive, Discrete.
INSTANTIATE_TEST_SUITE_P(, HardCaseGrazing,
                         ::testing::Values(StepMode::Hybrid, StepMode::Predictive, StepMode::Discrete),
                         ModeParamName());

// =====================================================================================================
// Bodies created overlapping.

class HardCaseOverlapping : public ModeTest {};

TEST_P(HardCaseOverlapping, ClusterCreatedOverlappingSeparatesWithoutEnergyGainOrAStormOfEvents) {
  // 12 disks (radius 0.5) dropped at random into a 2 x 2 square, so most pairs overlap deeply, with random
  // velocities (speed 0.5..1) in open space, no gravity. An overlapping pair that approaches collides once
  // and then separates; one that separates is left alone (Bannerman et al. 2014, time_of_impact.h). With
  // restitution e > 0 every collision leaves the pair separating, so the cluster flies apart: kinetic energy
  // never rises (it is conserved for e = 1), momentum is conserved, a handful of events per pair at most
  // (12 disks: 66 pairs; we allow 4 N^2 = 576 events in all), and after 20 s every pair that still
  // overlaps is moving apart (a slow separation may take longer than 20 s).
  for (double e : {1.0, 0.5})
    for (uint64_t seed : {1u, 2u, 3u}) {
      SCOPED_TRACE("e " + std::to_string(e) + " seed " + std::to_string(seed));
      std::mt19937_64 rng(seed);
      auto uniform = [&rng](double lo, double hi) {
        return lo + (hi - lo) * (static_cast<double>(rng() >> 11) * 0x1.0p-53);
      };
      World world(def());
      std::vector<Disk> disks;
      for (int i = 0; i < 12; ++i) {
        const double th = uniform(0, 2 * std::numbers::pi), speed = uniform(0.5, 1);
        disks.push_back(addDisk(
            world, {{uniform(0, 2), uniform(0, 2)}, {speed * std::cos(th), speed * std::sin(th)}, 0.5, 1.0, e}));
      }
      ASSERT_LT(minPairwiseGap(world, disks), -0.3) << "the cluster should start deeply overlapped";
      const LD e0 = kineticEnergy(world, disks);
      const LongVec2 p0 = momentum(world, disks);
      const LD scale = momentumScale(world, disks);
      LD previous = e0;
      int events = 0, worstStep = 0;
      for (int step = 0; step < 400; ++step) {
        world.step(0.05);
        const int n = static_cast<int>(world.contactEvents().size());
        events += n;
        worstStep = std::max(worstStep, n);
        ASSERT_TRUE(allFinite(world, disks));
        const LD k = kineticEnergy(world, disks);
        EXPECT_LE(k, previous * (1 + 1e-12L)) << "kinetic energy rose at step " << step;
        if (e == 1.0) {
          EXPECT_NEAR(static_cast<double>(k / e0), 1.0, 1e-12);
        }
        previous = k;
        const LongVec2 p = momentum(world, disks);
        EXPECT_LE(std::fabs(static_cast<double>(p.x - p0.x)), 1e-12 * static_cast<double>(scale));
        EXPECT_LE(std::fabs(static_cast<double>(p.y - p0.y)), 1e-12 * static_cast<double>(scale));
      }
      EXPECT_LE(events, 4 * 12 * 12);
      int stillOverlapping = 0;
      for (size_t i = 0; i < disks.size(); ++i)
        for (size_t j = i + 1; j < disks.size(); ++j) {
          const Vec2 dp = world.position(disks[i].body) - world.position(disks[j].body);
          const Vec2 dv = world.velocity(disks[i].body) - world.velocity(disks[j].body);
          if (rattle::length(dp) >= 1.0) continue;
          ++stillOverlapping;
          EXPECT_GT(rattle::dot(dp, dv), 0.0) << "disks " << i << " and " << j << " overlap and do not separate";
        }
      std::printf(
          "[ overlapping cluster e=%.1f seed %d ] %d events (at most %d in a step), kinetic energy x %.6f, "
          "%d pairs still overlapping (separating)\n",
          e, static_cast<int>(seed), events, worstStep, static_cast<double>(previous / e0), stillOverlapping);
    }
}

// Modes: Hybrid, Predictive, Discrete (no mode may gain energy or make a storm of events from an
// overlapping start).
INSTANTIATE_TEST_SUITE_P(, HardCaseOverlapping,
                         ::testing::Values(StepMode::Hybrid, StepMode::Predictive, StepMode::Discrete),
                         ModeParamName());

class HardCaseOverlappingStart : public ModeTest {};

TEST_P(HardCaseOverlappingStart, DiskCreatedOverlappingAWallOrACoincidentDisk) {
  // (a) A disk (radius 0.5, e = 1) created with its centre 0.3 from a static wall, i.e. overlapping it by
  // 0.2, moving into it at speed 1: one collision at t = 0, then it leaves at speed 1; moving out of it: no
  // event; at rest: no event, no motion. (b) Two disks created with the same centre, moving apart: no
  // collision (no approach along any normal), each keeps its velocity.
  for (double vx : {-1.0, 1.0, 0.0}) {
    SCOPED_TRACE("vx " + std::to_string(vx));
    World world(def());
    addStatic(world, rattle::Segment{{0, -10}, {0, 10}}, 1.0);
    const Disk d = addDisk(world, {{0.3, 0}, {vx, 0}, 0.5, 1.0, 1.0});
    int events = 0;
    for (int step = 0; step < 10; ++step) {
      world.step(0.1);
      events += static_cast<int>(world.contactEvents().size());
    }
    EXPECT_EQ(events, vx < 0 ? 1 : 0);
    EXPECT_EQ(world.velocity(d.body).x, std::fabs(vx));
    EXPECT_NEAR(world.position(d.body).x, 0.3 + std::fabs(vx) * 1.0, 1e-12);
  }
  World world(def());
  const Disk a = addDisk(world, {{1, 1}, {1, 0.5}, 0.5, 1.0, 1.0});
  const Disk b = addDisk(world, {{1, 1}, {-1, 0.25}, 0.5, 1.0, 1.0});
  int events = 0;
  for (int step = 0; step < 10; ++step) {
    world.step(0.1);
    events += static_cast<int>(world.contactEvents().size());
  }
  EXPECT_EQ(events, 0);
  EXPECT_EQ(world.velocity(a.body), (Vec2{1, 0.5}));
  EXPECT_EQ(world.velocity(b.body), (Vec2{-1, 0.25}));
}

TEST_P(HardCaseOverlappingStart, StackCreatedOverlappingOnAFloorUnderGravityGainsNoEnergy) {
  // A column of 8 disks (radius 0.5, e = 0.5) created 0.9 apart (each pair overlapping by 0.1) with the
  // lowest touching a floor, plus 4 disks overlapping the column from the side, in a closed box, g = 10
  // down. Energy may rise only through minimum bounces, by at most m restingSpeed^2 / 2 each (see
  // GravityPile in test_gravity.cpp for the derivation and the impulse test that picks them out). No storm
  // of events: at most 1000 in any step (the disks spill over the floor; one that ends up wedged between a
  // side wall and a sleeping disk must come to rest, see GravityResting.DiskWedgedBetweenAWallAndAStatic-
  // DiskComesToRest). State stays finite and inside the box.
  WorldDef d = def();
  d.gravity = {0, -10};
  World world(d);
  const ClosedBox box = makeClosedBox(world, -5, 0, 5, 20);
  std::vector<Disk> disks;
  for (int k = 0; k < 8; ++k) disks.push_back(addDisk(world, {{0, 0.5 + 0.9 * k}, {0, 0}, 0.5, 1.0, 0.5}));
  for (int k = 0; k < 4; ++k) disks.push_back(addDisk(world, {{0.8, 1.0 + 1.7 * k}, {0, 0}, 0.5, 1.0, 0.5}));
  const double m = disks[0].mass, rs = d.restingSpeed;
  LD previous = hard_case::totalEnergy(world, disks, d.gravity);
  int events = 0, worstStep = 0;
  for (int step = 0; step < 200; ++step) {
    world.step(1.0 / 60);
    const auto evs = world.contactEvents();
    events += static_cast<int>(evs.size());
    worstStep = std::max(worstStep, static_cast<int>(evs.size()));
    const LD e = hard_case::totalEnergy(world, disks, d.gravity);
    EXPECT_LE(e - previous, hard_case::minimumBounceAllowance(evs, m, rs) + 1e-12L * std::fabs(previous))
        << "step " << step;
    previous = e;
    ASSERT_TRUE(allFinite(world, disks));
    EXPECT_LE(maxRelativeWallPenetration(world, disks, box), 1e-9) << "step " << step;
    EXPECT_FALSE(world.stats().eventBudgetReached);
  }
  EXPECT_LE(worstStep, 1000);
  int asleep = 0;
  for (const Disk& disk : disks) asleep += world.isAsleep(disk.body) ? 1 : 0;
  std::printf(
      "[ overlapping stack under gravity ] %d events in 200 steps (at most %d in a step); %d of %zu asleep "
      "after 3.3 s; worst overlap now %.3g of a radius\n",
      events, worstStep, asleep, disks.size(), maxRelativeOverlap(world, disks));
}

// Modes: Hybrid, Predictive (the overlap rules of time_of_impact.h, contacts made exactly). Not Discrete,
// which pushes overlapping pairs apart after the fact: that moves disks (and under gravity can lift them,
// adding potential energy) and leaves walls penetrated by up to a step's travel.
INSTANTIATE_TEST_SUITE_P(, HardCaseOverlappingStart, ::testing::Values(StepMode::Hybrid, StepMode::Predictive),
                         ModeParamName());

// =====================================================================================================
// Scale: far from the origin, radii 10^4 apart.

class HardCaseScale : public ModeTest {};

// The closed-form outcome of two disks colliding: first contact of centres c1 + v1 t, c2 + v2 t at distance
// r1 + r2, then the impulse along the normal with restitution e, all in long double from the exact doubles.
struct TwoDiskOutcome {
  LD time;
  LV v1, v2;
  LD impulse;
};
TwoDiskOutcome twoDiskCollision(Vec2 c1, Vec2 v1, double r1, double m1, Vec2 c2, Vec2 v2, double r2, double m2,
                                double e) {
  const LV r = lv(c1) - lv(c2), v = lv(v1) - lv(v2);
  const LD reach = static_cast<LD>(r1) + r2;
  const LD A = dotL(v, v), b = dotL(r, v), c = dotL(r, r) - reach * reach;
  const LD t = c / (-b + std::sqrt(b * b - A * c));
  const LV rc = r + t * v;
  const LV n = (1 / lenL(rc)) * rc;  // from 2 towards 1
  const LD vn = dotL(v, n);
  const LD j = -(1 + e) * vn / (1 / static_cast<LD>(m1) + 1 / static_cast<LD>(m2));
  return {t, lv(v1) + (j / m1) * n, lv(v2) - (j / m2) * n, j};
}

TEST_P(HardCaseScale, CollisionAtAMillionFromTheOriginIsExactRelativeToTheScale) {
  // Two disks of radius 0.01 collide obliquely, once near the origin and once with every coordinate
  // shifted by (1e6, 1e6). Expected: the closed form, computed in long double from the positions as stored.
  // Near the origin that holds to round-off. At 1e6 a stored coordinate is exact, but each move rounds it
  // to ulp(1e6) = 1.16e-10, so the contact normal is known to about 2 ulp(1e6) / (r1 + r2) = 1.2e-8 and the
  // velocities after to that times |v|: tolerances 8 ulp(1e6) / (r1 + r2) |v| for velocities and
  // 8 ulp(1e6) / |v| for the time. "Exact relative to the scale": the errors are those of the coordinates.
  const double ulp = std::nextafter(1e6, 2e6) - 1e6;
  for (double shift : {0.0, 1e6}) {
    SCOPED_TRACE("shift " + std::to_string(shift));
    World world(def());
    const Vec2 X{shift, shift};
    const Vec2 c1 = X + Vec2{0, 0}, c2 = X + Vec2{0.1, 0.005};
    const Vec2 v1{1, 0.25}, v2{-1, 0};
    const Disk a = addDisk(world, {c1, v1, 0.01, 1.0, 1.0});
    const Disk b = addDisk(world, {c2, v2, 0.01, 2.0, 1.0});
    const TwoDiskOutcome o = twoDiskCollision(c1, v1, 0.01, a.mass, c2, v2, 0.01, b.mass, 1.0);
    world.step(0.1);
    ASSERT_EQ(world.contactEvents().size(), 1u);
    const double vscale = 2.1;
    const double timeTol = shift == 0 ? 1e-15 : 8 * ulp / vscale;
    const double velTol = shift == 0 ? 1e-13 : 8 * ulp / 0.02 * vscale;
    EXPECT_NEAR(world.contactEvents()[0].time, static_cast<double>(o.time), timeTol);
    EXPECT_TRUE(near(world.velocity(a.body), o.v1, velTol));
    EXPECT_TRUE(near(world.velocity(b.body), o.v2, velTol));
    const LV pa = lv(c1) + o.time * lv(v1) + (0.1L - o.time) * o.v1;
    EXPECT_TRUE(near(world.position(a.body), pa, shift == 0 ? 1e-15 : 8 * ulp));
    std::printf("[ far from origin, shift %g ] velocity error %.3g (tolerance %.3g)\n", shift,
                static_cast<double>(lenL(lv(world.velocity(a.body)) - o.v1)), velTol);
  }
}

TEST_P(HardCaseScale, SmallDiskGasAtAMillionFromTheOrigin) {
  // 200 disks of radius 0.01 in a closed box [1e6, 1e6 + 1]^2 (restitution 1), 8 s. Kinetic energy is
  // conserved to round-off (an elastic impulse along any unit normal keeps it). Overlaps and wall
  // penetrations stay within the rounding of the coordinates: 64 ulp(1e6) = 7.5e-9, i.e. 7.5e-7 of a radius.
  const double X = 1e6, ulp = std::nextafter(1e6, 2e6) - 1e6;
  World world(def());
  const ClosedBox box = makeClosedBox(world, X, X, X + 1, X + 1, 1.0);
  RandomDiskOptions o;
  o.count = 200;
  o.seed = 9;
  o.xmin = o.ymin = X;
  o.xmax = o.ymax = X + 1;
  o.minRadius = o.maxRadius = 0.01;
  o.minSpeed = 0.2;
  o.maxSpeed = 1;
  o.minGap = 1e-4;
  const auto disks = addDisks(world, randomDisks(o));
  const LD e0 = kineticEnergy(world, disks);
  long long events = 0;
  double worstOverlap = -1, worstPenetration = -1;
  for (int step = 0; step < 400; ++step) {
    world.step(0.02);
    events += static_cast<long long>(world.contactEvents().size());
    worstOverlap = std::max(worstOverlap, maxRelativeOverlap(world, disks));
    worstPenetration = std::max(worstPenetration, maxRelativeWallPenetration(world, disks, box));
    for (const Disk& d : disks) ASSERT_TRUE(centreInside(world.position(d.body), box));
  }
  EXPECT_NEAR(static_cast<double>(kineticEnergy(world, disks) / e0), 1.0, 1e-12);
  EXPECT_LE(worstOverlap, 64 * ulp / 0.01);
  EXPECT_LE(worstPenetration, 64 * ulp / 0.01);
  EXPECT_GT(events, 1000);
  std::printf("[ gas at 1e6 ] %lld events; worst overlap %.3g, wall penetration %.3g of a radius (ulp/r = %.3g)\n",
              events, worstOverlap, worstPenetration, ulp / 0.01);
}

TEST_P(HardCaseScale, DisksWhoseRadiiDifferByTenThousandTimes) {
  // A disk of radius 10 and one of radius 1e-3 (masses 1e8 apart at equal density) collide: the small one
  // thrown at the big one obliquely, the big one moving into the small one, and with restitution 1 and 0.5.
  // Expected: the closed form (twoDiskCollision). The small disk's velocity to 1e-12 relative; the big one's
  // change is 1e-8 of the small one's speed, checked to 1e-15 absolute (so to 1e-6 relative of that change).
  struct Case {
    Vec2 cBig, vBig, cSmall, vSmall;
    double e;
  };
  for (const Case& c :
       {Case{{0, 0}, {0, 0}, {20, 3}, {-5, 0}, 1.0}, Case{{0, 0}, {1, 0}, {12, 0.5}, {0, 0}, 1.0},
        Case{{0, 0}, {0, 0}, {20, -7}, {-5, 1}, 0.5}, Case{{0, 0}, {0.5, 0.2}, {15, 2}, {-3, 0}, 0.5}}) {
    SCOPED_TRACE("big v " + str(c.vBig) + " small at " + str(c.cSmall) + " v " + str(c.vSmall) + " e " +
                 std::to_string(c.e));
    World world(def());
    const Disk big = addDisk(world, {c.cBig, c.vBig, 10, 1.0, c.e});
    const Disk small = addDisk(world, {c.cSmall, c.vSmall, 1e-3, 1.0, c.e});
    ASSERT_NEAR(big.mass / small.mass, 1e8, 1e-4);
    const TwoDiskOutcome o = twoDiskCollision(c.cSmall, c.vSmall, 1e-3, small.mass, c.cBig, c.vBig, 10, big.mass, c.e);
    ASSERT_LT(o.time, 5) << "the scene should collide within the step";
    world.step(5);
    ASSERT_EQ(world.contactEvents().size(), 1u);
    const ContactEvent& ev = world.contactEvents()[0];
    EXPECT_NEAR(ev.time, static_cast<double>(o.time), 1e-12 * static_cast<double>(o.time));
    EXPECT_NEAR(ev.impulse, static_cast<double>(o.impulse), 1e-12 * static_cast<double>(o.impulse));
    const LD vs = lenL(lv(c.vSmall) - lv(c.vBig));
    EXPECT_TRUE(near(world.velocity(small.body), o.v1, 1e-12L * vs));
    EXPECT_TRUE(near(world.velocity(big.body), o.v2, 1e-15L));
    // The big disk's change is what the impulse says.
    const LV dv = lv(world.velocity(big.body)) - lv(c.vBig);
    EXPECT_NEAR(static_cast<double>(lenL(dv) * big.mass), static_cast<double>(o.impulse),
                1e-6 * static_cast<double>(o.impulse));
  }
}

// Modes: Hybrid, Predictive. (Discrete may step a small fast disk past the other.)
INSTANTIATE_TEST_SUITE_P(, HardCaseScale, ::testing::Values(StepMode::Hybrid, StepMode::Predictive), ModeParamName());

// =====================================================================================================
// Simultaneous collisions on a lattice; determinism.

// 40 x 25 disks of radius 0.25 on the integer lattice, disk (i, j) moving ((-1)^i, (-1)^j).
struct Lattice {
  static constexpr int kNx = 40, kNy = 25;
  World world;
  std::vector<Disk> disks;
  std::vector<Vec2> start, velocity0;
  explicit Lattice(const WorldDef& def, bool walls) : world(def) {
    if (walls) makeClosedBox(world, -0.5, -0.5, kNx - 0.5, kNy - 0.5, 1.0);
    for (int j = 0; j < kNy; ++j)
      for (int i = 0; i < kNx; ++i) {
        const Vec2 p{static_cast<double>(i), static_cast<double>(j)}, v{i % 2 ? -1.0 : 1.0, j % 2 ? -1.0 : 1.0};
        disks.push_back(addDisk(world, {p, v, 0.25, 1.0, 1.0}));
        start.push_back(p);
        velocity0.push_back(v);
      }
  }
};

// Displacement of a coordinate starting at velocity +1 in the walled lattice: moves +1 until the first
// meeting at t = 0.25, then reverses every 0.5: a triangle wave of amplitude 0.25 and period 1.
LD triangle(LD t) {
  const LD tau = std::fmod(t + 0.25L, 1.0L);
  return tau < 0.5L ? tau - 0.25L : 0.75L - tau;
}

// Events at the meeting instant j (t = 0.25 + 0.5 j) along one axis of n lattice lines: a coordinate of
// index i moves + before instant j when i + j is even; it meets i + 1 (moving -) or the far wall, and
// index 0 moving - meets the near wall.
int eventsPerLine(int n, int j) {
  int count = 0;
  for (int i = 0; i < n; ++i) {
    const bool plus = (i + j) % 2 == 0;
    if (plus) ++count;             // meets i + 1, or the wall after the last
    if (!plus && i == 0) ++count;  // the wall before the first
  }
  return count;
}

class HardCaseSimultaneous : public ModeTest {};

TEST_P(HardCaseSimultaneous, LatticeOfThousandDisksBouncesInLockStep) {
  // In a box with walls half a spacing outside the lattice, every disk meets its x neighbour (or a wall)
  // and its y neighbour (or a wall) at the same instants t = 0.25 + 0.5 j, two collisions per disk per
  // instant, all at once. The normals of a disk's two collisions are orthogonal and equal masses swap the
  // normal components, so the outcome does not depend on their order: each disk reverses both components,
  // and each coordinate follows the triangle wave above (the walls mirror the missing neighbours). The
  // number of events per instant is 25 eventsPerLine(40, j) + 40 eventsPerLine(25, j) (1020 or 1045), and
  // x momentum stays 0.
  // The lock step is dynamically unstable: an error in a disk's position turns its next collision normals
  // by error / radius, so errors grow about fourfold per instant. With a step of 0.1 (not dyadic, so every
  // move rounds) they reach 1e-12 after 6 instants and 1e-9 after 10. With the dyadic step 5/32 every
  // time, position and speed here is exact in binary, so an engine that rounds nothing keeps the lattice
  // exact (the worst error is printed). The tolerance, 1e-6, lets a mode whose clocks round by an ulp
  // pass (amplified fourfold per instant, 1e-16 grows to about 1e-8 in 13 instants), while a wrongly
  // resolved simultaneous collision (an error of 0.25 or more) fails. Some instants fall exactly on a
  // step's end (1.25, 3.75, 6.25);
  // the events of such an instant may be reported by that step or the next, so event counts are checked
  // cumulatively.
  Lattice l(def(), true);
  const double dt = 5.0 / 32;
  int instant = 0;
  long long seen = 0, before = 0, upTo = 0;  // events so far; expected before / up to the step's end
  double worst = 0;
  for (int step = 0; step < 41; ++step) {  // to 6.40625: past the instant at 6.25, before the next
    const double t0 = l.world.time();
    l.world.step(dt);
    const double t1 = l.world.time();
    before = upTo;
    while (0.25 + 0.5 * instant <= t1) {
      const int n =
          Lattice::kNy * eventsPerLine(Lattice::kNx, instant) + Lattice::kNx * eventsPerLine(Lattice::kNy, instant);
      upTo += n;
      if (0.25 + 0.5 * instant < t1) before += n;
      ++instant;
    }
    const auto events = l.world.contactEvents();
    seen += static_cast<long long>(events.size());
    EXPECT_GE(seen, before) << "step " << step;
    EXPECT_LE(seen, upTo) << "step " << step;
    for (const ContactEvent& ev : events) {
      const double t = t0 + ev.time;
      const double phase = std::fmod(t - 0.25, 0.5);
      EXPECT_LE(std::min(phase, 0.5 - phase), 1e-6) << "event at " << t;  // as the positions, below
    }
    const LD w = triangle(t1);
    int bad = 0;
    for (size_t k = 0; k < l.disks.size() && bad < 5; ++k) {
      const LV expectedP = lv(l.start[k]) + LV{l.velocity0[k].x * w, l.velocity0[k].y * w};
      const Vec2 p = l.world.position(l.disks[k].body);
      worst = std::max(worst, static_cast<double>(lenL(lv(p) - expectedP)));
      if (!near(p, expectedP, 1e-6)) {
        ++bad;
        ADD_FAILURE() << "step " << step << ", disk " << k << ": " << near(p, expectedP, 1e-6).message();
      }
    }
    if (bad) break;
    // x momentum: 0 by symmetry (the walls' impulses cancel), to the same relative 1e-6; not checked when
    // the step ended at an instant that may be only partly resolved.
    if (before == upTo) {
      const LongVec2 p = momentum(l.world, l.disks);
      EXPECT_LE(std::fabs(static_cast<double>(p.x)), 1e-6 * static_cast<double>(momentumScale(l.world, l.disks)));
    }
  }
  EXPECT_EQ(instant, 13);
  EXPECT_EQ(seen, upTo);
  std::printf("[ lattice in lock step ] %lld events over 13 instants; worst position error %.3g\n", seen, worst);
}

// Modes: Hybrid, Predictive.
INSTANTIATE_TEST_SUITE_P(, HardCaseSimultaneous, ::testing::Values(StepMode::Hybrid, StepMode::Predictive),
                         ModeParamName());

class HardCaseDeterminism : public ModeTest {};

TEST_P(HardCaseDeterminism, LatticeOfSimultaneousCollisionsGivesTheSameStateTwice) {
  // The same lattice without walls: the inside pairs meet at the same instants, the edge disks fly off,
  // and the collisions spread from there. Two worlds built alike give equal state hashes after every step,
  // and total momentum (no walls: nothing external) is conserved to round-off.
  Lattice a(def(), false), b(def(), false);
  const LongVec2 p0 = momentum(a.world, a.disks);
  const LD scale = momentumScale(a.world, a.disks);
  long long events = 0;
  for (int step = 0; step < 60; ++step) {
    a.world.step(0.1);
    b.world.step(0.1);
    events += static_cast<long long>(a.world.contactEvents().size());
    ASSERT_EQ(a.world.stateHash(), b.world.stateHash()) << "diverged at step " << step;
    ASSERT_EQ(a.world.contactEvents().size(), b.world.contactEvents().size());
    const LongVec2 p = momentum(a.world, a.disks);
    EXPECT_LE(std::fabs(static_cast<double>(p.x - p0.x)), 1e-12 * static_cast<double>(scale)) << "step " << step;
    EXPECT_LE(std::fabs(static_cast<double>(p.y - p0.y)), 1e-12 * static_cast<double>(scale)) << "step " << step;
  }
  EXPECT_GT(events, 5000);
}

// Modes: Hybrid, Predictive, Discrete.
INSTANTIATE_TEST_SUITE_P(, HardCaseDeterminism,
                         ::testing::Values(StepMode::Hybrid, StepMode::Predictive, StepMode::Discrete),
                         ModeParamName());

// =====================================================================================================
// Fast bodies against every geometry.

struct Target {
  const char* name;
  rattle::Geometry geometry;
};

std::vector<Target> fastTargets() {
  rattle::Polygon pentagon;
  for (int k = 0; k < 5; ++k) {
    const double a = 2 * std::numbers::pi * k / 5 + 0.3;
    pentagon.points.push_back({std::cos(a), std::sin(a)});
  }
  return {{"point", rattle::Point{{0, 0}}},
          {"circle", rattle::Circle{{0, 0}, 1.0}},
          {"segment", rattle::Segment{{-1, -1}, {1, 1}}},
          {"polyline", rattle::Polyline{{{-1.5, -1}, {-0.5, 1}, {0.5, -1}, {1.5, 1}}}},
          {"polygon", pentagon}};
}

// Whether the straight path p + v t, t in [0, 1], first comes within r of the segment at one of its ends.
// Its distance from the segment is convex in t: the minimum by ternary search, then the first time it is r
// by bisection before the minimum.
bool firstTouchIsAtSegmentEnd(LV p, LV v, const rattle::Geometry& g, double r) {
  const auto& s = std::get<rattle::Segment>(g);
  const LV a = lv(s.a), b = lv(s.b);
  auto distance = [&](LD t) { return hard_case::pointSegmentDistanceL(p + t * v, a, b); };
  LD lo = 0, hi = 1;
  for (int i = 0; i < 200; ++i) {
    const LD m1 = lo + (hi - lo) / 3, m2 = hi - (hi - lo) / 3;
    (distance(m1) < distance(m2) ? hi : lo) = distance(m1) < distance(m2) ? m2 : m1;
  }
  LD l = 0, h = lo;
  for (int i = 0; i < 200; ++i) {
    const LD mid = (l + h) / 2;
    (distance(mid) > r ? l : h) = mid;
  }
  LD param = 0;
  hard_case::closestOnSegmentL(p + h * v, a, b, &param);
  return !(param > 1e-9L && param < 1 - 1e-9L);
}

class HardCaseFastBodies : public ModeTest {};

TEST_P(HardCaseFastBodies, AMillionRadiiPerStepNeverPassThroughAnyGeometry) {
  // A disk of radius 0.5 at 5e5 per step (1e6 radii) aimed at a random point near a target of size ~2,
  // static or kinematic (random velocity up to 2.5e5), one step of 1 s. The disk's path is rebuilt from
  // the contact events (straight pieces; after each event its velocity changes by impulse / m along the
  // normal), and in the target's frame (where the relative motion is straight too) no piece may come
  // closer to the target than r less 1e-3 r ("never through"). Every path whose straight line would meet
  // the target must have at least one event, and the rebuilt end point must be where the world put the
  // disk (to 1e-6). The deepest approach is printed: against faces it is round-off; against points,
  // circles and corners (a quadratic in |r0 + v t|^2, |r0| the distance at the start, up to 5e5 in the
  // target's frame) the contact time carries the rounding of |r0|^2, about 1e-16 |r0|^2 / r, a few 1e-5
  // here: the disk may end its approach that deep into the target before it is turned back.
  const double r = 0.5, speed = 5e5;
  std::mt19937_64 rng(7);
  auto uniform = [&rng](double lo, double hi) {
    return lo + (hi - lo) * (static_cast<double>(rng() >> 11) * 0x1.0p-53);
  };
  for (const Target& target : fastTargets())
    for (bool kinematic : {false, true}) {
      SCOPED_TRACE(std::string(target.name) + (kinematic ? ", kinematic" : ", static"));
      int hits = 0, failures = 0, endOn = 0;
      double worstDepth = -1;
      for (int trial = 0; trial < 200 && failures < 5; ++trial) {
        World world(def());
        const double ua = uniform(0, 2 * std::numbers::pi), us = kinematic ? uniform(0, 2.5e5) : 0;
        const Vec2 U{us * std::cos(ua), us * std::sin(ua)};
        const BodyId tb = world.createBody(bodyDef(kinematic ? BodyType::Kinematic : BodyType::Static, {0, 0}, U));
        addFixture(world, tb, target.geometry, 1.0);
        const double th = uniform(0, 2 * std::numbers::pi), tAim = uniform(0.3, 0.7);
        const Vec2 dir{std::cos(th), std::sin(th)};
        const bool isSegment = std::holds_alternative<rattle::Segment>(target.geometry);
        const double spread = std::holds_alternative<rattle::Point>(target.geometry) ? 0.8 : 1.6;
        // Near the segment (along it, up to 0.8 across); elsewhere in a square around the target.
        const double along = uniform(-1.1, 1.1), across = uniform(-0.8, 0.8);
        const Vec2 offset = isSegment ? Vec2{along + across / std::numbers::sqrt2, along - across / std::numbers::sqrt2}
                                      : Vec2{uniform(-spread, spread), uniform(-spread, spread)};
        const Vec2 aim = tAim * U + offset;
        const Vec2 c0 = aim - (speed * tAim) * dir, v0 = speed * dir;
        const Disk d = addDisk(world, {c0, v0, r, 1.0, 1.0});
        world.step(1.0);
        // Rebuild the path in the target's frame.
        LV q = lv(c0), vel = lv(v0) - lv(U);
        LD t = 0, closest = std::numeric_limits<LD>::infinity();
        const LD straight = hard_case::pathDistanceL(lv(c0), lv(c0) + (lv(v0) - lv(U)), target.geometry, {0, 0});
        for (const ContactEvent& ev : world.contactEvents()) {
          const LV next = q + (static_cast<LD>(ev.time) - t) * vel;
          closest = std::min(closest, hard_case::pathDistanceL(q, next, target.geometry, {0, 0}));
          const LD sign = ev.bodyB == d.body ? 1 : -1;  // B receives +impulse * normal
          vel = vel + (sign * ev.impulse / d.mass) * lv(ev.normal);
          q = next;
          t = ev.time;
        }
        const LV end = q + (1 - t) * vel;
        closest = std::min(closest, hard_case::pathDistanceL(q, end, target.geometry, {0, 0}));
        const bool shouldHit = straight < r;
        // A Segment's ends are not corners (geometry.h): a disk whose first touch is at an end passes into
        // (and possibly through) the segment. Only paths that first meet its inside are checked.
        if (isSegment && shouldHit && firstTouchIsAtSegmentEnd(lv(c0), lv(v0) - lv(U), target.geometry, r)) {
          ++endOn;
          continue;
        }
        hits += shouldHit ? 1 : 0;
        const LV endWorld = end + lv(U);
        bool ok = true;
        if (shouldHit && world.contactEvents().empty()) ok = false, ADD_FAILURE() << "no event on a hitting path";
        worstDepth = std::max(worstDepth, static_cast<double>(r - closest));
        if (!(closest >= r - 1e-3 * r)) ok = false, ADD_FAILURE() << "the path comes within " << (double)closest;
        if (!near(world.position(d.body), endWorld, 1e-6)) {
          ok = false;
          ADD_FAILURE() << "end position: " << near(world.position(d.body), endWorld, 1e-6).message();
        }
        if (!ok) {
          ++failures;
          ADD_FAILURE() << "trial " << trial << ": c0 " << str(c0) << ", v0 " << str(v0) << ", target velocity "
                        << str(U) << ", " << world.contactEvents().size() << " events";
        }
      }
      EXPECT_GT(hits, 40) << "too few hitting paths for a meaningful test";
      std::printf(
          "[ fast disk vs %s %s ] %d of 200 paths hit (%d more first touch a segment end, unchecked); "
          "deepest approach r - %.3g\n",
          target.name, kinematic ? "kinematic" : "static", hits, endOn, worstDepth);
    }
}

TEST_P(HardCaseFastBodies, HeadOnAtAMillionRadiiPerStepMatchesTheClosedForm) {
  // Head-on along +x at 5e5 from x = -2.5e5 against a flat or round face at x = -f (relative to the target,
  // which moves with velocity (u, 0), u = 0 or -1e5): contact when the gap f0 = 2.5e5 - f - r closes at
  // speed 5e5 - u, at t* = f0 / (5e5 - u); the disk leaves at 2u - 5e5 (elastic, infinite mass), and at the
  // end of the step is at x(t*) + (2u - 5e5)(1 - t*).
  struct Face {
    const char* name;
    rattle::Geometry geometry;
    double f;
  };
  const std::vector<Face> faces{{"point", rattle::Point{{0, 0}}, 0},
                                {"circle", rattle::Circle{{0, 0}, 1.0}, 1},
                                {"segment", rattle::Segment{{0, -1}, {0, 1}}, 0},
                                {"polyline", rattle::Polyline{{{0, -1}, {0, 1}, {1, 1}}}, 0},
                                {"polygon", rattle::Polygon{{{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}}, 1}};
  const double V = 5e5, r = 0.5;
  for (const Face& face : faces)
    for (double u : {0.0, -1e5}) {
      SCOPED_TRACE(std::string(face.name) + ", target velocity " + std::to_string(u));
      World world(def());
      const BodyId tb = world.createBody(bodyDef(u != 0 ? BodyType::Kinematic : BodyType::Static, {0, 0}, {u, 0}));
      addFixture(world, tb, face.geometry, 1.0);
      const Disk d = addDisk(world, {{-2.5e5, 0}, {V, 0}, r, 1.0, 1.0});
      world.step(1.0);
      ASSERT_EQ(world.contactEvents().size(), 1u);
      const LD t = (2.5e5L - face.f - r) / (V - u);
      EXPECT_NEAR(world.contactEvents()[0].time, static_cast<double>(t), 1e-15);
      const LD vAfter = 2 * static_cast<LD>(u) - V;
      EXPECT_EQ(world.velocity(d.body).x, static_cast<double>(vAfter));
      EXPECT_EQ(world.velocity(d.body).y, 0.0);
      const LD x = -2.5e5L + V * t + vAfter * (1 - t);
      EXPECT_NEAR(world.position(d.body).x, static_cast<double>(x), 1e-9);
    }
}

// Modes: Hybrid, Predictive. Not Discrete (it may tunnel; types.h).
INSTANTIATE_TEST_SUITE_P(, HardCaseFastBodies, ::testing::Values(StepMode::Hybrid, StepMode::Predictive),
                         ModeParamName());

// =====================================================================================================
// A dynamic disk squeezed between a kinematic wall and a static wall.

struct Squeeze {
  World world;
  BodyId wall;
  Disk disk;
  // Static wall: x = 0. Kinematic wall: x = 3 at t = 0, moving at (-1, 0). Disk: radius 0.5 at (1.5, 0.2),
  // at rest, restitution 1. The kinematic wall would reach x = 1 (one diameter from the static wall) at
  // t = 2: the disk, bouncing between the walls, gains 2 per hit on the moving wall while the gap closes,
  // so the number of bounces grows without bound as t -> 2 (a Zeno squeeze with unbounded speed).
  explicit Squeeze(const WorldDef& def) : world(def) {
    addStatic(world, rattle::Segment{{0, -10}, {0, 10}}, 1.0);
    wall = world.createBody(bodyDef(BodyType::Kinematic, {3, 0}, {-1, 0}));
    addFixture(world, wall, rattle::Segment{{0, -10}, {0, 10}}, 1.0);
    disk = addDisk(world, {{1.5, 0.2}, {0, 0}, 0.5, 1.0, 1.0});
  }
};

class HardCaseSqueeze : public ModeTest {};

TEST_P(HardCaseSqueeze, DiskSqueezedByAKinematicWallStopsAndTheWallPassesOverIt) {
  // What the engine does (README, "Squeezes"; squeeze.cpp): once the disk has bounced more than 64 times
  // in a step between walls that do not yield, its next contact with the kinematic wall is a squeeze. It
  // stops along the contact's normal, the kinematic wall passes over it (the pair is exempt until they
  // no longer overlap), and it is never pushed through the static wall. Each step stays cheap: no budget
  // (here 10,000) is reached. Before squeezes existed, every step from t = 2 on spent the whole budget.
  WorldDef d = def();
  d.maxEventsPerStep = 10000;
  Squeeze s(d);
  int squeezes = 0, squeezeStep = -1, worstEvents = 0;
  double restingX = 0;
  for (int step = 0; step < 40; ++step) {
    s.world.step(0.1);
    const auto& stats = s.world.stats();
    const Vec2 p = s.world.position(s.disk.body), v = s.world.velocity(s.disk.body);
    const double wx = s.world.position(s.wall).x;
    ASSERT_TRUE(rattle::isFinite(p) && rattle::isFinite(v) && std::isfinite(wx)) << "step " << step;
    EXPECT_GE(p.x, 0.5 - 1e-9) << "through the static wall at step " << step;
    EXPECT_FALSE(stats.eventBudgetReached) << "step " << step;
    worstEvents = std::max(worstEvents, stats.eventsProcessed);
    if (stats.squeezes > 0 && squeezeStep < 0) {
      squeezeStep = step;
      restingX = p.x;
    }
    squeezes += stats.squeezes;
    if (squeezeStep < 0) {
      // Until then the disk is exactly between the walls.
      EXPECT_LE(p.x, wx - 0.5 + 1e-9) << "through the kinematic wall at step " << step;
    } else {
      // Stopped along the normal (x); the wall passes over it.
      EXPECT_EQ(v.x, 0.0) << "step " << step;
      EXPECT_EQ(p.x, restingX) << "step " << step;
    }
    EXPECT_NEAR(s.world.time(), 0.1 * (step + 1), 1e-12);
  }
  // The gap closes to a diameter at t = 2: the squeeze comes in the step that ends there, once.
  EXPECT_EQ(squeezeStep, 19);
  EXPECT_EQ(squeezes, 1);
  EXPECT_LE(worstEvents, 4 * 64);
  EXPECT_LT(s.world.position(s.wall).x, 0.0);  // the wall went on, over the disk and past the static wall
}

// Modes: Hybrid, Predictive.
INSTANTIATE_TEST_SUITE_P(, HardCaseSqueeze, ::testing::Values(StepMode::Hybrid, StepMode::Predictive), ModeParamName());

class HardCaseSqueezeAnyMode : public ModeTest {};

TEST_P(HardCaseSqueezeAnyMode, SqueezeStepReturnsWithFiniteStateAndTheDefaultBudget) {
  // The same squeeze with the default budget (10^6 events a step): each step still returns (within 10 s),
  // with finite state. (Where the disk ends is promised only by the modes that never tunnel: see
  // HardCaseSqueeze.)
  Squeeze s(def());
  for (int step = 0; step < 25; ++step) {
    const auto start = std::chrono::steady_clock::now();
    s.world.step(0.1);
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
    const Vec2 p = s.world.position(s.disk.body), v = s.world.velocity(s.disk.body);
    ASSERT_TRUE(rattle::isFinite(p) && rattle::isFinite(v)) << "step " << step;
    ASSERT_TRUE(rattle::isFinite(s.world.position(s.wall))) << "step " << step;
  }
  std::printf("[ kinematic squeeze, default budget ] after 2.5 s: wall at x = %.9f, disk speed %.4g, budget %s\n",
              s.world.position(s.wall).x, rattle::length(s.world.velocity(s.disk.body)),
              s.world.stats().eventBudgetReached ? "reached" : "not reached");
}

// Modes: Hybrid, Predictive, Discrete.
INSTANTIATE_TEST_SUITE_P(, HardCaseSqueezeAnyMode,
                         ::testing::Values(StepMode::Hybrid, StepMode::Predictive, StepMode::Discrete),
                         ModeParamName());

}  // namespace
