// Projectiles: small fast disks. A projectile covers several wall thicknesses per tick, so only an
// engine that finds the exact time of impact inside the step stops it at a wall; rattle does, and the
// contact event says where. A projectile is removed on its first contact: with a wall (a wall hit) or
// with an enemy (a hit, one hit point).
#include <algorithm>
#include <cmath>

#include "game/game.h"

namespace rts {

void Game::fireWeapons() {
  if (!config_.weapons) return;
  for (Unit& u : units_) {
    if (!u.alive) continue;
    if (u.reloadTicks > 0) {
      --u.reloadTicks;
      continue;
    }
    // Forget the dead, then try the nearest few enemies in the sensor until one is in line of sight.
    std::erase_if(u.inSensor, [&](uint32_t t) { return !units_[t].alive; });
    if (u.inSensor.empty()) continue;
    uint32_t candidates[3];
    int count = 0;
    for (uint32_t t : u.inSensor) {
      // Insertion into a sorted top three, by distance and then id, so the choice never depends on
      // the order the sensor events came in.
      const double d = lengthSquared(units_[t].position - u.position);
      int at = count;
      while (at > 0) {
        const uint32_t o = candidates[at - 1];
        const double od = lengthSquared(units_[o].position - u.position);
        if (od < d || (od == d && o < t)) break;
        --at;
      }
      if (at >= 3) continue;
      for (int k = std::min(count, 2); k > at; --k) candidates[k] = candidates[k - 1];
      candidates[at] = t;
      count = std::min(count + 1, 3);
    }
    bool fired = false;
    for (int k = 0; k < count && !fired; ++k) {
      if (physics_.clearLine(u.position, units_[candidates[k]].position)) {
        fire(u, units_[candidates[k]]);
        fired = true;
      }
    }
    // Nothing in line of sight: look again in a few ticks rather than every tick.
    u.reloadTicks = fired ? int(std::lround(kUnitTypes[u.type].reload * kTicksPerSecond)) : 4;
  }
}

void Game::fire(Unit& shooter, const Unit& target) {
  const UnitType& type = kUnitTypes[shooter.type];
  ++stats_.shotsFired;
  const Vec2 offset = target.position - shooter.position;
  const double distance = rattle::length(offset);
  const double muzzle = type.radius + type.shotRadius + 0.02;
  if (distance <= muzzle + kUnitTypes[target.type].radius + type.shotRadius) {
    // Point blank: the projectile would start inside the target. It hits at once.
    ++stats_.unitHits;
    damage(units_[target.id]);
    return;
  }
  const Vec2 dir = offset * (1.0 / distance);
  Shot s;
  s.id = nextShotId_++;
  s.team = shooter.team;
  s.type = shooter.type;
  s.shooter = shooter.id;
  s.position = shooter.position + dir * muzzle;
  s.velocity = dir * type.shotSpeed;
  s.ticksLeft = int(std::ceil(type.range / (type.shotSpeed * kTickSeconds)));
  s.body = physics_.addShot(s.id, s.team, s.position, s.velocity, type.shotRadius);
  shots_.push_back(s);
}

void Game::damage(Unit& target) {
  if (target.alive) --target.hitPoints;
}

void Game::onShotContact(const ShotContact& c) {
  // Shots are kept in id order, so a binary search finds one.
  auto it = std::lower_bound(shots_.begin(), shots_.end(), c.shot, [](const Shot& s, uint32_t id) { return s.id < id; });
  if (it == shots_.end() || it->id != c.shot || !it->alive) return;  // already spent this step
  it->alive = false;
  if (c.other == Tag::Unit) {
    if (c.otherId < units_.size()) {
      ++stats_.unitHits;
      damage(units_[c.otherId]);
    }
    impacts_.push_back({c.point, tick_, false});
  } else {
    ++stats_.wallHits;
    impacts_.push_back({c.point, tick_, true});
  }
}

void Game::expireShots() {
  for (Shot& s : shots_) {
    if (!s.alive) continue;
    const bool off = s.position.x < -1 || s.position.y < -1 || s.position.x > map_.width + 1 || s.position.y > map_.height + 1;
    if (--s.ticksLeft <= 0 || off) s.alive = false;
  }
}

}  // namespace rts
