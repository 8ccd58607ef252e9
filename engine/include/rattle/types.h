// rattle: handles, definitions, events and statistics.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "rattle/geometry.h"
#include "rattle/vec2.h"

namespace rattle {

/// Thrown for invalid input: a definition, a value passed to a setter, a stale handle. The message names
/// the field and the value. Also thrown when memory runs out in a call that changes a World (a create,
/// a destroy, a setter, a step): "step: out of memory (the world is unchanged)". When it is thrown the
/// world is unchanged.
class Error : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// A body handle: a slot index and the slot's generation. Generation 0 is the null handle. When a body
/// is destroyed its slot's generation changes, so old handles to it are detected and rejected.
struct BodyId {
  uint32_t index = 0;
  uint32_t generation = 0;
  bool isNull() const { return generation == 0; }
  friend bool operator==(BodyId, BodyId) = default;
};

/// A fixture handle, like BodyId.
struct FixtureId {
  uint32_t index = 0;
  uint32_t generation = 0;
  bool isNull() const { return generation == 0; }
  friend bool operator==(FixtureId, FixtureId) = default;
};

enum class BodyType : uint8_t {
  Static,     ///< never moves; infinite mass
  Dynamic,    ///< moves, bounces; one circle or several circles sharing one centre
  Kinematic,  ///< moves with the velocity it is given, pushes dynamic bodies, is never pushed
};

/// How World::step advances time. All three use the same bodies, events and rules, but for resting and
/// the collapse guard (WorldDef::restingSpeed, WorldDef::collapseTime), which the discrete mode has not:
/// its bodies never sleep.
enum class StepMode : uint8_t {
  /// The default. Each step: swept boxes through sort-and-sweep, then exact times of impact inside the
  /// step, in time order. Nothing tunnels; a body may collide many times in one step. Sensor events are
  /// found after the step's collisions, exactly, along the paths the bodies took (one more sort-and-sweep
  /// per step when the world has sensors).
  Hybrid,
  /// Step-and-check, the cheap baseline: every body moves a whole step, then overlapping pairs found by
  /// sort-and-sweep are pushed apart and reflected, once per pair per step. Fast bodies can pass through
  /// thin walls and a body cannot collide twice in a step; sensors see only where bodies end a step
  /// (a change is reported at the step's end, but an overlap that held where the step began, as a body
  /// created inside a sensor, begins at time 0).
  Discrete,
  /// Event-driven throughout: every future collision is predicted exactly and kept in one queue; step(dt)
  /// just processes the events up to the new time. A cell grid with cell-crossing events and lazy
  /// per-body clocks keeps the cost per collision near log N, as in event-driven molecular dynamics.
  /// Sensor events are found as in the hybrid step, along the paths the bodies took.
  Predictive,
};

struct WorldDef {
  StepMode mode = StepMode::Hybrid;
  /// Acceleration of every awake dynamic body, world units per second squared. Kinematic bodies ignore
  /// it. Zero (the default) means straight paths and no parabolic solvers at all.
  Vec2 gravity;
  /// Under gravity, a contact that would leave a body bouncing off something that does not fall with it
  /// (a static or kinematic body, or a sleeping one) slower than this, in world units per second, ends
  /// the bouncing instead (see README, "Resting"), so a bouncing ball comes to rest in finitely many
  /// events: it sleeps when it is slow and held (the up direction lies between the normals of what it
  /// touches), slides along a flat static surface when it is still moving, and otherwise bounces off at
  /// this speed. A sleeping body is woken by a hit faster than this, by its support waking (or moving,
  /// for a point held in a cusp by an awake disk: docs/guide.md, "Squeezes"), or by a setter. In the
  /// hybrid mode, two moving bodies pressed together that would bounce off each other slower than this
  /// rest on each other instead, in a stepped island (README, "Gravity and resting"):
  /// their resting contacts are held by a solve once a step rather than by events, which lets a pile come
  /// to rest. Must be >= 0; 0 turns resting off. The hybrid and predictive modes only: the discrete mode
  /// has no resting, and its bodies never sleep.
  double restingSpeed = 0.01;
  /// Inelastic collapse guard (the TC model of Luding & McNamara, Granular Matter 1, 113, 1998): a contact
  /// of a body that already collided less than this many seconds ago is elastic (restitution 1). Dense
  /// clusters with restitution below 1 otherwise collide infinitely often in finite time (McNamara &
  /// Young 1992), like a row of disks on a floor. It never adds energy. Must be >= 0; 0 (the default)
  /// turns it off. The hybrid and predictive modes only: a discrete step resolves a pair once, with its
  /// fixtures' restitution.
  double collapseTime = 0;
  /// Collisions resolved in one step at most. When the next one would exceed it, at time t_b inside the
  /// step, every body stays where it was at t_l, the last instant before t_b at which a collision (or
  /// another event) changed a body's motion, for the rest of the step: the step then simulates only t_l
  /// seconds of motion, so nothing passes through anything and no body is left touching what it was about
  /// to meet. StepStats::eventBudgetReached says so.
  /// The predictive mode also stops there when it has taken 16 times this many events of any kind (cell
  /// crossings, stale predictions) from its queue, so that every step returns.
  int maxEventsPerStep = 1'000'000;
};

struct BodyDef {
  BodyType type = BodyType::Static;
  Vec2 position;          ///< world units
  Vec2 velocity;          ///< world units per second; must be zero for a static body
  uint64_t userData = 0;  ///< yours; never read by rattle
};

/// Which fixtures may touch. Two fixtures are tested against each other when each one's category is in
/// the other's mask, and they are not members of the same nonzero group (a group of things that never
/// meet, like a city's walls and trees).
struct Filter {
  uint32_t categoryBits = 0x0001;
  uint32_t maskBits = 0xFFFFFFFF;
  int32_t group = 0;
};

struct FixtureDef {
  Geometry geometry = Circle{};
  /// Mass per unit area. Must be > 0 on a dynamic body. Mass of a body = sum of density x area of its
  /// physical (non-sensor) fixtures; a dynamic body whose fixtures have no area (points) gets mass 1.
  double density = 1.0;
  /// Bounciness in [0, 1]: 1 keeps all the normal speed, 0 keeps none. Two fixtures that touch use the
  /// larger of their two restitutions.
  double restitution = 0.0;
  /// A sensor never changes motion; it is told when physical fixtures overlap it.
  bool sensor = false;
  Filter filter;
};

/// Which fixtures a query sees: a fixture is seen when its category is in the query's mask and the
/// query's category is in the fixture's mask. Sensors are skipped unless asked for.
struct QueryFilter {
  uint32_t categoryBits = 0x0001;
  uint32_t maskBits = 0xFFFFFFFF;
  bool includeSensors = false;
};

/// A ray-cast hit against a fixture in the world.
struct RayHit {
  FixtureId fixture;
  BodyId body;
  Vec2 point;
  Vec2 normal;          ///< unit, on the side the ray came from
  double fraction = 0;  ///< along the ray's translation, in [0, 1]
};

/// A physical fixture started or stopped overlapping a sensor fixture during a step.
struct SensorEvent {
  double time = 0;  ///< seconds from the start of the step, in [0, dt]
  FixtureId sensor;
  BodyId sensorBody;
  FixtureId visitor;  ///< the physical fixture
  BodyId visitorBody;
  bool begin = true;  ///< true: started overlapping; false: stopped
};

/// One collision resolved during a step.
struct ContactEvent {
  double time = 0;     ///< seconds from the start of the step, in [0, dt]
  FixtureId fixtureA;  ///< the fixture with the lower index of the two
  FixtureId fixtureB;
  BodyId bodyA;
  BodyId bodyB;
  Vec2 point;          ///< world position of the contact at `time`
  Vec2 normal;         ///< unit, from A toward B
  double impulse = 0;  ///< >= 0; B received impulse * normal, A received -impulse * normal
};

/// What one step did.
struct StepStats {
  int candidatePairs = 0;     ///< fixture pairs the broad phase handed to the narrow phase
  int timeOfImpactTests = 0;  ///< narrow-phase time-of-impact evaluations
  int eventsProcessed = 0;    ///< collisions resolved (a jam resolved at once: one per contact)
  int staleEvents = 0;        ///< predictions discarded because a body's motion changed first
  int requeries = 0;          ///< times a body's new path left its swept box and the broad phase was asked again
  int sleeping = 0;           ///< dynamic bodies asleep at the end of the step
  /// Contact rows the contact solves swept: each contact of a solved island once per sweep of its
  /// projected Gauss-Seidel (piles, jams; README, "Gravity and resting"). The work of holding pressed
  /// bodies, which no event counts: a pile stepped a whole second at a time solves thousands of
  /// speculative contacts in each of its solves.
  long long contactRowsSwept = 0;
  /// Squeezes this step: each time a dynamic body caught between bodies that do not yield was stopped
  /// along a contact and the kinematic body closing on it set to pass over it, each member of a crowd
  /// held by the contact solve that a kinematic body was set to pass over once no velocities met every
  /// contact, and each pair of dynamic bodies made overlapping deeply set to pass through each other
  /// until the steps' starts have moved it apart (README, "Squeezes"). It counts events, not bodies: one
  /// body squeezed against a wall by a piston counts about twice.
  int squeezes = 0;
  /// The step's next change of motion would have taken it past WorldDef::maxEventsPerStep: every body
  /// stopped at the last change of motion before it (WorldDef::maxEventsPerStep).
  bool eventBudgetReached = false;
};

}  // namespace rattle
