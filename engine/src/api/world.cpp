// The world's bookkeeping: creating, validating, destroying and reading bodies and fixtures.
// Every mutating call validates everything first and changes nothing when it throws.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

#include "common/format.h"
#include "api/value_ranges.h"
#include "common/out_of_memory.h"
#include "contact/resting.h"
#include "contact/separation.h"
#include "contact/squeeze.h"
#include "sensors/sensors.h"
#include "world/step_undo.h"
#include "world/stepper.h"
#include "world/world_impl.h"

namespace rattle {

using detail::BodySlot;
using detail::FixtureSlot;
using detail::inRange;
using detail::require;
using detail::str;

namespace {

void checkFinite(Vec2 v, const char* field) {
  require(isFinite(v), [&] { return std::string(field) + " = " + str(v) + ": must be finite"; });
}

// The speed must be finite and so must its square, which every time of impact works with: below
// World::kMaxSpeed (1.3e154, a little under 2^512, where the square overflows). Gravity likewise.
void checkVelocity(Vec2 v, const char* field) {
  checkFinite(v, field);
  require(length(v) < World::kMaxSpeed, [&] {
    return std::string(field) + " = " + str(v) + ": its length must be below 1.3e154 (World::kMaxSpeed)";
  });
}

void checkRestitution(double e, const char* field) {
  require(std::isfinite(e) && e >= 0 && e <= 1,
          [&] { return std::string(field) + " = " + str(e) + ": must be in [0, 1]"; });
}

// The centre of a circle-like geometry; dynamic bodies hold only those.
std::optional<Vec2> centreOf(const Geometry& g) {
  if (const auto* c = std::get_if<Circle>(&g)) return c->center;
  if (const auto* p = std::get_if<Point>(&g)) return p->position;
  return std::nullopt;
}

uint32_t nextGeneration(uint32_t g) { return g == UINT32_MAX ? 1 : g + 1; }

}  // namespace

// ---- World -------------------------------------------------------------------------------------------

World::World(const WorldDef& def) : impl_(std::make_unique<Impl>()) {
  require(def.mode == StepMode::Hybrid || def.mode == StepMode::Discrete || def.mode == StepMode::Predictive, [&] {
    return std::string("WorldDef.mode = " + std::to_string(static_cast<int>(def.mode)) + ": not a StepMode");
  });
  require(def.maxEventsPerStep > 0, [&] {
    return std::string("WorldDef.maxEventsPerStep = " + std::to_string(def.maxEventsPerStep) + ": must be > 0");
  });
  checkVelocity(def.gravity, "WorldDef.gravity");
  require(std::isfinite(def.restingSpeed) && def.restingSpeed >= 0,
          [&] { return "WorldDef.restingSpeed = " + str(def.restingSpeed) + ": must be finite and >= 0"; });
  require(std::isfinite(def.collapseTime) && def.collapseTime >= 0,
          [&] { return "WorldDef.collapseTime = " + str(def.collapseTime) + ": must be finite and >= 0"; });
  impl().def = def;
  impl().stepper = def.mode == StepMode::Discrete     ? detail::makeDiscreteStepper(impl())
                   : def.mode == StepMode::Predictive ? detail::makePredictiveStepper(impl())
                                                      : detail::makeHybridStepper(impl());
}

World::~World() = default;
World::World(World&&) noexcept = default;
World& World::operator=(World&&) noexcept = default;

World::Impl& World::impl() const {
  if (!impl_) throw Error("World: used after it was moved from (a moved-from World holds nothing)");
  return *impl_;
}

const WorldDef& World::definition() const { return impl().def; }

namespace {

// The live slot an id names, or an Error that says why it names none ("BodyId", "body" for bodies).
template <class Slot, class Id>
Slot& lookUp(detail::LargeArray<Slot>& slots, Id id, const char* idName, const char* noun) {
  if (id.isNull()) throw Error(std::string(idName) + " is null");
  if (id.index >= slots.size() || !slots[id.index].alive || slots[id.index].generation != id.generation) {
    throw Error(std::string(idName) + " {index " + std::to_string(id.index) + ", generation " +
                std::to_string(id.generation) + "} is stale: that " + noun + " was destroyed");
  }
  return slots[id.index];
}

BodySlot& lookUp(detail::LargeArray<BodySlot>& bodies, BodyId id) { return lookUp(bodies, id, "BodyId", "body"); }

FixtureSlot& lookUp(detail::LargeArray<FixtureSlot>& fixtures, FixtureId id) {
  return lookUp(fixtures, id, "FixtureId", "fixture");
}

// A free or new slot made live: defaults, but the generation it had (destroying it moved that on).
template <class Slot>
Slot& renewed(Slot& slot) {
  const uint32_t generation = slot.generation;
  slot = Slot{};
  slot.generation = generation;
  slot.alive = true;
  return slot;
}

}  // namespace

BodyId World::createBody(const BodyDef& def) {
  return detail::unlessOutOfMemory("createBody", [&]() -> BodyId {
    require(def.type == BodyType::Static || def.type == BodyType::Dynamic || def.type == BodyType::Kinematic, [&] {
      return std::string("BodyDef.type = " + std::to_string(static_cast<int>(def.type)) + ": not a BodyType");
    });
    checkFinite(def.position, "BodyDef.position");
    require(inRange(def.position),
            [&] { return "BodyDef.position = " + str(def.position) + ": outside +-1e150 (World::kMaxCoordinate)"; });
    checkVelocity(def.velocity, "BodyDef.velocity");
    require(def.type != BodyType::Static || def.velocity == Vec2{},
            [&] { return std::string("BodyDef.velocity = " + str(def.velocity) + ": a static body cannot move"); });

    Impl& w = impl();
    if (w.freeBodies.empty()) {
      detail::roomForOneMore(w.bodies);
      detail::roomForOneMore(w.userData);
      detail::roomForOneMore(w.dependents);
      detail::roomForOneMore(w.diskShapes);
    }
    uint32_t index;
    if (!w.freeBodies.empty()) {
      index = w.freeBodies.back();
      w.freeBodies.pop_back();
    } else {
      index = static_cast<uint32_t>(w.bodies.size());
      w.bodies.emplace_back();
      w.userData.emplace_back();
      w.dependents.emplace_back();
      w.diskShapes.emplace_back();
    }
    BodySlot& b = renewed(w.bodies[index]);
    b.type = def.type;
    b.position = def.position;
    b.velocity = def.velocity;
    w.userData[index] = def.userData;
    w.dependents[index].clear();
    recomputeMass(w, b);
    ++w.liveBodies;
    w.changes.structureChanged = true;
    return BodyId{index, b.generation};
  });
}

namespace {

// The bodies that slide on a face of a fixture that is destroyed or moved (`going` says which) stop
// sliding: the next step finds their contacts again. A slide is motion along a face where it was, and
// kept, a disk on a floor moved away by setPosition went on sliding in the air; and a save made before
// the next step held a slide on a destroyed face, which World::load refuses (the step stopped the slide
// only at its start: fuzz/regressions/world_api/save-slide-on-a-destroyed-floor). Only a static body's
// faces are slid on (resting.cpp), so a shot's fixture costs no scan.
template <typename Going>
void stopSlidesOn(detail::WorldState& w, const BodySlot& owner, Going going) {
  if (owner.type == BodyType::Dynamic) return;
  for (BodySlot& b : w.bodies) {
    if (b.alive && b.sliding && going(b.support.fixture)) detail::stopSliding(w, b);
  }
}

}  // namespace

void World::destroyBody(BodyId id) {
  Impl& w = impl();
  BodySlot& b = lookUp(w.bodies, id);
  detail::unlessOutOfMemory("destroyBody", [&] {
    // What it held up falls, and its overlaps end: found first, with room for what follows.
    std::vector<uint32_t> woken;
    for (uint32_t d : w.dependents[id.index]) collectWake(w, d, woken);
    std::vector<uint64_t> ended;
    for (uint32_t f : b.fixtures)
      overlapsToEnd(
          w, f, [](uint32_t) { return false; }, ended);
    detail::roomFor(w.pendingSensorEvents, ended.size());
    detail::roomFor(w.freeFixtures, b.fixtures.size());
    detail::roomForOneMore(w.freeBodies);
    // Nothing below allocates.
    applyWake(w, woken, 0, 0.0);
    endOverlaps(w, ended);
  });
  w.dependents[id.index].clear();
  stopSlidesOn(w, b, [&](uint32_t f) { return w.fixtures[f].body == id.index; });
  for (uint32_t f : b.fixtures) {
    w.broadPhase.remove(f);
    FixtureSlot& fs = w.fixtures[f];
    if (fs.sensor) --w.liveSensors;
    fs.alive = false;
    fs.generation = nextGeneration(fs.generation);
    fs.geometry = Point{};
    w.segmentNeighbours[f] = {};
    w.freeFixtures.push_back(f);
  }
  b.fixtures.clear();
  detail::refreshDiskShape(w, id.index);
  w.changes.staticsChanged(b.type);
  ++w.changes.fixtureRemovals;
  b.alive = false;
  b.generation = nextGeneration(b.generation);
  w.freeBodies.push_back(id.index);
  --w.liveBodies;
  w.changes.structureChanged = true;
}

bool World::isValid(BodyId id) const {
  return !id.isNull() && id.index < impl().bodies.size() && impl().bodies[id.index].alive &&
         impl().bodies[id.index].generation == id.generation;
}

BodyType World::type(BodyId id) const { return lookUp(impl().bodies, id).type; }
Vec2 World::position(BodyId id) const { return lookUp(impl().bodies, id).position; }
Vec2 World::velocity(BodyId id) const { return lookUp(impl().bodies, id).velocity; }
double World::mass(BodyId id) const { return lookUp(impl().bodies, id).mass; }
bool World::isAsleep(BodyId id) const { return lookUp(impl().bodies, id).asleep; }

void World::wake(BodyId id) {
  lookUp(impl().bodies, id);
  detail::unlessOutOfMemory("wake", [&] {
    std::vector<uint32_t> woken;
    detail::collectWake(impl(), id.index, woken);
    impl().changes.roomToTouch(woken.size());
    detail::applyWake(impl(), woken, 0, 0.0);
    impl().touched(woken);
  });
}

uint64_t World::userData(BodyId id) const {
  lookUp(impl().bodies, id);  // checks the handle
  return impl().userData[id.index];
}
int World::bodyCount() const { return impl().liveBodies; }

void World::setPosition(BodyId id, Vec2 position) {
  BodySlot& b = lookUp(impl().bodies, id);
  checkFinite(position, "position");
  for (uint32_t f : b.fixtures) {
    const Box& local = impl().fixtures[f].localBox;
    require(inRange(local.translated(position)), [&] {
      return "position = " + str(position) +
             ": the body's fixtures would reach outside +-1e150 (World::kMaxCoordinate)";
    });
  }
  require(inRange(position),
          [&] { return "position = " + str(position) + ": outside +-1e150 (World::kMaxCoordinate)"; });
  detail::unlessOutOfMemory("setPosition", [&] {
    // It wakes, and what rested on it falls: found first, with room for what follows.
    std::vector<uint32_t> woken;
    detail::collectWake(impl(), id.index, woken);
    for (uint32_t d : impl().dependents[id.index]) detail::collectWake(impl(), d, woken);
    impl().changes.roomToTouch(1 + woken.size());
    // Nothing below allocates.
    detail::applyWake(impl(), woken, 0, 0.0);
    impl().dependents[id.index].clear();
    // What slid on its faces slides no longer: the faces have gone from under it (or into it).
    stopSlidesOn(impl(), b, [&](uint32_t f) { return impl().fixtures[f].body == id.index; });
    b.clearSupport();
    b.position = position;
    // Static proxies are not refreshed each step, so move their boxes now.
    for (uint32_t f : b.fixtures) impl().broadPhase.setBox(f, impl().worldBox(f));
    impl().touched(id.index);
    impl().touched(woken);
  });
}

void World::setVelocity(BodyId id, Vec2 velocity) {
  BodySlot& b = lookUp(impl().bodies, id);
  checkVelocity(velocity, "velocity");
  require(b.type != BodyType::Static || velocity == Vec2{},
          [&] { return std::string("velocity = " + str(velocity) + ": a static body cannot move"); });
  detail::unlessOutOfMemory("setVelocity", [&] {
    std::vector<uint32_t> woken;
    detail::collectWake(impl(), id.index, woken);
    impl().changes.roomToTouch(1 + woken.size());
    // Nothing below allocates.
    detail::applyWake(impl(), woken, 0, 0.0);
    if (b.sliding) detail::stopSliding(impl(), b);
    b.velocity = velocity;
    b.driven = b.type == BodyType::Dynamic;
    impl().touched(id.index);
    impl().touched(woken);
  });
}

std::vector<FixtureId> World::fixtures(BodyId id) const {
  const BodySlot& b = lookUp(impl().bodies, id);
  std::vector<FixtureId> out;
  for (uint32_t f : b.fixtures) out.push_back({f, impl().fixtures[f].generation});
  return out;
}

FixtureId World::createFixture(BodyId bodyId, const FixtureDef& def) {
  return detail::unlessOutOfMemory("createFixture", [&]() -> FixtureId {
    Impl& w = impl();
    BodySlot& body = lookUp(w.bodies, bodyId);
    if (auto error = validationError(def.geometry)) throw Error("FixtureDef.geometry: " + *error);
    if (const auto* circle = std::get_if<Circle>(&def.geometry)) {
      // Times of impact resolve a radius down to a few ulps of the coordinates (and of the distances a
      // step covers); kMinRelativeRadius leaves a hundredfold margin above that.
      const Vec2 at = body.position + circle->center;
      const double smallest = kMinRelativeRadius * std::max({1.0, std::fabs(at.x), std::fabs(at.y)});
      require(circle->radius == 0 || circle->radius >= smallest, [&] {
        return "FixtureDef.geometry: Circle.radius = " + str(circle->radius) + ": below the smallest radius that " +
               "collides at " + str(at) + ", 1e-12 x max(1, |x|, |y|) = " + str(smallest) + " (0 makes a point)";
      });
    }
    if (body.type == BodyType::Dynamic) {
      const auto centre = centreOf(def.geometry);
      require(centre.has_value(), [&] {
        return std::string(std::string("FixtureDef.geometry is a ") + nameOf(typeOf(def.geometry)) +
                           ": a dynamic body holds only circles and points sharing one centre");
      });
      for (uint32_t f : body.fixtures) {
        const Vec2 other = *centreOf(w.fixtures[f].geometry);
        require(other == *centre, [&] {
          return std::string("FixtureDef.geometry centre = " + str(*centre) + ": differs from the centre " +
                             str(other) +
                             " of the body's other fixtures (a dynamic body's circles share one centre)");
        });
      }
      require(std::isfinite(def.density) && def.density > 0, [&] {
        return std::string("FixtureDef.density = " + str(def.density) + ": must be finite and > 0 on a dynamic body");
      });
    } else {
      require(std::isfinite(def.density) && def.density >= 0,
              [&] { return std::string("FixtureDef.density = " + str(def.density) + ": must be finite and >= 0"); });
    }
    checkRestitution(def.restitution, "FixtureDef.restitution");
    if (body.type == BodyType::Dynamic && !def.sensor) {
      const double mass = physicalMass(w, body) + def.density * areaOf(def.geometry);
      require(mass <= kMaxMass, [&] {
        return std::string("FixtureDef.density = " + str(def.density) + ": gives the body a mass of " + str(mass) +
                           ", more than 1e150 (World::kMaxMass)");
      });
    }
    const Box localBox = boxOf(def.geometry);
    require(inRange(localBox.translated(body.position)), [&] {
      return "FixtureDef.geometry: its box reaches outside +-1e150 (World::kMaxCoordinate) at the body's position " +
             str(body.position);
    });

    // Everything that allocates first (the stored geometry, room in the lists it joins), then the changes.
    Geometry geometry = normalized(def.geometry);
    const uint32_t index = w.freeFixtures.empty() ? static_cast<uint32_t>(w.fixtures.size()) : w.freeFixtures.back();
    if (w.freeFixtures.empty()) {
      detail::roomForOneMore(w.fixtures);
      detail::roomForOneMore(w.segmentNeighbours);
    }
    body.fixtures.reserveOneMore();
    w.broadPhase.reserveFor(index, def.sensor);
    if (w.freeFixtures.empty()) {
      w.fixtures.emplace_back();
      w.segmentNeighbours.emplace_back();
    } else {
      w.freeFixtures.pop_back();
    }
    FixtureSlot& f = renewed(w.fixtures[index]);
    f.body = bodyId.index;
    f.geometry = std::move(geometry);
    f.localBox = localBox;
    f.density = def.density;
    f.restitution = def.restitution;
    f.sensor = def.sensor;
    f.filter = def.filter;
    body.fixtures.push_back(index);
    detail::refreshDiskShape(w, f.body);
    detail::refreshSegmentNeighboursAround(w, f.body, index);
    if (body.sliding) stopSliding(w, body);  // as in destroyFixture
    recomputeMass(w, body);
    w.changes.structureChanged = true;
    w.changes.staticsChanged(body.type);
    w.broadPhase.add(index, w.worldBox(index), body.type != BodyType::Static, f.sensor, f.filter.categoryBits,
                     f.filter.maskBits);
    if (f.sensor) ++w.liveSensors;
    return FixtureId{index, f.generation};
  });
}

void World::destroyFixture(FixtureId id) {
  Impl& w = impl();
  FixtureSlot& f = lookUp(w.fixtures, id);
  BodySlot& body = w.bodies[f.body];
  detail::unlessOutOfMemory("destroyFixture", [&] {
    std::vector<uint64_t> ended;
    overlapsToEnd(
        w, id.index, [](uint32_t) { return false; }, ended);
    detail::roomFor(w.pendingSensorEvents, ended.size());
    detail::roomForOneMore(w.freeFixtures);
    endOverlaps(w, ended);  // nothing from here on allocates
  });
  body.fixtures.erase(std::find(body.fixtures.begin(), body.fixtures.end(), id.index));
  detail::refreshDiskShape(w, f.body);
  detail::refreshSegmentNeighboursAround(w, f.body, id.index);
  // A slide is the motion of the body's circle along a face: with the circle gone (or another left),
  // the next step finds its contacts again (fuzz/regressions/world_api/ub-predictive-slide-of-a-body-
  // without-fixtures).
  if (body.sliding) stopSliding(w, body);
  stopSlidesOn(w, body, [&](uint32_t g) { return g == id.index; });
  w.broadPhase.remove(id.index);
  if (f.sensor) --w.liveSensors;
  w.changes.structureChanged = true;
  w.changes.staticsChanged(body.type);
  f.alive = false;
  f.generation = nextGeneration(f.generation);
  f.geometry = Point{};
  w.freeFixtures.push_back(id.index);
  ++w.changes.fixtureRemovals;
  recomputeMass(w, body);
}

bool World::isValid(FixtureId id) const {
  return !id.isNull() && id.index < impl().fixtures.size() && impl().fixtures[id.index].alive &&
         impl().fixtures[id.index].generation == id.generation;
}

BodyId World::body(FixtureId id) const {
  const FixtureSlot& f = lookUp(impl().fixtures, id);
  return BodyId{f.body, impl().bodies[f.body].generation};
}
const Geometry& World::geometry(FixtureId id) const { return lookUp(impl().fixtures, id).geometry; }
double World::density(FixtureId id) const { return lookUp(impl().fixtures, id).density; }
double World::restitution(FixtureId id) const { return lookUp(impl().fixtures, id).restitution; }
bool World::isSensor(FixtureId id) const { return lookUp(impl().fixtures, id).sensor; }
Filter World::filter(FixtureId id) const { return lookUp(impl().fixtures, id).filter; }

void World::setDensity(FixtureId id, double density) {
  Impl& w = impl();
  FixtureSlot& f = lookUp(w.fixtures, id);
  BodySlot& body = w.bodies[f.body];
  if (body.type == BodyType::Dynamic) {
    require(std::isfinite(density) && density > 0,
            [&] { return std::string("density = " + str(density) + ": must be finite and > 0 on a dynamic body"); });
  } else {
    require(std::isfinite(density) && density >= 0,
            [&] { return std::string("density = " + str(density) + ": must be finite and >= 0"); });
  }
  detail::unlessOutOfMemory("setDensity", [&] { w.changes.roomToTouch(1); });
  const double old = f.density;
  f.density = density;
  const double mass = physicalMass(w, body);
  if (body.type == BodyType::Dynamic && !f.sensor && !(mass <= kMaxMass)) {
    f.density = old;
    throw Error("density = " + str(density) + ": gives the body a mass of " + str(mass) +
                ", more than 1e150 (World::kMaxMass)");
  }
  recomputeMass(w, body);
  w.touched(f.body);
}

void World::setRestitution(FixtureId id, double restitution) {
  FixtureSlot& f = lookUp(impl().fixtures, id);
  checkRestitution(restitution, "restitution");
  f.restitution = restitution;
  impl().changes.restitutionChanged = true;
}

void World::setFilter(FixtureId id, const Filter& filter) {
  FixtureSlot& fixture = lookUp(impl().fixtures, id);
  detail::unlessOutOfMemory("setFilter", [&] {
    Impl& w = impl();
    // Overlaps the new filter forbids end now; new ones begin when the next step finds them. Found
    // with the new filter in place, which goes back if memory runs out before anything else changed.
    const Filter old = fixture.filter;
    fixture.filter = filter;
    std::vector<uint64_t> ended;
    try {
      overlapsToEnd(
          w, id.index, [&](uint32_t other) { return canSense(w, id.index, other); }, ended);
      detail::roomFor(w.pendingSensorEvents, ended.size());
    } catch (...) {
      fixture.filter = old;
      throw;
    }
    detail::refreshDiskShape(w, fixture.body);
    w.broadPhase.setFilter(id.index, filter.categoryBits, filter.maskBits);
    w.changes.structureChanged = true;
    endOverlaps(w, ended);
  });
}

std::vector<FixtureId> World::sensorOverlaps(FixtureId id) const {
  const FixtureSlot& sensor = lookUp(impl().fixtures, id);
  require(sensor.sensor, [&] {
    return "sensorOverlaps: FixtureId {index " + std::to_string(id.index) + ", generation " +
           std::to_string(id.generation) + "} is not a sensor (FixtureDef.sensor = false)";
  });
  std::vector<uint32_t> found;
  for (const auto& [key, stamp] : impl().sensorOverlaps) {
    if (static_cast<uint32_t>(key >> 32) == id.index) found.push_back(static_cast<uint32_t>(key));
  }
  std::sort(found.begin(), found.end());
  std::vector<FixtureId> out;
  for (uint32_t f : found) out.push_back({f, impl().fixtures[f].generation});
  return out;
}

void World::step(double dt) {
  require(std::isfinite(dt) && dt >= 0,
          [&] { return std::string("step: dt = " + str(dt) + ": must be finite and >= 0"); });
  Impl& w = impl();
  try {
    saveStepStart(w);
    refreshSqueezes(w);
    if (w.def.mode != StepMode::Discrete) separateExemptPairs(w);  // the discrete step pushes apart itself
    wakeSleepersOfMovingBodies(w);
    w.stepper->step(dt);
  } catch (const std::bad_alloc&) {
    undoStep(w);
    throw Error("step: out of memory (the world is unchanged)");
  } catch (const std::length_error&) {
    undoStep(w);
    throw Error("step: out of memory (the world is unchanged)");
  }
  endStep(w);
  // Every body setVelocity drove is in touchedBodies.
  for (uint32_t i : impl().changes.touchedBodies) impl().bodies[i].driven = false;
  impl().changes.clear();
}

void World::advanceTo(double t) {
  require(std::isfinite(t) && t >= impl().time,
          [&] { return "advanceTo: t = " + str(t) + ": must be finite and >= time() = " + str(impl().time); });
  step(t - impl().time);
}

double World::time() const { return impl().time; }
std::span<const ContactEvent> World::contactEvents() const { return impl().contactEvents; }
std::span<const SensorEvent> World::sensorEvents() const { return impl().sensorEvents; }
const StepStats& World::stats() const { return impl().stats; }

uint64_t World::stateHash() const {
  // FNV-1a over the exact bytes, in slot order: independent of pointers and of any container's order.
  uint64_t h = 0xcbf29ce484222325ull;
  auto mix = [&h](uint64_t v) {
    for (int i = 0; i < 8; ++i) {
      h ^= (v >> (8 * i)) & 0xff;
      h *= 0x100000001b3ull;
    }
  };
  auto mixDouble = [&mix](double d) {
    uint64_t bits;
    std::memcpy(&bits, &d, sizeof bits);
    mix(bits);
  };
  mixDouble(impl().time);
  for (uint32_t i = 0; i < impl().bodies.size(); ++i) {
    const BodySlot& b = impl().bodies[i];
    if (!b.alive) continue;
    mix(i);
    mix(b.generation);
    mix(static_cast<uint64_t>(b.type));
    mixDouble(b.position.x);
    mixDouble(b.position.y);
    mixDouble(b.velocity.x);
    mixDouble(b.velocity.y);
  }
  return h;
}

}  // namespace rattle
