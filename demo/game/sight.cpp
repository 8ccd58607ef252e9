// Sight: an enemy is seen when it is inside a unit's sight sensor (kept up to date from the engine's
// sensor begin and end events, so no unit ever searches for its neighbours) and no wall is on the line
// between their centres (a ray cast, made only when the answer is needed: when a unit picks a target,
// or when a frame is drawn; never for every pair every tick).
#include <algorithm>
#include <cmath>

#include "game/game.h"

namespace rts {

void Game::onSight(const SensorChange& c) {
  if (c.sensor >= units_.size() || c.unit >= units_.size()) return;
  Unit& observer = units_[c.sensor];
  if (!observer.alive || !units_[c.unit].alive) return;  // already forgotten when it died
  if (c.begin) {
    observer.inSensor.push_back(c.unit);
  } else {
    std::erase(observer.inSensor, c.unit);
  }
}

bool Game::sees(uint32_t observer, uint32_t target) const {
  if (observer >= units_.size() || target >= units_.size()) return false;
  const Unit& o = units_[observer];
  const Unit& t = units_[target];
  if (!o.alive || !t.alive || o.team == t.team) return false;
  if (std::find(o.inSensor.begin(), o.inSensor.end(), target) == o.inSensor.end()) return false;
  return physics_.clearLine(o.position, t.position);
}

std::vector<uint8_t> Game::visibleTo(int team) const {
  std::vector<uint8_t> seen(units_.size(), 0);
  for (const Unit& u : units_) {
    if (!u.alive || u.team != team) continue;
    seen[u.id] = 1;
    for (uint32_t t : u.inSensor) {
      if (!seen[t] && units_[t].alive && physics_.clearLine(u.position, units_[t].position)) seen[t] = 1;
    }
  }
  return seen;
}

std::vector<Vec2> Game::sightOutline(const Unit& u, int rays) const {
  const double r = kUnitTypes[u.type].sight;
  std::vector<Vec2> out;
  out.reserve(size_t(rays));
  for (int i = 0; i < rays; ++i) {
    // Only for drawing: the angles need not be bit-identical across libm versions.
    const double a = 2 * 3.141592653589793 * double(i) / double(rays);
    const Vec2 d{std::cos(a) * r, std::sin(a) * r};
    out.push_back(u.position + d * physics_.wallFraction(u.position, d));
  }
  return out;
}

}  // namespace rts
