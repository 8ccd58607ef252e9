// World::save and World::load: the world's lasting state as bytes, and a world made from them.
//
// What a save holds is what the next step reads and cannot rebuild: every body and fixture slot, live
// or free (ids and generations, so handles stay valid), the free lists in their order, who sleeps on
// whom, the sensors' overlaps and the end events still to report, the squeezes, and the contact solve's
// warm start and jam count. What the modes keep only to go faster (the broad phase's sorted lists, the
// predictive grid and queue) is built anew by the first step, as after a step that ran out of memory.
// So load is a function of the bytes alone: two worlds loaded from one save step alike forever, on every
// machine, while the saved world itself may part from them in the last bits where its broad phase's
// order broke a tie. Lockstep peers therefore load together (the demo's keyframes).
//
// Format (little-endian; doubles as their IEEE-754 bits), in the order written below: "RTLW", the
// version, the WorldDef, the time, the body slots, the free bodies, the fixture slots, the free
// fixtures, the sensors' overlaps, their pending events, the squeezes, the islands, and an FNV-1a
// checksum of everything before it. load checks the checksum first, then every field as the World API
// would check it, and throws rattle::Error naming the byte and the field.
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>

#include "api/value_ranges.h"
#include "common/byte_io.h"
#include "common/format.h"
#include "contact/islands.h"
#include "contact/resting.h"
#include "world/stepper.h"
#include "world/world_impl.h"

namespace rattle {

using detail::BodySlot;
using detail::ByteReader;
using detail::ByteWriter;
using detail::finiteSquare;
using detail::FixtureSlot;
using detail::inRange;

namespace {

constexpr uint8_t kMagic[4] = {'R', 'T', 'L', 'W'};
constexpr uint32_t kSaveVersion = 1;
const char* const kWhat = "World::load";

// Body flags, one byte.
enum : uint8_t { kAsleep = 1, kStepped = 2, kSliding = 4, kDriven = 8, kStepLocalsSet = 16 };

void writeGeometry(ByteWriter& out, const Geometry& g) {
  out.u8(static_cast<uint8_t>(g.index()));
  std::visit(
      [&](const auto& s) {
        using S = std::decay_t<decltype(s)>;
        if constexpr (std::is_same_v<S, Point>) {
          out.vec2(s.position);
        } else if constexpr (std::is_same_v<S, Circle>) {
          out.vec2(s.center);
          out.f64(s.radius);
        } else if constexpr (std::is_same_v<S, Segment>) {
          out.vec2(s.a);
          out.vec2(s.b);
        } else {
          out.u32(static_cast<uint32_t>(s.points.size()));
          for (Vec2 p : s.points) out.vec2(p);
        }
      },
      g);
}

Geometry readGeometry(ByteReader& in) {
  const size_t at = in.offset();
  const uint8_t type = in.u8("geometry type");
  switch (type) {
    case 0:
      return Point{in.vec2("geometry")};
    case 1: {
      Circle c;
      c.center = in.vec2("geometry");
      c.radius = in.f64("geometry");
      return c;
    }
    case 2: {
      Segment s;
      s.a = in.vec2("geometry");
      s.b = in.vec2("geometry");
      return s;
    }
    case 3:
    case 4: {
      std::vector<Vec2> points(in.count("geometry point count", 16));
      for (Vec2& p : points) p = in.vec2("geometry");
      if (type == 3) return Polyline{std::move(points)};
      return Polygon{std::move(points)};
    }
    default:
      in.fail(at, "geometry type", " = " + std::to_string(type) + ": not a GeometryType (0 to 4)");
  }
}

void writeId(ByteWriter& out, uint32_t index, uint32_t generation) {
  out.u32(index);
  out.u32(generation);
}

}  // namespace

std::vector<uint8_t> World::save() const {
  const Impl& w = impl();
  ByteWriter out;
  for (uint8_t m : kMagic) out.u8(m);
  out.u32(kSaveVersion);
  out.u8(static_cast<uint8_t>(w.def.mode));
  out.vec2(w.def.gravity);
  out.f64(w.def.restingSpeed);
  out.f64(w.def.collapseTime);
  out.i32(w.def.maxEventsPerStep);
  out.f64(w.time);
  out.u32(w.stepStamp);

  out.u32(static_cast<uint32_t>(w.bodies.size()));
  for (uint32_t i = 0; i < w.bodies.size(); ++i) {
    const BodySlot& b = w.bodies[i];
    out.u8(b.alive ? 1 : 0);
    out.u32(b.generation);
    if (!b.alive) continue;
    out.u8(static_cast<uint8_t>(b.type));
    out.u8(static_cast<uint8_t>((b.asleep ? kAsleep : 0) | (b.stepped ? kStepped : 0) | (b.sliding ? kSliding : 0) |
                                (b.driven ? kDriven : 0) | (b.stepLocalsSet ? kStepLocalsSet : 0)));
    out.vec2(b.position);
    out.vec2(b.velocity);
    out.vec2(b.acceleration);
    out.f64(b.localTime);
    out.u32(b.collisionCount);
    out.i32(b.stepCollisions);
    out.u32(b.last.fixtureLow);
    out.u32(b.last.fixtureHigh);
    out.i32(b.last.feature);
    out.f64(b.last.time);
    out.u32(b.support.fixture);
    out.u32(b.support.generation);
    out.i32(b.support.feature);
    out.vec2(b.support.normal);
    out.f64(b.lastContactTime);
    out.u64(w.userData[i]);
    out.u32(static_cast<uint32_t>(w.dependents[i].size()));
    for (uint32_t d : w.dependents[i]) out.u32(d);
    out.u32(static_cast<uint32_t>(b.fixtures.size()));
    for (uint32_t f : b.fixtures) out.u32(f);
  }
  out.u32(static_cast<uint32_t>(w.freeBodies.size()));
  for (uint32_t i : w.freeBodies) out.u32(i);

  out.u32(static_cast<uint32_t>(w.fixtures.size()));
  for (const FixtureSlot& f : w.fixtures) {
    out.u8(f.alive ? 1 : 0);
    out.u32(f.generation);
    if (!f.alive) continue;
    out.u32(f.body);
    writeGeometry(out, f.geometry);
    out.f64(f.density);
    out.f64(f.restitution);
    out.u8(f.sensor ? 1 : 0);
    out.u32(f.filter.categoryBits);
    out.u32(f.filter.maskBits);
    out.i32(f.filter.group);
  }
  out.u32(static_cast<uint32_t>(w.freeFixtures.size()));
  for (uint32_t i : w.freeFixtures) out.u32(i);

  // The overlaps by key: the map's own order depends on its history.
  std::vector<std::pair<uint64_t, uint32_t>> overlaps(w.sensorOverlaps.begin(), w.sensorOverlaps.end());
  std::sort(overlaps.begin(), overlaps.end());
  out.u32(static_cast<uint32_t>(overlaps.size()));
  for (const auto& [key, stamp] : overlaps) {
    out.u64(key);
    out.u32(stamp);
  }
  out.u32(static_cast<uint32_t>(w.pendingSensorEvents.size()));
  for (const SensorEvent& e : w.pendingSensorEvents) {
    out.f64(e.time);
    writeId(out, e.sensor.index, e.sensor.generation);
    writeId(out, e.sensorBody.index, e.sensorBody.generation);
    writeId(out, e.visitor.index, e.visitor.generation);
    writeId(out, e.visitorBody.index, e.visitorBody.generation);
    out.u8(e.begin ? 1 : 0);
  }
  out.u32(static_cast<uint32_t>(w.squeezes.size()));
  for (const auto& s : w.squeezes) {
    out.u64(s.key);
    out.u32(s.generationA);
    out.u32(s.generationB);
  }
  // Bodies whose squeeze count the next step's start sets back to 0 (refreshSqueezes).
  out.u32(static_cast<uint32_t>(w.squeezeCounted.size()));
  for (uint32_t i : w.squeezeCounted) out.u32(i);

  const detail::Islands* islands = w.stepper->islands();
  out.u8(islands ? 1 : 0);
  if (islands) {
    out.u32(islands->jamCounter);
    // The next step's warm start, unless a fixture destroyed since voids it (Islands::beginStep).
    const bool kept = islands->warmStartKept();
    out.u32(kept ? static_cast<uint32_t>(islands->islandNext.size()) : 0);
    if (kept) {
      for (const auto& [key, impulse] : islands->islandNext) {
        out.u64(key);
        out.f64(impulse);
      }
    }
  }
  const uint64_t checksum = detail::fnv1a(out.bytes());
  out.u64(checksum);
  return std::move(out.bytes());
}

namespace {

// World::load's reading, part by part, into a new world's state. Every part checks what it reads the way
// the World API checks what it is given, and fails naming the byte and the field.
class SaveReader {
 public:
  SaveReader(ByteReader& in, detail::WorldState& w) : in_(in), w_(w) {}

  void bodies();
  void fixtures();
  /// What follows a body's fixtures: its mass, disk shape and place in the broad phase, the rules
  /// createFixture holds a dynamic body to, and its support.
  void finishBodies();
  void sensors();
  void squeezes();
  void islands();

 private:
  template <class Message>
  void check(bool ok, size_t at, const char* field, Message&& message) {
    if (!ok) in_.fail(at, field, message());
  }
  /// A slot's alive flag and generation, which every slot has, live or free.
  template <class Slot>
  void slotHead(Slot& slot) {
    slot.alive = in_.flag("alive");
    const size_t at = in_.offset();
    slot.generation = in_.u32("generation");
    check(slot.generation != 0, at, "generation", [] { return " = 0: generations start at 1"; });
  }
  /// A free list: each free slot of `slots` once, in the saved order (`noun`: "body" or "fixture").
  template <class Slots>
  void freeList(const Slots& slots, std::vector<uint32_t>& list, const char* noun);
  void body(uint32_t i);
  void fixture(uint32_t k);

  ByteReader& in_;
  detail::WorldState& w_;
  uint32_t bodyCount_ = 0, fixtureCount_ = 0;
  std::vector<uint32_t> fixtureOwner_;  // by fixture index: the body listing it + 1 (0: none)
};

template <class Slots>
void SaveReader::freeList(const Slots& slots, std::vector<uint32_t>& list, const char* noun) {
  in_.entry(nullptr);
  const std::string countField = std::string("free ") + noun + " count", field = std::string("free ") + noun;
  std::vector<uint8_t> listed(slots.size(), 0);
  const uint32_t count = in_.count(countField.c_str(), 4);
  for (uint32_t k = 0; k < count; ++k) {
    const size_t at = in_.offset();
    const uint32_t i = in_.u32(field.c_str());
    check(i < slots.size() && !slots[i].alive && !listed[i], at, field.c_str(),
          [&] { return " = " + std::to_string(i) + ": not a free " + noun + " slot, or listed twice"; });
    listed[i] = 1;
    list.push_back(i);
  }
  const auto dead = std::count_if(slots.begin(), slots.end(), [](const auto& s) { return !s.alive; });
  check(count == static_cast<uint32_t>(dead), in_.offset(), countField.c_str(),
        [&] { return " = " + std::to_string(count) + ": every free " + noun + " slot must be listed once"; });
}

void SaveReader::bodies() {
  bodyCount_ = in_.count("body slot count", 5);
  w_.bodies.resize(bodyCount_);
  w_.userData.resize(bodyCount_);
  w_.dependents.resize(bodyCount_);
  w_.diskShapes.resize(bodyCount_);
  for (uint32_t i = 0; i < bodyCount_; ++i) body(i);
  freeList(w_.bodies, w_.freeBodies, "body");
}

void SaveReader::body(uint32_t i) {
  in_.entry("bodies", i);
  BodySlot& b = w_.bodies[i];
  slotHead(b);
  if (!b.alive) return;
  size_t at = in_.offset();
  const uint8_t type = in_.u8("type");
  check(type <= static_cast<uint8_t>(BodyType::Kinematic), at, "type",
        [&] { return " = " + std::to_string(type) + ": not a BodyType (0 to 2)"; });
  b.type = static_cast<BodyType>(type);
  at = in_.offset();
  const uint8_t flags = in_.u8("flags");
  check(flags < 32 && (b.type == BodyType::Dynamic || (flags & ~kStepLocalsSet) == 0), at, "flags",
        [&] { return " = " + std::to_string(flags) + ": unknown bits, or a static or kinematic body's"; });
  b.asleep = flags & kAsleep;
  b.stepped = flags & kStepped;
  b.sliding = flags & kSliding;
  b.driven = flags & kDriven;
  b.stepLocalsSet = flags & kStepLocalsSet;
  at = in_.offset();
  b.position = in_.vec2("position");
  check(isFinite(b.position) && inRange(b.position), at, "position",
        [&] { return " = " + detail::str(b.position) + ": must be finite, within +-1e150"; });
  at = in_.offset();
  b.velocity = in_.vec2("velocity");
  check(finiteSquare(b.velocity) && (b.type != BodyType::Static || b.velocity == Vec2{}), at, "velocity",
        [&] { return " = " + detail::str(b.velocity) + ": not finite, too fast, or a static body's"; });
  at = in_.offset();
  // Gravity, its part along a face a body slides on, or nothing: never more than gravity, and nothing
  // on a body that is not dynamic.
  b.acceleration = in_.vec2("acceleration");
  const double g = length(w_.def.gravity);
  check(finiteSquare(b.acceleration) && length(b.acceleration) <= g * (1 + 1e-9) &&
            (b.type == BodyType::Dynamic || b.acceleration == Vec2{}),
        at, "acceleration",
        [&] { return " = " + detail::str(b.acceleration) + ": more than gravity, or a static or kinematic body's"; });
  // Every body's clock is at 0 between steps: a step moves them all to its end. Another time would move
  // the body by its velocity times that time at the next step's start (the world_load fuzzer found
  // -1.6e306, which overflowed to a NaN in the broad phase).
  at = in_.offset();
  b.localTime = in_.f64("localTime");
  check(b.localTime == 0, at, "localTime",
        [&] { return " = " + detail::str(b.localTime) + ": must be 0 between steps"; });
  b.collisionCount = in_.u32("collisionCount");
  at = in_.offset();
  b.stepCollisions = in_.i32("stepCollisions");
  check(b.stepCollisions >= 0, at, "stepCollisions",
        [&] { return " = " + std::to_string(b.stepCollisions) + ": must be >= 0"; });
  b.last.fixtureLow = in_.u32("last.fixtureLow");
  b.last.fixtureHigh = in_.u32("last.fixtureHigh");
  b.last.feature = in_.i32("last.feature");
  at = in_.offset();
  b.last.time = in_.f64("last.time");
  check(std::isfinite(b.last.time), at, "last.time",
        [&] { return " = " + detail::str(b.last.time) + ": must be finite"; });
  b.support.fixture = in_.u32("support.fixture");
  b.support.generation = in_.u32("support.generation");
  b.support.feature = in_.i32("support.feature");
  at = in_.offset();
  b.support.normal = in_.vec2("support.normal");
  check(isFinite(b.support.normal) && std::fabs(b.support.normal.x) <= 1 && std::fabs(b.support.normal.y) <= 1, at,
        "support.normal", [&] { return " = " + detail::str(b.support.normal) + ": a unit normal or none"; });
  at = in_.offset();
  b.lastContactTime = in_.f64("lastContactTime");
  check(!std::isnan(b.lastContactTime) && b.lastContactTime != INFINITY, at, "lastContactTime",
        [&] { return " = " + detail::str(b.lastContactTime) + ": must be finite or -inf (none)"; });
  w_.userData[i] = in_.u64("userData");
  w_.dependents[i].resize(in_.count("dependent count", 4));
  for (uint32_t& d : w_.dependents[i]) {
    at = in_.offset();
    d = in_.u32("dependent");
    check(d < bodyCount_, at, "dependent", [&] { return " = " + std::to_string(d) + ": no such body slot"; });
  }
  const uint32_t fixtures = in_.count("fixture count", 4);
  for (uint32_t k = 0; k < fixtures; ++k) {
    at = in_.offset();
    const uint32_t f = in_.u32("fixture");
    // Checked once the fixture slots are read; here only that no fixture is listed twice. The owners'
    // list grows no larger than the bytes left could hold fixture slots.
    if (f >= fixtureOwner_.size()) fixtureOwner_.resize(std::min<size_t>(size_t{f} + 1, in_.left() + 1), 0);
    check(f < fixtureOwner_.size() && fixtureOwner_[f] == 0, at, "fixture",
          [&] { return " = " + std::to_string(f) + ": listed twice, or no such fixture slot"; });
    fixtureOwner_[f] = i + 1;
    b.fixtures.push_back(f);
  }
  ++w_.liveBodies;
}

void SaveReader::fixtures() {
  fixtureCount_ = in_.count("fixture slot count", 5);
  check(fixtureOwner_.size() <= fixtureCount_, in_.offset(), "fixture slot count", [&] {
    return " = " + std::to_string(fixtureCount_) + ": a body lists fixture " + std::to_string(fixtureOwner_.size() - 1);
  });
  fixtureOwner_.resize(fixtureCount_, 0);
  w_.fixtures.resize(fixtureCount_);
  for (uint32_t k = 0; k < fixtureCount_; ++k) fixture(k);
  freeList(w_.fixtures, w_.freeFixtures, "fixture");
}

void SaveReader::fixture(uint32_t k) {
  in_.entry("fixtures", k);
  FixtureSlot& f = w_.fixtures[k];
  size_t at = in_.offset();
  slotHead(f);
  if (!f.alive) {
    f.geometry = Point{};
    check(fixtureOwner_[k] == 0, at, "alive", [] { return " = 0: a body lists it"; });
    return;
  }
  at = in_.offset();
  f.body = in_.u32("body");
  check(f.body < bodyCount_ && fixtureOwner_[k] == f.body + 1, at, "body",
        [&] { return " = " + std::to_string(f.body) + ": that body does not list this fixture"; });
  at = in_.offset();
  Geometry g = readGeometry(in_);
  if (auto error = validationError(g)) in_.fail(at, "geometry", ": " + *error);
  f.geometry = normalized(g);
  f.localBox = boxOf(f.geometry);
  const BodySlot& b = w_.bodies[f.body];
  check(inRange(f.localBox.translated(b.position)), at, "geometry",
        [] { return std::string(": its box reaches outside +-1e150 at its body's position"); });
  at = in_.offset();
  f.density = in_.f64("density");
  check(std::isfinite(f.density) && (b.type == BodyType::Dynamic ? f.density > 0 : f.density >= 0), at, "density",
        [&] { return " = " + detail::str(f.density) + ": must be finite and > 0 (>= 0 off a dynamic body)"; });
  at = in_.offset();
  f.restitution = in_.f64("restitution");
  check(std::isfinite(f.restitution) && f.restitution >= 0 && f.restitution <= 1, at, "restitution",
        [&] { return " = " + detail::str(f.restitution) + ": must be in [0, 1]"; });
  f.sensor = in_.flag("sensor");
  f.filter.categoryBits = in_.u32("filter.categoryBits");
  f.filter.maskBits = in_.u32("filter.maskBits");
  f.filter.group = in_.i32("filter.group");
  if (f.sensor) ++w_.liveSensors;
}

void SaveReader::finishBodies() {
  for (uint32_t i = 0; i < bodyCount_; ++i) {
    BodySlot& b = w_.bodies[i];
    if (!b.alive) continue;
    in_.entry("bodies", i);
    const size_t at = in_.offset();
    if (b.type == BodyType::Dynamic) {
      std::optional<Vec2> centre;
      for (uint32_t f : b.fixtures) {
        const Geometry& g = w_.fixtures[f].geometry;
        const Circle* c = std::get_if<Circle>(&g);
        const Point* p = std::get_if<Point>(&g);
        check(c || p, at, "fixtures",
              [&] { return ": fixture " + std::to_string(f) + " is not a circle or a point (a dynamic body's)"; });
        const Vec2 here = c ? c->center : p->position;
        check(!centre || *centre == here, at, "fixtures",
              [&] { return ": fixture " + std::to_string(f) + "'s centre differs from the others'"; });
        centre = here;
      }
      check(detail::physicalMass(w_, b) <= World::kMaxMass, at, "fixtures",
            [] { return std::string(": their mass is more than 1e150 (World::kMaxMass)"); });
    }
    detail::recomputeMass(w_, b);
    detail::refreshDiskShape(w_, i);
    const uint32_t s = b.support.fixture;
    if (b.sliding) {
      check(s < fixtureCount_ && w_.fixtures[s].alive && w_.fixtures[s].generation == b.support.generation &&
                w_.bodies[w_.fixtures[s].body].type != BodyType::Dynamic &&
                detail::isFlatFeature(w_, s, b.support.feature),
            at, "support",
            [] { return std::string(": it slides, but not on a flat face of a fixture that cannot move"); });
    } else {
      check(b.support.generation == 0 || s < fixtureCount_, at, "support.fixture",
            [&] { return " = " + std::to_string(s) + ": no such fixture slot"; });
    }
  }
  in_.entry(nullptr);
  for (uint32_t k = 0; k < fixtureCount_; ++k) {
    const FixtureSlot& f = w_.fixtures[k];
    if (!f.alive) continue;
    w_.broadPhase.add(k, w_.worldBox(k), w_.bodies[f.body].type != BodyType::Static, f.sensor, f.filter.categoryBits,
                      f.filter.maskBits);
  }
}

void SaveReader::sensors() {
  const uint32_t overlaps = in_.count("sensor overlap count", 12);
  for (uint32_t k = 0; k < overlaps; ++k) {
    in_.entry("sensorOverlaps", k);
    const size_t at = in_.offset();
    const uint64_t key = in_.u64("key");
    const uint32_t sensor = static_cast<uint32_t>(key >> 32), visitor = static_cast<uint32_t>(key);
    const auto live = [&](uint32_t f, bool isSensor) {
      return f < fixtureCount_ && w_.fixtures[f].alive && w_.fixtures[f].sensor == isSensor;
    };
    check(live(sensor, true) && live(visitor, false) && w_.fixtures[sensor].body != w_.fixtures[visitor].body, at,
          "key", [&] {
            return ": sensor " + std::to_string(sensor) + ", visitor " + std::to_string(visitor) +
                   ": not a live sensor and a live physical fixture of another body";
          });
    const uint32_t stamp = in_.u32("stamp");
    check(w_.sensorOverlaps.emplace(key, stamp).second, at, "key", [] { return std::string(": listed twice"); });
  }
  const uint32_t pending = in_.count("pending sensor event count", 41);
  for (uint32_t k = 0; k < pending; ++k) {
    in_.entry("pendingSensorEvents", k);
    SensorEvent e;
    const size_t at = in_.offset();
    e.time = in_.f64("time");
    check(std::isfinite(e.time), at, "time", [&] { return " = " + detail::str(e.time) + ": must be finite"; });
    e.sensor = {in_.u32("sensor.index"), in_.u32("sensor.generation")};
    e.sensorBody = {in_.u32("sensorBody.index"), in_.u32("sensorBody.generation")};
    e.visitor = {in_.u32("visitor.index"), in_.u32("visitor.generation")};
    e.visitorBody = {in_.u32("visitorBody.index"), in_.u32("visitorBody.generation")};
    e.begin = in_.flag("begin");
    w_.pendingSensorEvents.push_back(e);
  }
}

void SaveReader::squeezes() {
  const uint32_t squeezes = in_.count("squeeze count", 16);
  for (uint32_t k = 0; k < squeezes; ++k) {
    in_.entry("squeezes", k);
    const size_t at = in_.offset();
    detail::WorldState::Squeeze s{};
    s.key = in_.u64("key");
    check(static_cast<uint32_t>(s.key >> 32) < fixtureCount_ && static_cast<uint32_t>(s.key) < fixtureCount_, at, "key",
          [] { return std::string(": names no fixture slot"); });
    s.generationA = in_.u32("generationA");
    s.generationB = in_.u32("generationB");
    w_.squeezes.push_back(s);
  }
  in_.entry(nullptr);
  const uint32_t counted = in_.count("squeeze-counted body count", 4);
  for (uint32_t k = 0; k < counted; ++k) {
    const size_t at = in_.offset();
    const uint32_t i = in_.u32("squeeze-counted body");
    check(i < bodyCount_, at, "squeeze-counted body",
          [&] { return " = " + std::to_string(i) + ": no such body slot"; });
    w_.squeezeCounted.push_back(i);
  }
}

void SaveReader::islands() {
  const size_t at = in_.offset();
  const uint8_t hasIslands = in_.u8("has islands");
  detail::Islands* islands = w_.stepper->islands();
  check(hasIslands == (islands ? 1 : 0), at, "has islands",
        [&] { return " = " + std::to_string(hasIslands) + ": the mode's is " + (islands ? "1" : "0"); });
  if (!islands) return;
  islands->jamCounter = in_.u32("jam counter");
  const uint32_t warm = in_.count("warm start count", 16);
  for (uint32_t k = 0; k < warm; ++k) {
    in_.entry("warmStart", k);
    const uint64_t key = in_.u64("key");
    const size_t impulseAt = in_.offset();
    const double impulse = in_.f64("impulse");
    check(std::isfinite(impulse) && impulse >= 0, impulseAt, "impulse",
          [&] { return " = " + detail::str(impulse) + ": must be finite and >= 0"; });
    islands->islandNext.emplace_back(key, impulse);
  }
  in_.entry(nullptr);
}

}  // namespace

World World::load(std::span<const uint8_t> bytes) {
  if (bytes.size() < sizeof kMagic + 4 + 8 || !std::equal(std::begin(kMagic), std::end(kMagic), bytes.begin())) {
    throw Error(std::string(kWhat) + ": not a saved world (it does not start with \"RTLW\")");
  }
  const std::span<const uint8_t> body = bytes.first(bytes.size() - 8);
  ByteReader tail(bytes.last(8), kWhat);
  if (tail.u64("checksum") != detail::fnv1a(body)) {
    throw Error(std::string(kWhat) + ": the checksum does not match (the " + std::to_string(bytes.size()) +
                " bytes were changed or cut short)");
  }
  ByteReader in(body, kWhat);
  in.u32("magic");
  const uint32_t version = in.u32("version");
  if (version != kSaveVersion) {
    in.fail(4, "version",
            " = " + std::to_string(version) + ": this build reads version " + std::to_string(kSaveVersion));
  }
  WorldDef def;
  in.entry("def");
  const size_t defAt = in.offset();
  const uint8_t mode = in.u8("mode");
  if (mode > static_cast<uint8_t>(StepMode::Predictive)) {
    in.fail(defAt, "mode", " = " + std::to_string(mode) + ": not a StepMode (0 to 2)");
  }
  def.mode = static_cast<StepMode>(mode);
  def.gravity = in.vec2("gravity");
  def.restingSpeed = in.f64("restingSpeed");
  def.collapseTime = in.f64("collapseTime");
  def.maxEventsPerStep = in.i32("maxEventsPerStep");
  std::optional<World> made;
  try {
    made.emplace(def);
  } catch (const Error& e) {
    in.fail(defAt, "", std::string(": ") + e.what());
  }
  World world = std::move(*made);
  detail::WorldState& w = world.impl();
  in.entry(nullptr);
  const size_t timeAt = in.offset();
  w.time = in.f64("time");
  if (!std::isfinite(w.time) || w.time < 0) {
    in.fail(timeAt, "time", " = " + detail::str(w.time) + ": must be finite and >= 0");
  }
  w.stepStamp = in.u32("stepStamp");
  SaveReader reader(in, w);
  reader.bodies();
  reader.fixtures();
  reader.finishBodies();
  detail::findSegmentNeighbours(w);
  reader.sensors();
  reader.squeezes();
  reader.islands();
  detail::findSleepersOnAwakeBodies(w);
  if (in.offset() != body.size()) {
    in.fail(in.offset(), "", std::to_string(body.size() - in.offset()) + " bytes after the last field");
  }
  // A body setVelocity drove before the save is driven in the first step too (World::step clears the
  // mark through touchedBodies). Every other change list starts as a new world's: all changed.
  for (uint32_t i = 0; i < w.bodies.size(); ++i) {
    if (w.bodies[i].alive && w.bodies[i].driven) w.changes.touchedBodies.push_back(i);
  }
  return world;
}

}  // namespace rattle
