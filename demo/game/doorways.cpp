// Doorways, rooms and gates.
//
// A doorway is a sensor segment across an opening. A unit crosses it when it touches the segment from
// one side and lets go of it on the other: the begin event records the side the unit came from (its
// position before the step, when it was not yet touching), the end event compares with the side it is
// on now. A unit that steps in and back out is not counted.
//
// A room is a polygon; each tick the game counts the unit centres inside it (updateRooms).
//
// A gate is a kinematic body that slides between its closed and open positions, on a timer and on
// command. It waits to close while a unit stands in the opening, so it never crushes anyone.
#include <algorithm>
#include <cmath>

#include "game/game.h"

namespace rts {
namespace {

int sideOf(const MapDoorway& d, Vec2 p) { return rattle::cross(d.b - d.a, p - d.a) > 0 ? 1 : -1; }

}  // namespace

void Game::onDoorway(const SensorChange& c) {
  if (c.sensor >= doorways_.size() || c.unit >= units_.size()) return;
  Unit& u = units_[c.unit];
  if (!u.alive) return;
  const MapDoorway& d = map_.doorways[c.sensor];
  if (c.begin) {
    u.doorways.push_back({c.sensor, int8_t(sideOf(d, u.previous))});
    return;
  }
  auto it = std::find_if(u.doorways.begin(), u.doorways.end(), [&](const Unit::DoorTouch& t) { return t.doorway == c.sensor; });
  if (it == u.doorways.end()) return;
  const int entry = it->entrySide;
  u.doorways.erase(it);
  if (sideOf(d, u.position) != entry) {
    DoorwayState& s = doorways_[c.sensor];
    ++s.crossings[u.team];
    s.lastCrossTick = int(tick_);
    s.lastCrossTeam = u.team;
    ++stats_.crossings;
  }
}

// Units touching a room's sensor from outside its wall overlap it too; a unit is inside when its
// centre is.
// A room counts the units whose centres are inside it, so the game asks where each centre is rather
// than keeping a sensor per room in the engine: a room's sensor tested every moving unit in its box
// against its polygon every step, a fifth of the engine's step in a 10,000-unit crowd, to answer a
// question a point-in-polygon test per unit answers outright.
void Game::updateRooms() {
  for (RoomState& s : rooms_) s.inside = {0, 0};
  for (const Unit& u : units_) {
    if (!u.alive) continue;
    const int r = navigation_.roomAt(u.position);
    if (r >= 0) ++rooms_[size_t(r)].inside[u.team];
  }
  for (RoomState& s : rooms_) s.holder = s.inside[0] > 0 ? (s.inside[1] > 0 ? 2 : 0) : (s.inside[1] > 0 ? 1 : -1);
}

void Game::toggleGate(size_t g) {
  gates_[g].wantOpen = !gates_[g].wantOpen;
  ++gates_[g].toggles;
}

uint32_t Game::gatesOpen() const {
  uint32_t open = 0;
  for (size_t g = 0; g < gates_.size() && g < 32; ++g) open |= uint32_t(gates_[g].openness > 0.99) << g;
  return open;
}

void Game::driveGates() {
  for (size_t g = 0; g < gates_.size(); ++g) {
    const MapGate& m = map_.gates[g];
    GateState& s = gates_[g];
    if (s.nextToggleTick > 0 && tick_ >= s.nextToggleTick) {
      toggleGate(g);
      s.nextToggleTick = tick_ + uint32_t(std::max(1l, std::lround(m.period * kTicksPerSecond)));
    }
    const Vec2 at = physics_.gatePosition(g);
    const Vec2 goal = m.origin + (s.wantOpen ? m.openOffset : Vec2{0, 0});
    const Vec2 left = goal - at;
    const double distance = rattle::length(left);
    const double stepLength = m.speed * kTickSeconds;
    if (distance < 1e-9) {
      // Land exactly, whatever round-off the steps left.
      if (distance > 0 || physics_.gateVelocity(g) != Vec2{0, 0}) physics_.placeGate(g, goal);
    } else {
      bool wait = false;
      if (!s.wantOpen) {
        // Closing: wait while a unit stands in the opening (the closed footprint, a little inside it).
        rattle::Box box{{1e300, 1e300}, {-1e300, -1e300}};
        for (Vec2 p : m.polygon) {
          box.min = {std::min(box.min.x, m.origin.x + p.x), std::min(box.min.y, m.origin.y + p.y)};
          box.max = {std::max(box.max.x, m.origin.x + p.x), std::max(box.max.y, m.origin.y + p.y)};
        }
        box.min += Vec2{0.05, 0.05};
        box.max -= Vec2{0.05, 0.05};
        wait = physics_.anyUnitIn(box);
      }
      // The last step lands on the goal: velocity = what is left over one tick.
      const Vec2 v = wait ? Vec2{0, 0} : (distance <= stepLength ? left * (1.0 / kTickSeconds) : left * (m.speed / distance));
      physics_.moveGate(g, v);
    }
    s.openness = std::clamp(rattle::dot(at - m.origin, m.openOffset) / lengthSquared(m.openOffset), 0.0, 1.0);
  }
}

}  // namespace rts
