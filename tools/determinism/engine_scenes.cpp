// gas, pile, bullets, sensors and crowd are the benchmark's scenes (scenes/scenes.h, one seed, no libm in
// their placement), with the default WorldDef but for the mode and gravity; the crowd is steered naively
// at every step of 1/30 s, as the benchmark steers it, so that its jams at the doorways are in the trace.
// kinematic is written here: two kinematic pushers, one carrying a sensor, that turn around every 40
// steps among bouncing disks.
#include "engine_scenes.h"

#include <rattle/rattle.h>
#include <scenes.h>

#include <bit>
#include <stdexcept>

namespace rattle_trace {
namespace {

uint64_t mix(uint64_t h, uint64_t v) {
  h ^= v + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
  return h * 0xFF51AFD7ED558CCDull;
}
uint64_t bits(double d) { return std::bit_cast<uint64_t>(d); }
uint64_t ids(uint32_t index, uint32_t generation) { return uint64_t(index) << 32 | generation; }

void turnPushers(EngineScene& s, int step) {
  if (step == 0 || step % 40 != 0) return;
  for (rattle::BodyId b : s.movers) s.world.setVelocity(b, -s.world.velocity(b));
}

// Every disk's velocity toward its doorway or the goal (rattle_bench::steerCrowd: divisions and a square
// root, both correctly rounded).
void steerCrowd(EngineScene& s, int) {
  std::vector<rattle::Vec2> positions, velocities;
  for (rattle::BodyId b : s.movers) positions.push_back(s.world.position(b));
  rattle_bench::steerCrowd(s.scene, positions, velocities);
  for (size_t i = 0; i < s.movers.size(); ++i) s.world.setVelocity(s.movers[i], velocities[i]);
}

// A 30 x 20 box, disks of restitution 0.9 on a lattice with seeded speeds, a kinematic polygon sweeping
// left and right through them, and a kinematic circle with a larger sensor ring moving diagonally.
void addKinematicScene(EngineScene& s, int disks) {
  rattle_bench::SceneParams p;
  p.name = "gas";
  p.n = disks;
  p.seed = 3;
  p.packing = 0.2;
  p.speed = 2;
  const rattle_bench::Scene gas = rattle_bench::buildScene(p);
  const double L = gas.bounds.max.x;
  rattle_bench::addToWorld(s.world, gas);

  rattle::BodyDef paddle;
  paddle.type = rattle::BodyType::Kinematic;
  paddle.position = {0.25 * L, 0.5 * L};
  paddle.velocity = {3, 0};
  const rattle::BodyId a = s.world.createBody(paddle);
  rattle::FixtureDef bar;
  bar.geometry = rattle::Polygon{{{-0.3, -2}, {0.3, -2}, {0.3, 2}, {-0.3, 2}}};
  bar.restitution = 0.9;
  s.world.createFixture(a, bar);

  rattle::BodyDef rover;
  rover.type = rattle::BodyType::Kinematic;
  rover.position = {0.6 * L, 0.3 * L};
  rover.velocity = {-1.5, 2};
  const rattle::BodyId b = s.world.createBody(rover);
  rattle::FixtureDef hull;
  hull.geometry = rattle::Circle{{0, 0}, 1};
  hull.restitution = 0.9;
  s.world.createFixture(b, hull);
  rattle::FixtureDef ring;
  ring.geometry = rattle::Circle{{0, 0}, 3};
  ring.sensor = true;
  s.world.createFixture(b, ring);

  s.movers = {a, b};
  s.beforeStep = turnPushers;
}

}  // namespace

const std::vector<std::string>& engineSceneNames() {
  static const std::vector<std::string> names = {"gas", "pile", "bullets", "sensors", "crowd", "kinematic"};
  return names;
}

EngineScene buildEngineScene(const std::string& name, rattle::StepMode mode, int disks) {
  rattle::WorldDef def;
  def.mode = mode;
  if (name == "kinematic") {
    EngineScene s{name, rattle::World(def)};
    addKinematicScene(s, disks);
    return s;
  }
  rattle_bench::SceneParams p;
  p.name = name;
  p.n = name == "bullets" || name == "sensors" ? disks / 2 : disks;
  p.seed = 1;
  const rattle_bench::Scene scene = rattle_bench::buildScene(p);  // throws SceneError for an unknown name
  def.gravity = scene.gravity;
  EngineScene s{name, rattle::World(def)};
  const rattle_bench::RattleScene added = rattle_bench::addToWorld(s.world, scene);
  if (scene.steering.enabled) {
    s.dt = 1.0 / 30.0;
    s.movers = added.disks;
    s.beforeStep = steerCrowd;
  }
  s.scene = scene;
  return s;
}

uint64_t stepHash(const rattle::World& world) {
  uint64_t h = world.stateHash();
  for (const rattle::ContactEvent& e : world.contactEvents()) {
    h = mix(h, bits(e.time));
    h = mix(h, ids(e.fixtureA.index, e.fixtureA.generation) ^ ids(e.fixtureB.index, e.fixtureB.generation) << 1);
    h = mix(h, bits(e.point.x) ^ bits(e.point.y) << 1);
    h = mix(h, bits(e.normal.x) ^ bits(e.normal.y) << 1);
    h = mix(h, bits(e.impulse));
  }
  for (const rattle::SensorEvent& e : world.sensorEvents()) {
    h = mix(h, bits(e.time));
    h = mix(h, ids(e.sensor.index, e.sensor.generation) ^ ids(e.visitor.index, e.visitor.generation) << 1);
    h = mix(h, uint64_t(e.begin));
  }
  return h;
}

}  // namespace rattle_trace
