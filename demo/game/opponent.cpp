// How the opponent thinks: each team splits its units into squads (runs of ids) and every few seconds a
// squad that has nothing to do, or now and then one that has, is sent to a room: one the team does not
// hold if there is one, or out into the field. Both teams draw from one generator in a fixed order.
#include "game/opponent.h"

#include <algorithm>
#include <cmath>

#include "game/game.h"

namespace rts {
namespace {

constexpr uint32_t kThinkTicks = 45;  // each team thinks every 1.5 s, the two teams half a period apart

// A random point inside a room: a random mix of its corners pulled toward its middle, so it stays well
// inside whatever the room's shape (convex, so any mix of corners is inside).
Vec2 pointInRoom(Rng& rng, const MapRoom& room) {
  Vec2 c{0, 0};
  for (Vec2 p : room.polygon) c += p;
  c = c * (1.0 / double(room.polygon.size()));
  const Vec2 corner = room.polygon[rng.below(uint32_t(room.polygon.size()))];
  return c + (corner - c) * rng.between(0.0, 0.6);
}

}  // namespace

void ScriptedOpponent::commandsFor(uint32_t tick, const Game& game, std::vector<Command>& out) {
  const Map& map = game.map();
  for (int team = 0; team < 2; ++team) {
    if (!(teams_ >> team & 1)) continue;
    if ((tick + uint32_t(team) * kThinkTicks / 2) % kThinkTicks != 0) continue;
    const int alive = game.alive(team);
    if (alive == 0) continue;
    const int squads = std::clamp(alive / 12, 1, 8);
    std::vector<std::vector<uint32_t>> members(static_cast<size_t>(squads));
    std::vector<int> idle(static_cast<size_t>(squads), 0);
    // Squads are runs of consecutive ids: units were placed nearest to their spawn point first, so a
    // run of ids stands together, and a squad sent somewhere does not have to cross its neighbours.
    int k = 0;
    for (const Unit& u : game.units()) {
      if (!u.alive || u.team != team) continue;
      const size_t s = size_t(int64_t(k++) * squads / alive);
      members[s].push_back(u.id);
      idle[s] += !u.order.active;
    }
    for (int s = 0; s < squads; ++s) {
      const bool mostlyIdle = idle[size_t(s)] * 2 > int(members[size_t(s)].size());
      if (!(mostlyIdle || rng_.chance(1, 6)) || members[size_t(s)].empty()) continue;
      Command c;
      c.tick = tick;
      c.team = uint8_t(team);
      c.type = CommandType::Move;
      c.units = members[size_t(s)];
      // Rooms the team does not hold alone are worth taking; sometimes go out into the field instead.
      std::vector<size_t> wanted;
      for (size_t r = 0; r < map.rooms.size(); ++r) {
        if (game.rooms()[r].holder != team) wanted.push_back(r);
      }
      if (!wanted.empty() && !rng_.chance(1, 4)) {
        c.target = pointInRoom(rng_, map.rooms[wanted[rng_.below(uint32_t(wanted.size()))]]);
      } else {
        c.target = {rng_.between(0.1, 0.9) * map.width, rng_.between(0.1, 0.9) * map.height};
      }
      out.push_back(std::move(c));
    }
    // Now and then, work a gate.
    if (!map.gates.empty() && rng_.chance(1, 8)) {
      Command c;
      c.tick = tick;
      c.team = uint8_t(team);
      c.type = CommandType::ToggleGate;
      c.gate = rng_.below(uint32_t(map.gates.size()));
      out.push_back(std::move(c));
    }
  }
}

}  // namespace rts
