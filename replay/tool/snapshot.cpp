#include "tool/snapshot.h"

namespace rts::replay {
namespace {

MotionState motionOf(Vec2 p, Vec2 v) { return {p.x, p.y, v.x, v.y}; }

}  // namespace

Snapshot snapshotOf(const Game& game) {
  Snapshot s;
  const GameStats& st = game.stats();
  s.counters.shotsFired = st.shotsFired;
  s.counters.wallHits = st.wallHits;
  s.counters.unitHits = st.unitHits;
  s.counters.crossings = st.crossings;
  s.counters.losses[0] = st.losses[0];
  s.counters.losses[1] = st.losses[1];
  for (const DoorwayState& d : game.doorways()) s.counters.doorwayCrossings.push_back({uint32_t(d.crossings[0]), uint32_t(d.crossings[1])});
  for (const RoomState& r : game.rooms()) s.counters.roomHolders.push_back(int8_t(r.holder));

  const rattle::World& world = game.physics().world();
  s.units.reserve(game.units().size());
  for (const Unit& u : game.units()) {
    UnitState x;
    x.alive = u.alive;
    x.hitPoints = u.hitPoints;
    x.reloadTicks = u.reloadTicks;
    if (u.alive) {
      x.orderActive = u.order.active;
      x.bodyIndex = u.body.index;
      x.bodyGeneration = u.body.generation;
      x.motion = motionOf(world.position(u.body), world.velocity(u.body));
      if (u.order.active) {
        x.targetX = u.order.target.x;
        x.targetY = u.order.target.y;
      }
    }
    s.units.push_back(x);
  }
  s.shots.reserve(game.shots().size());
  for (const Shot& sh : game.shots()) {
    ShotState x;
    x.id = sh.id;
    x.team = sh.team;
    x.shooter = sh.shooter;
    x.ticksLeft = sh.ticksLeft;
    x.bodyIndex = sh.body.index;
    x.bodyGeneration = sh.body.generation;
    x.motion = motionOf(world.position(sh.body), world.velocity(sh.body));
    s.shots.push_back(x);
  }
  for (size_t g = 0; g < game.gates().size(); ++g) {
    GateBodyState x;
    x.wantOpen = game.gates()[g].wantOpen;
    x.openness = game.gates()[g].openness;
    x.motion = motionOf(game.physics().gatePosition(g), game.physics().gateVelocity(g));
    s.gates.push_back(x);
  }
  return s;
}

ReplayConfig configOf(const Game& game) {
  ReplayConfig c;
  c.unitsPerTeam = uint32_t(game.config().unitsPerTeam);
  c.stepMode = uint8_t(game.config().stepMode);
  c.weapons = game.config().weapons;
  c.unitCount = uint32_t(game.units().size());
  c.gateCount = uint32_t(game.gates().size());
  c.doorwayCount = uint32_t(game.doorways().size());
  c.roomCount = uint32_t(game.rooms().size());
  return c;
}

}  // namespace rts::replay
