// The README's promise on segment ends, held in every path that asks it (issue 25): a bare Segment's
// ends do not collide (events in every mode, the discrete push-apart), a Polyline's do; queries and
// sensors treat every geometry as a closed set, segment ends included.
//
// The scene: a wall from (0, 0) to (0, 2); a disk of radius 0.5 moving along y = 2.3 at speed 1 from
// x = -3. Its centre passes 0.3 from the wall's upper end, inside its radius, and never faces the wall
// (its centre stays above the wall's top). With ends that collide it meets the end when its centre is
// 0.5 from it: x = -sqrt(0.5^2 - 0.3^2) = -0.4, at t = 2.6 s, and leaves the end's reach at x = 0.4,
// t = 3.4 s.
#include <gtest/gtest.h>

#include <rattle/rattle.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

using namespace rattle;

namespace {

constexpr StepMode kModes[] = {StepMode::Discrete, StepMode::Hybrid, StepMode::Predictive};
constexpr double kRadius = 0.5;
constexpr double kDt = 1.0 / 60;

std::string nameOf(StepMode m) {
  return m == StepMode::Discrete ? "discrete" : m == StepMode::Hybrid ? "hybrid" : "predictive";
}

struct Scene {
  World world;
  FixtureId wall;
  BodyId disk;
};

Scene sceneWith(StepMode mode, const Geometry& wall, bool sensor) {
  WorldDef def;
  def.mode = mode;
  Scene s{World(def), {}, {}};
  const BodyId ground = s.world.createBody({.type = BodyType::Static});
  s.wall = s.world.createFixture(ground, {.geometry = wall, .sensor = sensor});
  s.disk = s.world.createBody({.type = BodyType::Dynamic, .position = {-3, 2.3}, .velocity = {1, 0}});
  s.world.createFixture(s.disk, {.geometry = Circle{{0, 0}, kRadius}, .restitution = 1});
  return s;
}

TEST(SegmentEnds, ADiskPassingABareSegmentsEndIsNotStoppedInAnyMode) {
  for (StepMode mode : kModes) {
    SCOPED_TRACE(nameOf(mode));
    Scene s = sceneWith(mode, Segment{{0, 0}, {0, 2}}, false);
    int contacts = 0;
    for (int i = 0; i < 360; ++i) {
      s.world.step(kDt);
      contacts += static_cast<int>(s.world.contactEvents().size());
    }
    EXPECT_EQ(contacts, 0);
    // Six seconds at speed 1, untouched.
    EXPECT_NEAR(s.world.position(s.disk).x, 3.0, 1e-9);
    EXPECT_EQ(s.world.velocity(s.disk).x, 1.0);
    EXPECT_EQ(s.world.position(s.disk).y, 2.3);
  }
}

TEST(SegmentEnds, APolylinesEndStopsTheSameDiskAtItsAnalyticTime) {
  // The exact modes meet the end at t = 2.6 and send the disk back along the line from the end's point
  // through its centre; the discrete mode pushes it out of the end within the step that overlaps.
  for (StepMode mode : kModes) {
    SCOPED_TRACE(nameOf(mode));
    Scene s = sceneWith(mode, Polyline{{{0, 0}, {0, 2}}}, false);
    std::vector<double> times;
    for (int i = 0; i < 360; ++i) {
      const double start = s.world.time();
      s.world.step(kDt);
      for (const ContactEvent& e : s.world.contactEvents()) times.push_back(start + e.time);
    }
    ASSERT_FALSE(times.empty());
    if (mode == StepMode::Discrete) {
      EXPECT_NEAR(times.front(), 2.6, kDt + 1e-9);
    } else {
      EXPECT_NEAR(times.front(), 2.6, 1e-9);
    }
    // Turned back: after six seconds it is left of the wall again.
    EXPECT_LT(s.world.position(s.disk).x, 0.0);
  }
}

TEST(SegmentEnds, QueriesCountABareSegmentsEnd) {
  for (StepMode mode : kModes) {
    SCOPED_TRACE(nameOf(mode));
    Scene s = sceneWith(mode, Segment{{0, 0}, {0, 2}}, false);
    // A circle around a point 0.4 above the end, radius 0.5: it holds the end and nothing of the face.
    const std::vector<FixtureId> found = s.world.overlapCircle({0, 2.4}, 0.5);
    EXPECT_NE(std::find(found.begin(), found.end(), s.wall), found.end());
    // 0.6 above the end, it holds nothing of the segment.
    const std::vector<FixtureId> beyond = s.world.overlapCircle({0, 2.6}, 0.5);
    EXPECT_EQ(std::find(beyond.begin(), beyond.end(), s.wall), beyond.end());
    // The end itself is a point of the segment.
    const std::vector<FixtureId> atEnd = s.world.overlapPoint({0, 2});
    EXPECT_NE(std::find(atEnd.begin(), atEnd.end(), s.wall), atEnd.end());
    // A ray crossing the wall's line exactly at the end hits it there, halfway.
    const auto hit = s.world.rayCastFirst({-1, 3}, {2, -2});
    ASSERT_TRUE(hit.has_value());
    EXPECT_EQ(hit->fixture, s.wall);
    EXPECT_NEAR(hit->fraction, 0.5, 1e-12);
  }
}

TEST(SegmentEnds, ASensorSegmentSeesTheDiskPassItsEnd) {
  // The same pass over a sensor Segment: the disk overlaps the sensor (closed, its end included) from
  // t = 2.6 to t = 3.4, and nothing stops it.
  for (StepMode mode : kModes) {
    SCOPED_TRACE(nameOf(mode));
    Scene s = sceneWith(mode, Segment{{0, 0}, {0, 2}}, true);
    std::vector<std::pair<double, bool>> events;
    for (int i = 0; i < 360; ++i) {
      const double start = s.world.time();
      s.world.step(kDt);
      for (const SensorEvent& e : s.world.sensorEvents()) events.push_back({start + e.time, e.begin});
    }
    ASSERT_EQ(events.size(), 2u);
    EXPECT_TRUE(events[0].second);
    EXPECT_FALSE(events[1].second);
    // The discrete mode compares overlaps at the ends of steps: within a step of the exact instants.
    const double tolerance = mode == StepMode::Discrete ? kDt + 1e-9 : 1e-9;
    EXPECT_NEAR(events[0].first, 2.6, tolerance);
    EXPECT_NEAR(events[1].first, 3.4, tolerance);
    EXPECT_NEAR(s.world.position(s.disk).x, 3.0, 1e-9);
  }
}

}  // namespace
