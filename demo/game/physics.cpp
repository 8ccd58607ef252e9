// The engine boundary (see physics.h). All rattle::World calls of the game are in this file.
#include "game/physics.h"

#include <time.h>

#include <chrono>
#include <cmath>
#include <variant>

#include "game/game.h"  // GameError

namespace rts {
namespace {

// Collision categories. A fixture pair is tested only when each one's category is in the other's mask.
enum : uint32_t {
  kWall = 1u << 0,  // walls, buildings, gates: block units, projectiles and sight rays
  kUnit0 = 1u << 1,
  kUnit1 = 1u << 2,
  kShot0 = 1u << 3,  // fired by team 0
  kShot1 = 1u << 4,
  kSight0 = 1u << 5,  // team 0's sight sensors
  kSight1 = 1u << 6,
  kDoorway = 1u << 7,
  // 1u << 8 was rooms' sensors: rooms are now counted by the game from unit centres (doorways.cpp).
  kRay = 1u << 9,  // the category of line-of-sight queries
  kGate = 1u << 10,  // gates: like walls, but they move
};

constexpr double kCollapseTime = 0.003;  // seconds

double threadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

uint32_t unitBit(int team) { return team == 0 ? kUnit0 : kUnit1; }
uint32_t shotBit(int team) { return team == 0 ? kShot0 : kShot1; }
uint32_t sightBit(int team) { return team == 0 ? kSight0 : kSight1; }

rattle::Filter filter(uint32_t category, uint32_t mask) {
  rattle::Filter f;
  f.categoryBits = category;
  f.maskBits = mask;
  return f;
}

rattle::FixtureDef fixture(rattle::Geometry g, rattle::Filter f, bool sensor = false, double density = 1) {
  rattle::FixtureDef d;
  d.geometry = std::move(g);
  d.filter = f;
  d.sensor = sensor;
  d.density = density;
  d.restitution = 0;
  return d;
}

rattle::BodyDef bodyAt(rattle::BodyType type, Vec2 position, Vec2 velocity = {}) {
  rattle::BodyDef d;
  d.type = type;
  d.position = position;
  d.velocity = velocity;
  return d;
}

// Queries for what blocks: walls and buildings, and (unless asked not to) gates.
rattle::QueryFilter wallQuery(bool gates = true) {
  rattle::QueryFilter q;
  q.categoryBits = kRay;
  q.maskBits = gates ? kWall | kGate : kWall;
  return q;
}

}  // namespace

Physics::Physics(const Map& map, rattle::StepMode mode) : world_([&] {
  rattle::WorldDef def;
  def.mode = mode;
  // Units have restitution 0 and are driven into one another every tick; such a crowd collides
  // infinitely often in finite time (inelastic collapse), and the step would spend its whole event
  // budget on it. The engine's guard makes a contact elastic for a body that collided less than this
  // long ago, which ends the cascade after a few events; a tenth of a tick is invisible in play.
  def.collapseTime = kCollapseTime;
  return def;
}()) {
  const uint32_t everything = 0xFFFFFFFFu;
  for (const MapWall& w : map.walls) {
    rattle::BodyId body = world_.createBody(bodyAt(rattle::BodyType::Static, w.origin));
    if (const auto* line = std::get_if<rattle::Polyline>(&w.shape); line && line->points.size() > 2) {
      // One fixture per segment, each with its own box: the arena's outer wall as one polyline has a box
      // round the whole map, and every moving unit would be tested against all of it every tick. Each
      // piece keeps its ends, so the corners still collide (from either piece: the second is then stale).
      for (size_t i = 0; i + 1 < line->points.size(); ++i) {
        world_.createFixture(body, fixture(rattle::Polyline{{line->points[i], line->points[i + 1]}}, filter(kWall, everything)));
      }
    } else {
      world_.createFixture(body, fixture(w.shape, filter(kWall, everything)));
    }
    setTag(body, Tag::Wall, uint32_t(w.objectId));
  }
  for (size_t i = 0; i < map.doorways.size(); ++i) {
    const MapDoorway& d = map.doorways[i];
    rattle::BodyId body = world_.createBody(bodyAt(rattle::BodyType::Static, d.a));
    world_.createFixture(body, fixture(rattle::Segment{{0, 0}, d.b - d.a}, filter(kDoorway, kUnit0 | kUnit1), true));
    setTag(body, Tag::Doorway, uint32_t(i));
  }
  for (size_t i = 0; i < map.gates.size(); ++i) {
    rattle::BodyId body = world_.createBody(bodyAt(rattle::BodyType::Kinematic, map.gates[i].origin));
    world_.createFixture(body, fixture(rattle::Polygon{map.gates[i].polygon}, filter(kGate, everything)));
    setTag(body, Tag::Gate, uint32_t(i));
    gates_.push_back(body);
    gateShapes_.push_back(map.gates[i]);
  }
}

void Physics::setTag(rattle::BodyId body, Tag tag, uint32_t id) {
  if (tags_.size() <= body.index) tags_.resize(size_t(body.index) + 1);
  tags_[body.index] = {body.generation, tag, id};
}

const Physics::SlotTag* Physics::tagOf(rattle::BodyId body) const {
  if (body.index >= tags_.size()) return nullptr;
  const SlotTag& t = tags_[body.index];
  return t.generation == body.generation ? &t : nullptr;
}

rattle::BodyId Physics::addUnit(uint32_t id, int team, Vec2 position, const UnitType& type) {
  const int other = 1 - team;
  rattle::BodyId body = world_.createBody(bodyAt(rattle::BodyType::Dynamic, position));
  // The body: blocked by walls and every unit, hit by the other team's shots, seen by the other team's
  // sight sensors, noticed by doorways and unit queries.
  world_.createFixture(body, fixture(rattle::Circle{{0, 0}, type.radius},
                                     filter(unitBit(team), kWall | kGate | kUnit0 | kUnit1 | shotBit(other) |
                                                               sightBit(other) | kDoorway | kRay),
                                     false, type.density));
  // The concentric sight sensor: told only about the other team's bodies.
  world_.createFixture(body, fixture(rattle::Circle{{0, 0}, type.sight}, filter(sightBit(team), unitBit(other)), true));
  setTag(body, Tag::Unit, id);
  return body;
}

rattle::BodyId Physics::addShot(uint32_t id, int team, Vec2 position, Vec2 velocity, double radius) {
  rattle::BodyId body = world_.createBody(bodyAt(rattle::BodyType::Dynamic, position, velocity));
  // Light, so a hit barely pushes the unit; it meets only walls and the other team's units.
  world_.createFixture(body, fixture(rattle::Circle{{0, 0}, radius}, filter(shotBit(team), kWall | kGate | unitBit(1 - team)),
                                     false, 0.2));
  setTag(body, Tag::Shot, id);
  return body;
}

void Physics::remove(rattle::BodyId body) { world_.destroyBody(body); }

void Physics::adopt(rattle::World world, const std::vector<std::pair<rattle::BodyId, uint32_t>>& units,
                    const std::vector<std::pair<rattle::BodyId, uint32_t>>& shots, double place, double speed) {
  const rattle::WorldDef& mine = world_.definition();
  const rattle::WorldDef& theirs = world.definition();
  if (theirs.mode != mine.mode || theirs.collapseTime != mine.collapseTime || !(theirs.gravity == mine.gravity) ||
      theirs.restingSpeed != mine.restingSpeed || theirs.maxEventsPerStep != mine.maxEventsPerStep) {
    throw GameError("world: its definition (mode, gravity, collapse time, budget) is not this game's");
  }
  // The map's bodies: made first, by every game of this map, so their ids are the same everywhere.
  for (uint32_t i = 0; i < tags_.size(); ++i) {
    const SlotTag& t = tags_[i];
    if (t.tag != Tag::Wall && t.tag != Tag::Doorway && t.tag != Tag::Gate) continue;
    const rattle::BodyId body{i, t.generation};
    if (!world_.isValid(body)) continue;
    if (!world.isValid(body) || world.type(body) != world_.type(body) ||
        world.fixtures(body).size() != world_.fixtures(body).size()) {
      throw GameError("world: body " + std::to_string(i) + " is not the map's " +
                      (t.tag == Tag::Wall   ? "wall"
                       : t.tag == Tag::Gate ? "gate"
                                            : "doorway") +
                      " it is here");
    }
  }
  std::vector<uint8_t> listed;  // by body index
  auto check = [&](const std::pair<rattle::BodyId, uint32_t>& b, const char* what) {
    const rattle::BodyId body = b.first;
    if (!world.isValid(body) || world.type(body) != rattle::BodyType::Dynamic) {
      throw GameError(std::string(what) + " " + std::to_string(b.second) + ": its body {" + std::to_string(body.index) +
                      ", " + std::to_string(body.generation) + "} is not a live dynamic body of the world");
    }
    if (body.index < tags_.size()) {
      const SlotTag& t = tags_[body.index];
      if ((t.tag == Tag::Wall || t.tag == Tag::Doorway || t.tag == Tag::Gate) && t.generation == body.generation) {
        throw GameError(std::string(what) + " " + std::to_string(b.second) + ": its body is one of the map's");
      }
    }
    const Vec2 p = world.position(body), v = world.velocity(body);
    if (!(std::fabs(p.x) <= place && std::fabs(p.y) <= place && std::fabs(v.x) <= speed && std::fabs(v.y) <= speed)) {
      throw GameError(std::string(what) + " " + std::to_string(b.second) +
                      ": its body is too far off the map or too fast");
    }
    if (body.index >= listed.size()) listed.resize(size_t(body.index) + 1, 0);
    if (listed[body.index]) {
      throw GameError(std::string(what) + " " + std::to_string(b.second) + ": its body is another unit's or shot's");
    }
    listed[body.index] = 1;
  };
  for (const auto& u : units) check(u, "unit");
  for (const auto& s : shots) check(s, "shot");
  // Checked: nothing below throws but for memory.
  world_ = std::move(world);
  for (SlotTag& t : tags_) {
    if (t.tag == Tag::Unit || t.tag == Tag::Shot) t = SlotTag{};
  }
  for (const auto& [body, id] : units) setTag(body, Tag::Unit, id);
  for (const auto& [body, id] : shots) setTag(body, Tag::Shot, id);
}

void Physics::placeGate(size_t gate, Vec2 position) {
  world_.setVelocity(gates_[gate], {0, 0});
  world_.setPosition(gates_[gate], position);
}

const StepEvents& Physics::step(double dt) {
  // The CPU clock (a system call) outside the wall clock (a cheap read), so the wall-clock time
  // rattle-demo reports is not made longer by the second measure.
  const double cpuStart = threadCpuSeconds();
  const auto start = std::chrono::steady_clock::now();
  world_.step(dt);
  lastStepSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  lastStepCpuSeconds_ = threadCpuSeconds() - cpuStart;

  events_.shotContacts.clear();
  events_.unitContacts.clear();
  events_.sight.clear();
  events_.doorways.clear();
  for (const rattle::ContactEvent& c : world_.contactEvents()) {
    const SlotTag* a = tagOf(c.bodyA);
    const SlotTag* b = tagOf(c.bodyB);
    if (!a || !b) continue;
    if (a->tag == Tag::Unit && b->tag == Tag::Unit) {
      events_.unitContacts.push_back({a->id, false, b->id, c.normal});
      events_.unitContacts.push_back({b->id, false, a->id, -c.normal});
      continue;
    }
    if (a->tag == Tag::Unit && (b->tag == Tag::Wall || b->tag == Tag::Gate)) {
      events_.unitContacts.push_back({a->id, true, 0, c.normal});
      continue;
    }
    if (b->tag == Tag::Unit && (a->tag == Tag::Wall || a->tag == Tag::Gate)) {
      events_.unitContacts.push_back({b->id, true, 0, -c.normal});
      continue;
    }
    if (b->tag == Tag::Shot) std::swap(a, b);
    if (a->tag != Tag::Shot) continue;  // a unit against a wall: the engine already did the work
    events_.shotContacts.push_back({a->id, b->tag, b->id, c.point});
  }
  for (const rattle::SensorEvent& e : world_.sensorEvents()) {
    const SlotTag* sensor = tagOf(e.sensorBody);
    const SlotTag* visitor = tagOf(e.visitorBody);
    if (!sensor || !visitor || visitor->tag != Tag::Unit) continue;  // gone since; the game forgot it already
    if (sensor->tag == Tag::Unit) {
      events_.sight.push_back({sensor->id, visitor->id, e.begin});
    } else if (sensor->tag == Tag::Doorway) {
      events_.doorways.push_back({sensor->id, visitor->id, e.begin});
    }
  }
  return events_;
}

bool Physics::clearLine(Vec2 a, Vec2 b) const { return !world_.rayCastFirst(a, b - a, wallQuery()).has_value(); }

double Physics::wallFraction(Vec2 origin, Vec2 translation) const {
  auto hit = world_.rayCastFirst(origin, translation, wallQuery());
  return hit ? hit->fraction : 1.0;
}

bool Physics::freeOfWalls(Vec2 center, double radius) const {
  return world_.overlapCircle(center, radius, wallQuery()).empty();
}

bool Physics::freeOfStaticWalls(Vec2 center, double radius) const {
  return world_.overlapCircle(center, radius, wallQuery(false)).empty();
}

bool Physics::gateBlocks(size_t gate, bool open, Vec2 p, double radius) const {
  const MapGate& g = gateShapes_[gate];
  const Vec2 at = g.origin + (open ? g.openOffset : Vec2{0, 0});
  return rattle::distanceTo(rattle::Polygon{g.polygon}, p - at) <= radius;
}

bool Physics::anyUnitIn(const rattle::Box& box) const {
  rattle::QueryFilter q;
  q.categoryBits = kRay;
  q.maskBits = kUnit0 | kUnit1;
  return !world_.overlapBox(box, q).empty();
}

}  // namespace rts
