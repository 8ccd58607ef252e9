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
using detail::FixtureSlot;

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

bool finiteSquare(Vec2 v) { return isFinite(v) && std::isfinite(dot(v, v)); }
bool inRange(Vec2 v) { return std::fabs(v.x) <= World::kMaxCoordinate && std::fabs(v.y) <= World::kMaxCoordinate; }
bool inRange(const Box& b) { return inRange(b.min) && inRange(b.max); }

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
    in.fail(4, "version", " = " + std::to_string(version) + ": this build reads version " +
                              std::to_string(kSaveVersion));
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
  Impl& w = world.impl();
  in.entry(nullptr);
  size_t at = in.offset();
  w.time = in.f64("time");
  if (!std::isfinite(w.time) || w.time < 0) in.fail(at, "time", " = " + detail::str(w.time) + ": must be finite and >= 0");
  w.stepStamp = in.u32("stepStamp");

  // Bodies: each slot as saved; their fixture lists are checked against the fixtures below.
  const uint32_t bodyCount = in.count("body slot count", 5);
  w.bodies.resize(bodyCount);
  w.userData.resize(bodyCount);
  w.dependents.resize(bodyCount);
  w.diskShapes.resize(bodyCount);
  std::vector<uint32_t> fixtureOwner;  // by fixture index: the body listing it + 1 (0: none)
  auto check = [&](bool ok, size_t fieldAt, const char* field, auto&& message) {
    if (!ok) in.fail(fieldAt, field, message());
  };
  for (uint32_t i = 0; i < bodyCount; ++i) {
    in.entry("bodies", i);
    BodySlot& b = w.bodies[i];
    at = in.offset();
    const uint8_t alive = in.u8("alive");
    check(alive <= 1, at, "alive", [&] { return " = " + std::to_string(alive) + ": must be 0 or 1"; });
    b.alive = alive == 1;
    b.generation = in.u32("generation");
    check(b.generation != 0, at + 1, "generation", [] { return " = 0: generations start at 1"; });
    if (!b.alive) continue;
    at = in.offset();
    const uint8_t type = in.u8("type");
    check(type <= static_cast<uint8_t>(BodyType::Kinematic), at, "type",
          [&] { return " = " + std::to_string(type) + ": not a BodyType (0 to 2)"; });
    b.type = static_cast<BodyType>(type);
    at = in.offset();
    const uint8_t flags = in.u8("flags");
    check(flags < 32 && (b.type == BodyType::Dynamic || (flags & ~kStepLocalsSet) == 0), at, "flags",
          [&] { return " = " + std::to_string(flags) + ": unknown bits, or a static or kinematic body's"; });
    b.asleep = flags & kAsleep;
    b.stepped = flags & kStepped;
    b.sliding = flags & kSliding;
    b.driven = flags & kDriven;
    b.stepLocalsSet = flags & kStepLocalsSet;
    at = in.offset();
    b.position = in.vec2("position");
    check(isFinite(b.position) && inRange(b.position), at, "position",
          [&] { return " = " + detail::str(b.position) + ": must be finite, within +-1e150"; });
    at = in.offset();
    b.velocity = in.vec2("velocity");
    check(finiteSquare(b.velocity) && (b.type != BodyType::Static || b.velocity == Vec2{}), at, "velocity",
          [&] { return " = " + detail::str(b.velocity) + ": not finite, too fast, or a static body's"; });
    at = in.offset();
    // Gravity, its part along a face a body slides on, or nothing: never more than gravity, and nothing
    // on a body that is not dynamic.
    b.acceleration = in.vec2("acceleration");
    const double g = length(def.gravity);
    check(finiteSquare(b.acceleration) && length(b.acceleration) <= g * (1 + 1e-9) &&
              (b.type == BodyType::Dynamic || b.acceleration == Vec2{}),
          at, "acceleration",
          [&] { return " = " + detail::str(b.acceleration) + ": more than gravity, or a static or kinematic body's"; });
    // Every body's clock is at 0 between steps: a step moves them all to its end. Another time would move
    // the body by its velocity times that time at the next step's start (the world_load fuzzer found
    // -1.6e306, which overflowed to a NaN in the broad phase).
    at = in.offset();
    b.localTime = in.f64("localTime");
    check(b.localTime == 0, at, "localTime",
          [&] { return " = " + detail::str(b.localTime) + ": must be 0 between steps"; });
    b.collisionCount = in.u32("collisionCount");
    at = in.offset();
    b.stepCollisions = in.i32("stepCollisions");
    check(b.stepCollisions >= 0, at, "stepCollisions",
          [&] { return " = " + std::to_string(b.stepCollisions) + ": must be >= 0"; });
    b.last.fixtureLow = in.u32("last.fixtureLow");
    b.last.fixtureHigh = in.u32("last.fixtureHigh");
    b.last.feature = in.i32("last.feature");
    at = in.offset();
    b.last.time = in.f64("last.time");
    check(std::isfinite(b.last.time), at, "last.time", [&] { return " = " + detail::str(b.last.time) + ": must be finite"; });
    b.support.fixture = in.u32("support.fixture");
    b.support.generation = in.u32("support.generation");
    b.support.feature = in.i32("support.feature");
    at = in.offset();
    b.support.normal = in.vec2("support.normal");
    check(isFinite(b.support.normal) && std::fabs(b.support.normal.x) <= 1 && std::fabs(b.support.normal.y) <= 1, at,
          "support.normal", [&] { return " = " + detail::str(b.support.normal) + ": a unit normal or none"; });
    at = in.offset();
    b.lastContactTime = in.f64("lastContactTime");
    check(!std::isnan(b.lastContactTime) && b.lastContactTime != INFINITY, at, "lastContactTime",
          [&] { return " = " + detail::str(b.lastContactTime) + ": must be finite or -inf (none)"; });
    w.userData[i] = in.u64("userData");
    const uint32_t dependents = in.count("dependent count", 4);
    w.dependents[i].resize(dependents);
    for (uint32_t& d : w.dependents[i]) {
      at = in.offset();
      d = in.u32("dependent");
      check(d < bodyCount, at, "dependent", [&] { return " = " + std::to_string(d) + ": no such body slot"; });
    }
    const uint32_t fixtures = in.count("fixture count", 4);
    for (uint32_t k = 0; k < fixtures; ++k) {
      at = in.offset();
      const uint32_t f = in.u32("fixture");
      // Checked once the fixture slots are read; here only that no fixture is listed twice.
      if (f >= fixtureOwner.size()) fixtureOwner.resize(std::min<size_t>(size_t{f} + 1, bytes.size()), 0);
      check(f < fixtureOwner.size() && fixtureOwner[f] == 0, at, "fixture",
            [&] { return " = " + std::to_string(f) + ": listed twice, or no such fixture slot"; });
      fixtureOwner[f] = i + 1;
      b.fixtures.push_back(f);
    }
    ++w.liveBodies;
  }
  in.entry(nullptr);
  std::vector<uint8_t> listedFree(bodyCount, 0);
  const uint32_t freeBodies = in.count("free body count", 4);
  for (uint32_t k = 0; k < freeBodies; ++k) {
    at = in.offset();
    const uint32_t i = in.u32("free body");
    check(i < bodyCount && !w.bodies[i].alive && !listedFree[i], at, "free body",
          [&] { return " = " + std::to_string(i) + ": not a free body slot, or listed twice"; });
    listedFree[i] = 1;
    w.freeBodies.push_back(i);
  }
  check(freeBodies == bodyCount - static_cast<uint32_t>(w.liveBodies), in.offset(), "free body count",
        [&] { return " = " + std::to_string(freeBodies) + ": every free body slot must be listed once"; });

  const uint32_t fixtureCount = in.count("fixture slot count", 5);
  check(fixtureOwner.size() <= fixtureCount, in.offset(), "fixture slot count",
        [&] { return " = " + std::to_string(fixtureCount) + ": a body lists fixture " +
                     std::to_string(fixtureOwner.size() - 1); });
  fixtureOwner.resize(fixtureCount, 0);
  w.fixtures.resize(fixtureCount);
  for (uint32_t k = 0; k < fixtureCount; ++k) {
    in.entry("fixtures", k);
    FixtureSlot& f = w.fixtures[k];
    at = in.offset();
    const uint8_t alive = in.u8("alive");
    check(alive <= 1, at, "alive", [&] { return " = " + std::to_string(alive) + ": must be 0 or 1"; });
    f.alive = alive == 1;
    f.generation = in.u32("generation");
    check(f.generation != 0, at + 1, "generation", [] { return " = 0: generations start at 1"; });
    if (!f.alive) {
      f.geometry = Point{};
      check(fixtureOwner[k] == 0, at, "alive", [] { return " = 0: a body lists it"; });
      continue;
    }
    at = in.offset();
    f.body = in.u32("body");
    check(f.body < bodyCount && fixtureOwner[k] == f.body + 1, at, "body",
          [&] { return " = " + std::to_string(f.body) + ": that body does not list this fixture"; });
    at = in.offset();
    Geometry g = readGeometry(in);
    if (auto error = validationError(g)) in.fail(at, "geometry", ": " + *error);
    f.geometry = normalized(g);
    f.localBox = boxOf(f.geometry);
    const BodySlot& b = w.bodies[f.body];
    check(inRange(f.localBox.translated(b.position)), at, "geometry",
          [] { return std::string(": its box reaches outside +-1e150 at its body's position"); });
    at = in.offset();
    f.density = in.f64("density");
    check(std::isfinite(f.density) && (b.type == BodyType::Dynamic ? f.density > 0 : f.density >= 0), at, "density",
          [&] { return " = " + detail::str(f.density) + ": must be finite and > 0 (>= 0 off a dynamic body)"; });
    at = in.offset();
    f.restitution = in.f64("restitution");
    check(std::isfinite(f.restitution) && f.restitution >= 0 && f.restitution <= 1, at, "restitution",
          [&] { return " = " + detail::str(f.restitution) + ": must be in [0, 1]"; });
    at = in.offset();
    const uint8_t sensor = in.u8("sensor");
    check(sensor <= 1, at, "sensor", [&] { return " = " + std::to_string(sensor) + ": must be 0 or 1"; });
    f.sensor = sensor == 1;
    f.filter.categoryBits = in.u32("filter.categoryBits");
    f.filter.maskBits = in.u32("filter.maskBits");
    f.filter.group = in.i32("filter.group");
    if (f.sensor) ++w.liveSensors;
  }
  in.entry(nullptr);
  for (uint32_t k = 0; k < fixtureCount; ++k) {
    check(fixtureOwner[k] == 0 || w.fixtures[k].alive, in.offset(), "fixture slots",
          [&] { return ": a body lists fixture " + std::to_string(k) + ", which is free"; });
  }
  std::vector<uint8_t> listedFreeFixture(fixtureCount, 0);
  const uint32_t freeFixtures = in.count("free fixture count", 4);
  uint32_t deadFixtures = 0;
  for (const FixtureSlot& f : w.fixtures) deadFixtures += f.alive ? 0 : 1;
  for (uint32_t k = 0; k < freeFixtures; ++k) {
    at = in.offset();
    const uint32_t f = in.u32("free fixture");
    check(f < fixtureCount && !w.fixtures[f].alive && !listedFreeFixture[f], at, "free fixture",
          [&] { return " = " + std::to_string(f) + ": not a free fixture slot, or listed twice"; });
    listedFreeFixture[f] = 1;
    w.freeFixtures.push_back(f);
  }
  check(freeFixtures == deadFixtures, in.offset(), "free fixture count",
        [&] { return " = " + std::to_string(freeFixtures) + ": every free fixture slot must be listed once"; });

  // What follows a body's fixtures: its mass, its disk shape, its place in the broad phase, and the rules
  // createFixture holds a dynamic body to (circles and points sharing one centre, a bounded mass).
  for (uint32_t i = 0; i < bodyCount; ++i) {
    BodySlot& b = w.bodies[i];
    if (!b.alive) continue;
    in.entry("bodies", i);
    if (b.type == BodyType::Dynamic) {
      std::optional<Vec2> centre;
      for (uint32_t f : b.fixtures) {
        const Geometry& g = w.fixtures[f].geometry;
        const Circle* c = std::get_if<Circle>(&g);
        const Point* p = std::get_if<Point>(&g);
        check(c || p, in.offset(), "fixtures",
              [&] { return ": fixture " + std::to_string(f) + " is not a circle or a point (a dynamic body's)"; });
        const Vec2 at2 = c ? c->center : p->position;
        check(!centre || *centre == at2, in.offset(), "fixtures",
              [&] { return ": fixture " + std::to_string(f) + "'s centre differs from the others'"; });
        centre = at2;
      }
      check(detail::physicalMass(w, b) <= kMaxMass, in.offset(), "fixtures",
            [] { return std::string(": their mass is more than 1e150 (World::kMaxMass)"); });
    }
    detail::recomputeMass(w, b);
    detail::refreshDiskShape(w, i);
    if (b.sliding) {
      const uint32_t s = b.support.fixture;
      check(s < fixtureCount && w.fixtures[s].alive && w.fixtures[s].generation == b.support.generation &&
                w.bodies[w.fixtures[s].body].type != BodyType::Dynamic && detail::isFlatFeature(w, s, b.support.feature),
            in.offset(), "support", [] { return std::string(": it slides, but not on a flat face of a fixture that cannot move"); });
    } else {
      check(b.support.generation == 0 || b.support.fixture < fixtureCount, in.offset(), "support.fixture",
            [&] { return " = " + std::to_string(b.support.fixture) + ": no such fixture slot"; });
    }
  }
  in.entry(nullptr);
  for (uint32_t k = 0; k < fixtureCount; ++k) {
    const FixtureSlot& f = w.fixtures[k];
    if (!f.alive) continue;
    w.broadPhase.add(k, w.worldBox(k), w.bodies[f.body].type != BodyType::Static, f.sensor, f.filter.categoryBits,
                     f.filter.maskBits);
  }

  const uint32_t overlaps = in.count("sensor overlap count", 12);
  for (uint32_t k = 0; k < overlaps; ++k) {
    in.entry("sensorOverlaps", k);
    at = in.offset();
    const uint64_t key = in.u64("key");
    const uint32_t sensor = static_cast<uint32_t>(key >> 32), visitor = static_cast<uint32_t>(key);
    check(sensor < fixtureCount && visitor < fixtureCount && w.fixtures[sensor].alive && w.fixtures[sensor].sensor &&
              w.fixtures[visitor].alive && !w.fixtures[visitor].sensor &&
              w.fixtures[sensor].body != w.fixtures[visitor].body,
          at, "key", [&] { return ": sensor " + std::to_string(sensor) + ", visitor " + std::to_string(visitor) +
                                  ": not a live sensor and a live physical fixture of another body"; });
    const uint32_t stamp = in.u32("stamp");
    check(w.sensorOverlaps.emplace(key, stamp).second, at, "key", [] { return std::string(": listed twice"); });
  }
  const uint32_t pending = in.count("pending sensor event count", 41);
  for (uint32_t k = 0; k < pending; ++k) {
    in.entry("pendingSensorEvents", k);
    SensorEvent e;
    at = in.offset();
    e.time = in.f64("time");
    check(std::isfinite(e.time), at, "time", [&] { return " = " + detail::str(e.time) + ": must be finite"; });
    e.sensor = {in.u32("sensor.index"), in.u32("sensor.generation")};
    e.sensorBody = {in.u32("sensorBody.index"), in.u32("sensorBody.generation")};
    e.visitor = {in.u32("visitor.index"), in.u32("visitor.generation")};
    e.visitorBody = {in.u32("visitorBody.index"), in.u32("visitorBody.generation")};
    at = in.offset();
    const uint8_t begin = in.u8("begin");
    check(begin <= 1, at, "begin", [&] { return " = " + std::to_string(begin) + ": must be 0 or 1"; });
    e.begin = begin == 1;
    w.pendingSensorEvents.push_back(e);
  }
  const uint32_t squeezes = in.count("squeeze count", 16);
  for (uint32_t k = 0; k < squeezes; ++k) {
    in.entry("squeezes", k);
    at = in.offset();
    detail::WorldState::Squeeze s{};
    s.key = in.u64("key");
    check(static_cast<uint32_t>(s.key >> 32) < fixtureCount && static_cast<uint32_t>(s.key) < fixtureCount, at, "key",
          [] { return std::string(": names no fixture slot"); });
    s.generationA = in.u32("generationA");
    s.generationB = in.u32("generationB");
    w.squeezes.push_back(s);
  }
  in.entry(nullptr);
  const uint32_t counted = in.count("squeeze-counted body count", 4);
  for (uint32_t k = 0; k < counted; ++k) {
    at = in.offset();
    const uint32_t i = in.u32("squeeze-counted body");
    check(i < bodyCount, at, "squeeze-counted body", [&] { return " = " + std::to_string(i) + ": no such body slot"; });
    w.squeezeCounted.push_back(i);
  }
  at = in.offset();
  const uint8_t hasIslands = in.u8("has islands");
  detail::Islands* islands = w.stepper->islands();
  check(hasIslands == (islands ? 1 : 0), at, "has islands",
        [&] { return " = " + std::to_string(hasIslands) + ": the mode's is " + (islands ? "1" : "0"); });
  if (islands) {
    islands->jamCounter = in.u32("jam counter");
    const uint32_t warm = in.count("warm start count", 16);
    for (uint32_t k = 0; k < warm; ++k) {
      in.entry("warmStart", k);
      const uint64_t key = in.u64("key");
      at = in.offset();
      const double impulse = in.f64("impulse");
      check(std::isfinite(impulse) && impulse >= 0, at, "impulse",
            [&] { return " = " + detail::str(impulse) + ": must be finite and >= 0"; });
      islands->islandNext.emplace_back(key, impulse);
    }
  }
  in.entry(nullptr);
  if (in.offset() != body.size()) {
    in.fail(in.offset(), "", std::to_string(body.size() - in.offset()) + " bytes after the last field");
  }
  // A body setVelocity drove before the save is driven in the first step too (World::step clears the
  // mark through touchedBodies). Every other change list starts as a new world's: all changed.
  for (uint32_t i = 0; i < bodyCount; ++i) {
    if (w.bodies[i].alive && w.bodies[i].driven) w.changes.touchedBodies.push_back(i);
  }
  return world;
}

}  // namespace rattle
