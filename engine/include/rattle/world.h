// rattle: the world. Create bodies and fixtures, step, read the events.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "rattle/types.h"

namespace rattle {

class World {
 public:
  /// Throws rattle::Error when the definition is invalid.
  explicit World(const WorldDef& def = {});
  ~World();
  /// A moved-from World holds nothing: every call on it but destruction and assignment throws
  /// rattle::Error.
  World(World&&) noexcept;
  World& operator=(World&&) noexcept;
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  /// Positions and fixtures' boxes must lie within +-kMaxCoordinate (creation and setPosition check it),
  /// so that the differences and products of coordinates the step forms stay finite.
  static constexpr double kMaxCoordinate = 1e150;
  /// Velocities (BodyDef::velocity, setVelocity) and WorldDef::gravity must be shorter than kMaxSpeed:
  /// the times of impact square speeds, and the square of a speed near 1.34e154 overflows a double.
  static constexpr double kMaxSpeed = 1.3e154;

  // Bodies. Every function taking a handle throws rattle::Error for a null or stale handle.
  BodyId createBody(const BodyDef& def);
  /// Destroys the body and its fixtures. Ids of destroyed bodies are reused (latest freed first).
  void destroyBody(BodyId body);
  bool isValid(BodyId body) const;
  BodyType type(BodyId body) const;
  Vec2 position(BodyId body) const;
  Vec2 velocity(BodyId body) const;
  double mass(BodyId body) const;  ///< infinity for static and kinematic bodies
  /// A dynamic body at rest (see WorldDef::restingSpeed): it does not move until something wakes it.
  bool isAsleep(BodyId body) const;
  /// Wakes a sleeping body (and the sleeping bodies it holds up). Setting a velocity or position does too.
  void wake(BodyId body);
  uint64_t userData(BodyId body) const;
  void setPosition(BodyId body, Vec2 position);
  /// Static bodies accept only zero. A dynamic body given a velocity is *driven* for the next step (a
  /// game steering it): without gravity, a cluster the game keeps driving into itself is held by the
  /// hybrid step's contact solve instead of endless collisions, and a body the solve leaves pressing
  /// into the cluster stops for that step (README, "Driven bodies").
  void setVelocity(BodyId body, Vec2 velocity);
  std::vector<FixtureId> fixtures(BodyId body) const;
  int bodyCount() const;

  // Fixtures.
  /// A circle's radius must be 0 (a point) or at least kMinRelativeRadius x max(1, |x|, |y|) of where its
  /// centre is when it is created: smaller circles could not be told from a point by the times of
  /// impact. Circles that small still collide head-on while their coordinates stay within that range.
  FixtureId createFixture(BodyId body, const FixtureDef& def);
  static constexpr double kMinRelativeRadius = 1e-12;
  /// A dynamic body's mass (the density x area of its physical fixtures) must be at most kMaxMass:
  /// creation and setDensity refuse a fixture or a density that would take it beyond, where its inverse
  /// mass loses its digits (it is subnormal near 1e308) and a collision's impulses overflow. A mass
  /// below kMinMass is taken as kMinMass: the inverse of a smaller one, times a distance, can overflow (a
  /// density of 4.9e-324 sent a disk to infinity when pushed apart in the discrete mode).
  static constexpr double kMaxMass = 1e150;
  static constexpr double kMinMass = 1e-150;
  void destroyFixture(FixtureId fixture);
  bool isValid(FixtureId fixture) const;
  BodyId body(FixtureId fixture) const;
  /// As stored: polygons wound counter-clockwise, coordinates relative to the body.
  const Geometry& geometry(FixtureId fixture) const;
  double density(FixtureId fixture) const;
  double restitution(FixtureId fixture) const;
  bool isSensor(FixtureId fixture) const;
  Filter filter(FixtureId fixture) const;
  void setDensity(FixtureId fixture, double density);
  void setRestitution(FixtureId fixture, double restitution);
  void setFilter(FixtureId fixture, const Filter& filter);

  /// Advances the world by dt seconds (finite, >= 0). When memory runs out part way, throws rattle::Error
  /// with the world as it was before the call: the bodies, the time, who sleeps and the sensors' overlaps
  /// (and no events: contactEvents() and sensorEvents() are empty until the next step). A save() then
  /// may differ from one made before the call in the step's own bookkeeping (a step counter, what the
  /// bodies last collided with in a step), which the next step sets afresh; stateHash() does not.
  void step(double dt);
  /// Advances the world to time t (>= time()); the same as step(t - time()).
  void advanceTo(double t);
  /// Seconds simulated since the world was made.
  double time() const;

  /// The collisions of the last step, ordered by time; events at the same instant come in the order they
  /// were resolved (by fixture ids, except where one collision causes the next at that instant).
  /// Valid until the next step.
  std::span<const ContactEvent> contactEvents() const;
  const StepStats& stats() const;

  /// Sensor begin and end events of the last step, ordered like contact events. A body created inside a
  /// sensor begins at time 0 of the next step; destroying a body or changing a filter ends its overlaps
  /// at once (sensorOverlaps forgets them) and reports the end events at time 0 of the next step, so
  /// begin and end events always pair up. Valid until the next step.
  std::span<const SensorEvent> sensorEvents() const;
  /// The physical fixtures overlapping a sensor now, by fixture index.
  std::vector<FixtureId> sensorOverlaps(FixtureId sensor) const;

  // Queries: the world as it stands between steps. Results are sorted (rays by fraction, then fixture
  // index; overlaps by fixture index), so they are the same on every run.
  std::optional<RayHit> rayCastFirst(Vec2 origin, Vec2 translation, const QueryFilter& filter = {}) const;
  std::vector<RayHit> rayCastAll(Vec2 origin, Vec2 translation, const QueryFilter& filter = {}) const;
  std::vector<FixtureId> overlapBox(const Box& box, const QueryFilter& filter = {}) const;
  std::vector<FixtureId> overlapCircle(Vec2 center, double radius, const QueryFilter& filter = {}) const;
  std::vector<FixtureId> overlapPoint(Vec2 point, const QueryFilter& filter = {}) const;

  /// A 64-bit hash of the exact bits of every live body's state (slot, generation, type, position,
  /// velocity) in index order, and of the world's time. Equal hashes at every step mean a replay matches.
  uint64_t stateHash() const;

  const WorldDef& definition() const;

  // Saving. A save holds the world's lasting state: every body and fixture (so handles stay valid), who
  // sleeps, the sensors' overlaps and the end events still to report, the squeezes and the contact
  // solve's warm start. Bytes, not text; the same on every machine (doubles as their bits).
  /// The world as bytes, between steps. The last step's events and stats are not in it.
  std::vector<uint8_t> save() const;
  /// A world from save()'s bytes, made by this version of rattle. Throws rattle::Error naming the byte
  /// and the field when the bytes are not such a save (a checksum catches bytes changed or cut short).
  /// The loaded world has no events until it steps. What the modes keep only for speed (the broad
  /// phase's order, the predictive mode's grid) is built anew, so two worlds loaded from one save step
  /// alike bit for bit, on every machine, but the saved world may part from them in the last bits:
  /// lockstep peers load together, at one tick (README, "Saving a world").
  static World load(std::span<const uint8_t> bytes);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  /// impl_, or rattle::Error when this World was moved from.
  /// (Like impl_ itself, it does not make the Impl const: const accessors share the Impl's lookups.)
  Impl& impl() const;
};

}  // namespace rattle
