// Private: the world's state (bodies, fixtures, the broad phase, the squeezes, the step's results), a
// plain struct with a few inline accessors (a body's motion within a step, keep, advance). The World
// API (api/) creates, checks and reads it; contact/ and sensors/ serve the modes with free functions over it
// (contact/response.h, resting.h, squeeze.h, sensors/sensors.h); each mode's step (hybrid/,
// predictive/, discrete/) is a class of its own over it.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <unordered_map>
#include <vector>

#include "broad_phase/broad_phase.h"
#include "collision/polyline_impact.h"
#include "world/change_log.h"
#include "world/fixture_list.h"
#include "common/out_of_memory.h"
#include "world/path_log.h"
#include "rattle/time_of_impact.h"
#include "rattle/world.h"

namespace rattle {

namespace detail {

class Stepper;            // stepper.h

// The last collision a body took part in, within the current step. A pair that was resolved at an
// instant and whose bodies have done nothing since cannot be approaching at that instant; remembering it
// keeps round-off from reporting the same contact again at time zero.
struct LastContact {
  uint32_t fixtureLow = 0;
  uint32_t fixtureHigh = 0;
  int feature = -1;
  double time = -1;  // < 0: none this step
  /// Whether it was the contact of these two fixtures (in either order) at time t.
  bool is(uint32_t fa, uint32_t fb, double t) const {
    return time == t && fixtureLow == std::min(fa, fb) && fixtureHigh == std::max(fa, fb);
  }
};

// A body resting on a flat feature of a static fixture: it slides along it (no friction) with gravity's
// tangential part, and the feature is left out of its predictions until it slides off the end
// (BodySlot::sliding). When it is not sliding, a point (radius 0) keeps here the feature of a static or
// kinematic fixture that it last touched, and the side it touched it from (`normal`, toward the point): a
// point lying on a line has no overlap to tell its side, and this does (detail::resolvedFeature). Bodies
// do not turn, so the side holds as a kinematic body moves.
struct Support {
  uint32_t fixture = 0;
  uint32_t generation = 0;  // the fixture's: 0 names none
  int feature = -1;
  Vec2 normal;
};

struct alignas(64) BodySlot {
  // The step reads a body in its first pass and a candidate pair's two bodies in every prediction, and
  // the two bodies of a pair are rarely near each other in memory: what those read is in the first two
  // cache lines (the motion, the counter a prediction carries and the flags that decide whether a pair
  // is an event at all in the first), the rest after. Three whole lines: the hybrid step's passes over
  // every body read the first line of each, and a loop reading the first 64 bytes of 10^6 slots took
  // about 5 ms at a stride of 192 bytes, aligned, against 12 at 224 (where half the slots' first 64
  // bytes straddle two lines) on the bench's machine. The 224-byte slot held what is now
  // detail::WorldState::dependents and userData.
  Vec2 position;      // at localTime within the current step (0 between steps)
  Vec2 velocity;      // at localTime
  Vec2 acceleration;  // gravity when awake and free, its tangential part when sliding, else zero
  double localTime = 0;
  uint32_t collisionCount = 0;  // step-local: bumps on every velocity change; predictions carry it
  BodyType type = BodyType::Static;
  bool alive : 1 = false;
  bool asleep : 1 = false;
  // In a stepped island (island.cpp): its contacts with other stepped bodies and with what cannot move
  // are held by a solve once per step, and it moves along straight lines. Kept from step to step.
  bool stepped : 1 = false;
  // Stepped since the step's start (Islands::startIslands), its velocity before that step's gravity and
  // solve in WorldState::stepStartVelocity; a body that joins an island mid-step clears it
  // (Islands::joinIslands). Read only while `stepped`, so a stale value between steps is never read.
  bool steppedSinceStart : 1 = false;
  // The hybrid step's first pass reads only this line of a body whose state allows it; these three say
  // whether it does. `sliding`: `support` is the face it slides on (setSupport, clearSupport).
  bool sliding : 1 = false;
  // last or stepCollisions may differ from their values at a step's start (every write of them sets it:
  // setLast, countStepCollision, settleJam; the hybrid step's first pass resets them only then).
  bool stepLocalsSet : 1 = false;
  // detail::WorldState::diskShapes[this body] holds its one fixture that is not a sensor, a circle
  // centred on it (refreshDiskShape keeps it with the fixtures).
  bool diskShape : 1 = false;
  // World::setVelocity gave it a velocity since the last step: the game drives it (a unit steered each
  // tick). Without gravity only a cluster with a driven body (or one wedged against a static face in the
  // step) is held as a jam (jam.cpp); a gas's clusters stay exact events. World::step clears it.
  bool driven : 1 = false;
  // Its state at the step's start is in detail::WorldState::StepStart::bodies (detail::WorldState::keep).
  bool kept : 1 = false;
  LastContact last;  // step-local
  Support support;
  uint32_t generation = 1;
  int stepCollisions = 0;  // collisions in the current step, for the Zeno guard
  FixtureList fixtures;  // in place for up to four (fixture_list.h)
  double lastContactTime = -std::numeric_limits<double>::infinity();  // world time of its last collision
  double mass = std::numeric_limits<double>::infinity();
  double inverseMass = 0;

  void setSupport(const Support& s) {
    support = s;
    sliding = s.generation != 0;
  }
  // The support stays as the face last touched (a point's side of it, see Support).
  void clearSupport() { sliding = false; }
  void rememberFace(const Support& s) {
    if (!sliding) support = s;
  }
  void setLast(const LastContact& contact) {
    last = contact;
    stepLocalsSet = true;
  }
  /// Counts a collision in the current step (the jam and Zeno guards); returns the count.
  int countStepCollision() {
    stepLocalsSet = true;
    return ++stepCollisions;
  }
};

// A body's fixtures when the only one that is not a sensor is a circle centred on the body
// (BodySlot::diskShape): the hybrid step's first pass reads these 16 bytes in body order instead of the
// body's fixture list and its fixture's two lines, and a candidate pair of two plain disks reads them with
// the bodies' first lines instead of their fixtures.
struct DiskShape {
  double radius = 0;  // the circle's; its box relative to the body is exactly [-radius, radius]^2
  uint32_t fixture = 0;
  int32_t group = 0;  // its filter's collision group
};

struct FixtureSlot {
  // What a prediction reads of both fixtures (the geometry) and what the broad phase's candidate pairs
  // are filtered by (body, sensor, filter) share the first cache line: a pair's two fixtures are rarely
  // near each other in memory.
  Geometry geometry;
  uint32_t body = 0;
  uint32_t generation = 1;
  Filter filter;
  bool alive = false;
  bool sensor = false;
  Box localBox;  // box of the geometry relative to the body's position
  double density = 1;
  double restitution = 0;
};

static_assert(sizeof(BodySlot) == 192, "BodySlot: three whole cache lines");
static_assert(offsetof(BodySlot, last) == 64 && sizeof(Support) + sizeof(LastContact) <= 64 - 8,
              "BodySlot: the motion and flags in the first cache line, what predictions read next in the second");
static_assert(sizeof(Geometry) + offsetof(FixtureSlot, localBox) - offsetof(FixtureSlot, body) <= 64,
              "FixtureSlot: geometry, body, filter and flags in the first cache line");

enum class EventKind : uint8_t { Contact = 0, SlideEnd = 1 };

// A predicted event. Contact: `a` is the fixture whose body was moving forward (a dynamic circle), `b`
// the other one; `normal` points from b toward a. SlideEnd: `a` is a fixture of the sliding body, `b`
// its support.
struct PredictedContact {
  double time;
  EventKind kind;
  // Predicted again after the same pair's contact with another feature was dropped at `time` (the
  // hybrid step's events): a second such drop takes every feature touching then as separating.
  bool afterDismissal;
  uint32_t a, b;
  int feature;
  uint32_t countA, countB;
  Vec2 point;
  Vec2 normal;
};

static_assert(sizeof(PredictedContact) == 64, "PredictedContact: one cache line");

// Total order for the event queue: by time, then by fixture ids, then the rest, so no two distinct
// predictions compare equal and the processing order never depends on the heap's implementation.
inline bool later(const PredictedContact& x, const PredictedContact& y) {
  if (x.time != y.time) return x.time > y.time;
  if (x.kind != y.kind) return x.kind > y.kind;
  const uint32_t xl = std::min(x.a, x.b), yl = std::min(y.a, y.b);
  if (xl != yl) return xl > yl;
  const uint32_t xh = std::max(x.a, x.b), yh = std::max(y.a, y.b);
  if (xh != yh) return xh > yh;
  if (x.feature != y.feature) return x.feature > y.feature;
  if (x.a != y.a) return x.a > y.a;
  if (x.countA != y.countA) return x.countA > y.countA;
  return x.countB > y.countB;
}

struct CandidatePair {
  uint32_t own;  // a fixture of the body whose list this is
  uint32_t other;
};

// Key of a sensor overlap: the sensor fixture in the high half, the visitor in the low half.
inline uint64_t overlapKey(uint32_t sensor, uint32_t visitor) { return (uint64_t{sensor} << 32) | visitor; }

// Key of a pair of fixtures in either order (an island contact's warm start, a squeeze): the lower index
// in the high half.
inline uint64_t islandKey(uint32_t fa, uint32_t fb) { return (uint64_t{std::min(fa, fb)} << 32) | std::max(fa, fb); }

// The world's state: every body and fixture, the broad phase, the last step's results, and the squeezes
// (each mode's own state, the islands among it, is its stepper's, stepper.h). What the modes share is
// written as free functions over it, each in its module's header (engine/src/README.md says which
// folder holds which). World's pimpl derives from it (World::Impl below), so code outside World can
// name it.
struct WorldState;
/// Keeps the body's state as the step found it (step_undo.h; WorldState::keep calls it).
void keepBody(WorldState& w, uint32_t body);

struct WorldState {
  WorldDef def;
  double time = 0;
  detail::LargeArray<detail::BodySlot> bodies;
  // By body index, apart from the BodySlots (which the step streams): what World::createBody was given,
  // and the sleeping bodies each body holds up (may hold stale entries; resting.cpp).
  detail::LargeArray<uint64_t> userData;
  detail::LargeArray<std::vector<uint32_t>> dependents;
  detail::LargeArray<detail::DiskShape> diskShapes;  // where BodySlot::diskShape holds
  std::vector<uint32_t> freeBodies;  // reused last-freed first
  detail::LargeArray<detail::FixtureSlot> fixtures;
  // By fixture index, apart from the FixtureSlots (which predictions stream): a Segment's neighbours on
  // its body, which a point's time of impact reads (segment_neighbours.cpp). Derived, so not saved.
  detail::LargeArray<detail::SegmentNeighbours> segmentNeighbours;
  std::vector<uint32_t> freeFixtures;
  int liveBodies = 0;
  detail::BroadPhase broadPhase;

  // Results of the last step.
  std::vector<ContactEvent> contactEvents;
  std::vector<SensorEvent> sensorEvents;
  StepStats stats;

  // Step scratch, kept to reuse its memory.
  detail::LargeArray<std::vector<detail::CandidatePair>> pairsOfBody;  // by body index; dynamic bodies only
  /// By body: the velocity a body stepped since the step's start had then, before the step's gravity and
  /// its island's solve (BodySlot::steppedSinceStart): the parabola it began the step on
  /// (impactNormalVelocity reads it).
  std::vector<Vec2> stepStartVelocity;
  /// Points carried along a stepped body for the rest of the step, their gravity taken off
  /// (squeeze.cpp: carryPointInWedge); the step's end gives it back (restoreCarriedPoints).
  std::vector<uint32_t> carriedPoints;
  std::vector<uint32_t> supporters;

  detail::BodySlot& bodyOf(uint32_t fixture) { return bodies[fixtures[fixture].body]; }
  const detail::BodySlot& bodyOf(uint32_t fixture) const { return bodies[fixtures[fixture].body]; }
  /// The fixture on the other side of body `i`'s last contact (BodySlot::last, which must be set).
  uint32_t lastPartnerFixture(uint32_t i) const {
    const LastContact& l = bodies[i].last;
    return fixtures[l.fixtureLow].body == i ? l.fixtureHigh : l.fixtureLow;
  }
  bool moves(const detail::BodySlot& b) const { return b.type != BodyType::Static; }
  Box worldBox(uint32_t fixture) const { return fixtures[fixture].localBox.translated(bodyOf(fixture).position); }

  // Sensors: overlaps that hold now, keyed by overlapKey, with the step stamp of the last sweep that saw
  // the pair (an unordered map for membership only: anything read out of it is sorted first).
  std::unordered_map<uint64_t, uint32_t> sensorOverlaps;
  std::vector<SensorEvent> pendingSensorEvents;  // ends caused between steps, reported at time 0 of the next
  uint32_t stepStamp = 0;
  int liveSensors = 0;
  // What the World API changed since the last step (change_log.h).
  detail::ChangeLog changes;
  void touched(uint32_t body) { changes.touched(body, bodies[body].type); }
  void touched(const std::vector<uint32_t>& woken) {
    for (uint32_t body : woken) touched(body);
  }
  // The paths bodies take through a step, recorded when the world has sensors: both the hybrid and the
  // predictive mode find sensor events from them once the step's collisions are done (sensor_paths.cpp).
  detail::PathLog pathLog;
  /// Records a body's motion from `now` on, after it changed.
  void recordPath(uint32_t body, double now) {
    if (pathLog.active) {
      const detail::BodySlot& b = bodies[body];
      pathLog.record(body, {now, positionAt(b, now), velocityAt(b, now), b.acceleration});
    }
  }

  // Motion inside a step: a parabola from the body's local time (a straight line without gravity).
  Vec2 positionAt(const detail::BodySlot& b, double t) const {
    const double h = t - b.localTime;
    return b.position + b.velocity * h + b.acceleration * (0.5 * h * h);
  }
  Vec2 velocityAt(const detail::BodySlot& b, double t) const { return b.velocity + b.acceleration * (t - b.localTime); }

  // The mode's stepper (stepper.h), made from def.mode when the world is made.
  std::unique_ptr<detail::Stepper> stepper;

  /// Moves a dynamic body's clock to t within a step: every change of a body within a step starts here,
  /// or says so (step_undo.cpp). Kinematic paths are evaluated from the step's start.
  void advance(detail::BodySlot& b, double t) {
    if (b.type != BodyType::Dynamic) return;
    keep(b);
    moveTo(b, t);
  }
  /// advance's motion alone: the body's clock moves to t (for the last pass, which keeps nothing).
  void moveTo(detail::BodySlot& b, double t) const {
    b.position = positionAt(b, t);
    b.velocity = velocityAt(b, t);
    b.localTime = t;
  }

  /// The broad phase's pair-test budget for one sweep (BroadPhase::setPairTestBudget): kPairTestsPerFixture
  /// a fixture, plus the event budget. Sort-and-sweep tests a few pairs a box in any world whose bodies
  /// do not pile up on each other (the bench's gas: under 4); bodies created on one point test every
  /// pair, N^2 / 2 (10^10 at 10^5 bodies), and a step that reaches the budget moves nothing instead.
  static constexpr size_t kPairTestsPerFixture = 256;
  size_t pairTestBudget() const {
    return kPairTestsPerFixture * fixtures.size() + static_cast<size_t>(def.maxEventsPerStep);
  }

  // squeeze.cpp: a dynamic body caught between bodies that do not yield.
  static constexpr int kSqueezeCollisions = 64;
  struct Squeeze {
    uint64_t key;  // islandKey of the dynamic body's fixture and the kinematic fixture passing over it
    uint32_t generationA, generationB;  // of the lower and the higher fixture index
  };
  std::vector<Squeeze> squeezes;  // exempt pairs, in the order they were squeezed
  /// The keys of squeezes[0, covered), sorted, so that asking whether a pair is exempt does not read every
  /// squeeze: a crowd made to overlap (units spawned at one point) exempts most of its pairs, and every
  /// prediction asks. The entries from `covered` on are read one by one, and merged in past
  /// kSqueezeIndexTail. Not valid (every entry read one by one) after an undone step or a load, until
  /// the next step's start sorts it again (squeeze.cpp).
  struct SqueezeIndex {
    std::vector<uint64_t> sorted;
    size_t covered = 0;
    bool valid = false;
  };
  static constexpr size_t kSqueezeIndexTail = 64;
  SqueezeIndex squeezeIndex;
  /// Bodies in a pair that this step's start parts (separateExemptPairs), sorted: they do not sleep, or a
  /// pile of units made at one point fell asleep on one another, parted by a fraction of their overlap.
  std::vector<uint32_t> beingParted;
  std::vector<uint32_t> squeezeCounted;  // bodies whose stepCollisions squeezeAt raised from 0 this step
  /// Bodies wedged between static faces this step: the instant and the normal of the last face they were
  /// stopped against (squeezeAt). Few: only bodies past kSqueezeCollisions.
  struct Wedged {
    uint32_t body;
    double time;
    Vec2 normal;
  };
  std::vector<Wedged> wedged;
  /// Bodies past kSqueezeCollisions bounced off a static face this step at an instant other than their
  /// last collision's: that instant and the face's normal, so that a second face met at the same
  /// instant corners them as a stop would (squeezeAt).
  std::vector<Wedged> bouncedOffStatic;
  /// Sleepers held by an awake body, (sleeper, holder) in order: a point put to sleep caught between a
  /// stepped body at rest and a face (squeeze.cpp). They wake when the holder moves
  /// (wakeSleepersOfMovingBodies); a holder that sleeps holds them as any sleeper does. Derived from the
  /// bodies and dependents (findSleepersOnAwakeBodies), so not saved.
  std::vector<std::pair<uint32_t, uint32_t>> sleepersOnAwakeBodies;

  // What a step changes of the world's lasting state, kept from its start (step_undo.cpp): when memory
  // runs out inside a step it is put back, so that World::step throws rattle::Error with the world
  // unchanged. Everything else a step changes is scratch, or a cache that undoStep marks void.
  struct BodyAtStepStart {
    uint32_t body;
    Vec2 position, velocity, acceleration;
    double localTime;  // 0, but where the predictive mode's clocks are rebased at the next step's start
    detail::Support support;
    double lastContactTime;
    bool asleep, stepped, sliding;
  };
  struct SensorOverlapChange {
    uint64_t key;
    std::unordered_map<uint64_t, uint32_t>::node_type ended;  // the entry an end took out; empty: a begin
  };
  struct StepStart {
    bool active = false;  // inside World::step: the changes below are being logged
    // The hybrid and predictive steps keep a body when they first change it (keep), until their last
    // pass, after which nothing fails (`keeping`); the discrete step keeps every moving body's motion as
    // it moves it (`motion`, by body index).
    bool keepEach = false;
    bool keeping = false;
    std::vector<std::pair<Vec2, Vec2>> motion;
    double time = 0;
    StepStats stats;
    std::vector<BodyAtStepStart> bodies;  // those keep kept, in the order kept
    std::vector<SensorEvent> pendingSensorEvents;
    std::vector<Squeeze> squeezes;
    std::vector<std::pair<uint32_t, uint32_t>> sleepersOnAwakeBodies;
    std::vector<SensorOverlapChange> sensorOverlaps;  // in the order they were made
    std::vector<std::pair<uint32_t, std::vector<uint32_t>>> dependents;  // lists wakeUp emptied, in order
  };
  StepStart stepStart;
  /// Keeps the body's state as the step found it, before the hybrid or predictive step first changes it.
  void keep(detail::BodySlot& b) {
    if (b.kept || !stepStart.keeping) return;
    keepBody(*this, static_cast<uint32_t>(&b - &bodies[0]));
  }
  void keep(uint32_t body) { keep(bodies[body]); }
};

// world_state.cpp: the rules of the world's state that the API and the modes share.
/// Two fixtures of different bodies, neither a sensor, at least one body dynamic, and the filters let
/// them meet.
bool canCollide(const WorldState& w, uint32_t fa, uint32_t fb);
/// One is a sensor, the other a physical fixture of another body, and the filters let them meet.
bool canSense(const WorldState& w, uint32_t fa, uint32_t fb);
/// The density x area of the body's physical fixtures (0 when none has area).
double physicalMass(const WorldState& w, const BodySlot& body);
/// The body's mass and inverse mass from its fixtures (infinite for a static or kinematic body).
void recomputeMass(WorldState& w, BodySlot& body);
/// BodySlot::diskShape and diskShapes[body] from the body's fixtures; after every change of them or of
/// their filters.
void refreshDiskShape(WorldState& w, uint32_t body);

// segment_neighbours.cpp: the Segments of a body that meet end to end.
/// segmentNeighbours of Segment `segment` and of every other Segment of `body` with an end at one of its
/// ends: after a Segment fixture joined the body's list, or left it (its own entry is then cleared).
void refreshSegmentNeighboursAround(WorldState& w, uint32_t body, uint32_t segment);
/// segmentNeighbours of every fixture, from the bodies' lists (World::load).
void findSegmentNeighbours(WorldState& w);

}  // namespace detail

struct World::Impl : detail::WorldState {};

}  // namespace rattle
