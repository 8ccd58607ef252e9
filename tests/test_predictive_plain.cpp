// The predictive mode's plain-disk path (plain_collision.h): in a world of plain disks (one circle on the
// body's centre, the default filter) with no gravity, no sensors and nobody asleep, disk-disk collisions
// are resolved on the engine's compact copies and the BodySlots catch up later. Checked against the
// general path, which the same scene takes once a far-away sensor (which touches nothing) is added:
// the same collisions, bit for bit, with restitutions below 1, the TC model, walls and a kinematic
// paddle in play; and momentum and energy conserved by a free cloud of disks.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "collision/plain_disk_impact.h"
#include "rattle/rattle.h"
#include "rattle/time_of_impact.h"
#include "world_test_support.h"

namespace {

using namespace rattle_test;
using rattle::ContactEvent;
using rattle::StepMode;
using rattle::WorldDef;

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool sameBits(Vec2 a, Vec2 b) { return sameBits(a.x, b.x) && sameBits(a.y, b.y); }

// A static body far from everything, holding a sensor circle: the world is no longer plain, and nothing
// else changes (sensors are not in the predictive grid; they only watch).
void addFarSensor(World& world) {
  const BodyId far = world.createBody(bodyDef(BodyType::Static, {1e4, 1e4}, {}));
  FixtureDef fd;
  fd.geometry = rattle::Circle{{0, 0}, 1.0};
  fd.sensor = true;
  world.createFixture(far, fd);
}

struct Twin {
  World world;
  std::vector<Disk> disks;
  explicit Twin(const WorldDef& d) : world(d) {}
};

void expectBitIdentical(const Twin& plain, const Twin& general, int step) {
  const auto ep = plain.world.contactEvents(), eg = general.world.contactEvents();
  ASSERT_EQ(ep.size(), eg.size()) << "step " << step;
  for (size_t k = 0; k < ep.size(); ++k) {
    const ContactEvent& a = ep[k];
    const ContactEvent& b = eg[k];
    ASSERT_TRUE(a.fixtureA == b.fixtureA && a.fixtureB == b.fixtureB && a.bodyA == b.bodyA && a.bodyB == b.bodyB)
        << "step " << step << " event " << k;
    ASSERT_TRUE(sameBits(a.time, b.time) && sameBits(a.point, b.point) && sameBits(a.normal, b.normal) &&
                sameBits(a.impulse, b.impulse))
        << "step " << step << " event " << k << ": time " << a.time << " vs " << b.time;
  }
  for (size_t i = 0; i < plain.disks.size(); ++i) {
    ASSERT_TRUE(sameBits(plain.world.position(plain.disks[i].body), general.world.position(general.disks[i].body)) &&
                sameBits(plain.world.velocity(plain.disks[i].body), general.world.velocity(general.disks[i].body)))
        << "step " << step << " disk " << i;
  }
  EXPECT_EQ(plain.world.stats().eventsProcessed, general.world.stats().eventsProcessed) << "step " << step;
  EXPECT_EQ(plain.world.stats().staleEvents, general.world.stats().staleEvents) << "step " << step;
}

TEST(PredictivePlain, InelasticGasInABoxSameBitsAsGeneralPath) {
  // Radii, densities and restitutions differ from disk to disk; the TC model turns some collisions
  // elastic. Steps of several lengths (the step's end writes the copies back).
  auto options = gasDiskOptions(600, 40);
  options.minRestitution = 0.6;
  options.maxRestitution = 1.0;
  const auto specs = randomDisks(options);
  WorldDef def;
  def.mode = StepMode::Predictive;
  def.collapseTime = 0.02;
  Twin plain(def), general(def);
  std::vector<DiskSpec> roomy;  // room for a kinematic paddle in the middle
  for (const DiskSpec& d : specs) {
    if (rattle::length(d.position - Vec2{20, 20}) > 3.2) roomy.push_back(d);
  }
  for (Twin* t : {&plain, &general}) {
    makeClosedBox(t->world, 0, 0, 40, 40, 0.9);
    t->disks = addDisks(t->world, roomy);
    // A kinematic paddle: its contacts take the general path, and it moves on at the step's end.
    const BodyId paddle = t->world.createBody(bodyDef(BodyType::Kinematic, {20, 20}, {0.3, -0.2}));
    FixtureDef fd;
    fd.geometry = rattle::Circle{{0, 0}, 2.0};
    t->world.createFixture(paddle, fd);
  }
  addFarSensor(general.world);
  size_t compared = 0;
  const double steps[] = {0.05, 0.3, 1.0 / 60, 0.2};
  for (int k = 0; k < 60; ++k) {
    const double dt = steps[k % 4];
    plain.world.step(dt);
    general.world.step(dt);
    expectBitIdentical(plain, general, k);
    if (::testing::Test::HasFatalFailure()) return;
    compared += plain.world.contactEvents().size();
    if (k == 20) {
      // A change between steps: one disk pushed, one fixture made less bouncy.
      for (Twin* t : {&plain, &general}) {
        t->world.setVelocity(t->disks[7].body, {2.0, -1.0});
        t->world.setRestitution(t->disks[11].fixture, 0.1);
      }
    }
  }
  EXPECT_GT(compared, 3000u);
}

TEST(PredictivePlain, FreeCloudConservesMomentumAndEnergy) {
  // No walls: only disk-disk collisions, which conserve momentum exactly in real arithmetic and energy
  // too with restitution 1. A dense cloud with inward velocities keeps colliding while it spreads.
  auto options = gasDiskOptions(2000, 70);
  const auto specs0 = randomDisks(options);
  std::vector<DiskSpec> specs = specs0;
  for (DiskSpec& d : specs) d.velocity = d.velocity + (Vec2{35, 35} - d.position) * 0.05;
  WorldDef def;
  def.mode = StepMode::Predictive;
  Twin plain(def), general(def);
  for (Twin* t : {&plain, &general}) t->disks = addDisks(t->world, specs);
  addFarSensor(general.world);
  const long double e0 = kineticEnergy(plain.world, plain.disks);
  const LongVec2 p0 = momentum(plain.world, plain.disks);
  const long double scale = momentumScale(plain.world, plain.disks);
  long long collisions = 0;
  for (int k = 0; k < 400 && collisions < 100000; ++k) {
    plain.world.step(0.1);
    general.world.step(0.1);
    collisions += static_cast<long long>(plain.world.contactEvents().size());
    expectBitIdentical(plain, general, k);
    if (::testing::Test::HasFatalFailure()) return;
  }
  EXPECT_GT(collisions, 20000);
  const LongVec2 p1 = momentum(plain.world, plain.disks);
  EXPECT_LE(std::fabs(static_cast<double>((p1.x - p0.x) / scale)), 1e-12);
  EXPECT_LE(std::fabs(static_cast<double>((p1.y - p0.y) / scale)), 1e-12);
  EXPECT_LE(std::fabs(static_cast<double>((kineticEnergy(plain.world, plain.disks) - e0) / e0)), 1e-12);
  EXPECT_LE(maxRelativeOverlap(plain.world, plain.disks), 1e-9);
}

TEST(PredictivePlain, CrowdedCellsSameBitsAsGeneralPath) {
  // Cells are as wide as the largest disk: one big disk among many small ones puts hundreds of bodies
  // in a cell's neighbourhood, more than the plain path's neighbour buffer holds (it then takes them
  // from a vector, in another order), and many cells hold several bodies (their lists are walked).
  auto options = gasDiskOptions(700, 30);
  options.minRadius = 0.1;
  options.maxRadius = 0.2;
  options.minSpeed = 1.0;
  options.maxSpeed = 2.0;
  options.seed = 5;
  std::vector<DiskSpec> specs;
  specs.push_back(DiskSpec{{15, 15}, {0.4, 0.3}, 3.0, 1.0, 1.0});
  for (const DiskSpec& d : randomDisks(options)) {
    if (rattle::length(d.position - Vec2{15, 15}) > 3.5) specs.push_back(d);
  }
  WorldDef def;
  def.mode = StepMode::Predictive;
  Twin plain(def), general(def);
  for (Twin* t : {&plain, &general}) {
    makeClosedBox(t->world, 0, 0, 30, 30, 1.0);
    t->disks = addDisks(t->world, specs);
  }
  addFarSensor(general.world);
  size_t compared = 0;
  for (int k = 0; k < 80; ++k) {
    plain.world.step(0.1);
    general.world.step(0.1);
    expectBitIdentical(plain, general, k);
    if (::testing::Test::HasFatalFailure()) return;
    compared += plain.world.contactEvents().size();
  }
  EXPECT_GT(compared, 2000u);
}

TEST(PredictivePlain, SplitTimeOfImpactSameBitsAsCircleCircle) {
  // plain_disk_impact.h against timeOfImpactCircleCircle, on pairs that meet, touch, overlap by
  // round-off, graze and miss, with and without the LastContact guard and a tight time limit.
  std::mt19937_64 rng(7);
  auto uniform = [&](double lo, double hi) { return lo + (hi - lo) * (static_cast<double>(rng() >> 11) * 0x1p-53); };
  int found = 0, touching = 0;
  for (int k = 0; k < 200000; ++k) {
    const double ra = uniform(0.1, 1.0), rb = uniform(0.1, 1.0);
    Vec2 centre{uniform(-3, 3), uniform(-3, 3)};
    if (k % 5 == 0) {
      // On the contact circle, up to a few ulps in or out.
      const double angle = uniform(0, 6.283185307179586);
      centre = Vec2{std::cos(angle), std::sin(angle)} * (ra + rb);
    }
    centre = centre + Vec2{uniform(-1e-15, 1e-15), 0.0};
    const Vec2 v{uniform(-2, 2), uniform(-2, 2)};
    const double maxTime = k % 3 == 0 ? uniform(0, 0.5) : 4.0;
    const bool guard = k % 7 == 0;
    const auto expected = rattle::timeOfImpactCircleCircle(rattle::Circle{centre, ra}, rattle::Motion{v},
                                                           rattle::Circle{Vec2{}, rb}, maxTime, guard ? 0 : -1);
    const Vec2 r = centre - Vec2{};
    const double reach = ra + rb;
    double t = -1;
    const bool hit = rattle::detail::plainTimeToReach(r, dot(r, r) - reach * reach, dot(r, v), v, reach, maxTime, guard, t);
    ASSERT_EQ(hit, expected.has_value()) << "pair " << k;
    if (!hit) continue;
    ++found;
    if (t == 0) ++touching;
    Vec2 point, normal;
    rattle::detail::plainContact(r, v, rb, t, point, normal);
    ASSERT_TRUE(sameBits(t, expected->time) && sameBits(point, expected->point) && sameBits(normal, expected->normal) &&
                expected->feature == 0)
        << "pair " << k;
  }
  EXPECT_GT(found, 20000);
  EXPECT_GT(touching, 100);
}

}  // namespace
