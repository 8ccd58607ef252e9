// Construction, commands, and the order of the rules within one tick.
#include "game/game.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace rts {
namespace {

uint64_t mix(uint64_t h, uint64_t v) {
  h ^= v + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
  return h * 0xFF51AFD7ED558CCDull;
}
uint64_t bitsOf(double d) { return std::bit_cast<uint64_t>(d); }

// A cell is walkable for a unit when its centre is this far from every wall: the unit's radius, and
// more than half a cell, so that no wall line (walls may be thin) can pass between two walkable
// neighbours.
double clearance(const UnitType& type) { return std::max(0.6, type.radius); }

// The clearances the configured unit types need, one navigation layer each, in order of first use.
std::vector<double> clearances(const GameConfig& config) {
  if (config.unitTypes.empty()) throw GameError("unit types: none given; expected at least one");
  std::vector<double> out;
  for (uint8_t t : config.unitTypes) {
    if (t >= kUnitTypes.size()) {
      throw GameError("unit types: " + std::to_string(t) + ": expected 0 to " + std::to_string(kUnitTypes.size() - 1));
    }
    if (std::find(out.begin(), out.end(), clearance(kUnitTypes[t])) == out.end()) out.push_back(clearance(kUnitTypes[t]));
  }
  return out;
}

}  // namespace

Game::Game(Map map, const GameConfig& config)
    : map_(std::move(map)),
      config_(config),
      physics_(map_, config.stepMode),
      navigation_(map_, physics_, clearances(config_)) {
  if (config_.unitsPerTeam < 0 || config_.unitsPerTeam > 1'000'000) {
    throw GameError("units per team = " + std::to_string(config_.unitsPerTeam) + ": expected 0 to 1000000");
  }
  const std::vector<double> layers = clearances(config_);
  for (size_t t = 0; t < kUnitTypes.size(); ++t) {
    const auto at = std::find(layers.begin(), layers.end(), clearance(kUnitTypes[t]));
    navigationLayer_[t] = at == layers.end() ? 0 : int(at - layers.begin());  // 0 for a type no unit has
  }
  doorways_.resize(map_.doorways.size());
  rooms_.resize(map_.rooms.size());
  gates_.resize(map_.gates.size());
  for (size_t g = 0; g < gates_.size(); ++g) {
    if (map_.gates[g].period > 0) gates_[g].nextToggleTick = uint32_t(std::lround(map_.gates[g].period * kTicksPerSecond));
  }
  placeUnits();
  updateRooms();
}

Game::~Game() = default;

bool Game::apply(const Command& c) {
  bool applied = false;
  if (c.team <= 1) {
    switch (c.type) {
      case CommandType::Move: {
        if (!std::isfinite(c.target.x) || !std::isfinite(c.target.y)) break;
        // Keep targets on the map: a click outside it means "as far as you can go that way".
        Vec2 target{std::clamp(c.target.x, 0.0, map_.width), std::clamp(c.target.y, 0.0, map_.height)};
        int count = 0;
        double radius = 0;
        for (uint32_t id : c.units) {
          if (id < units_.size() && units_[id].alive && units_[id].team == c.team) {
            ++count;
            radius = std::max(radius, kUnitTypes[units_[id].type].radius);
          }
        }
        if (count == 0) break;
        // A group stops when it is about as close as a packed crowd of its size (of its largest units)
        // can get.
        const double arrival = radius * (1.5 + 1.1 * std::sqrt(double(count)));
        // One flow field for the whole group, or one for each clearance its unit types need.
        std::vector<std::shared_ptr<const FlowField>> fields(size_t(navigation_.layers()));
        for (uint32_t id : c.units) {
          if (id >= units_.size() || !units_[id].alive || units_[id].team != c.team) continue;
          const int layer = navigationLayer_[units_[id].type];
          if (!fields[size_t(layer)]) fields[size_t(layer)] = navigation_.field(target, gatesOpen(), tick_, layer);
          orderMove(units_[id], target, arrival, fields[size_t(layer)]);
        }
        applied = true;
        break;
      }
      case CommandType::Stop:
        for (uint32_t id : c.units) {
          if (id < units_.size() && units_[id].alive && units_[id].team == c.team) {
            units_[id].order = Order{};
            applied = true;
          }
        }
        break;
      case CommandType::ToggleGate:
        if (c.gate < gates_.size()) {
          toggleGate(c.gate);
          applied = true;
        }
        break;
      case CommandType::ReloadWorld:
        reloadPending_ = true;
        applied = true;
        break;
    }
  }
  ++(applied ? stats_.commandsApplied : stats_.commandsIgnored);
  return applied;
}

void Game::tick() {
  // 0. The world as a spectator loads it from this state (commands.h, ReloadWorld).
  if (reloadPending_) {
    physics_.reload();
    reloadPending_ = false;
  }
  // 1. Decide: gates move, units steer and fire, all from the state at the end of the last tick.
  driveGates();
  steer();
  fireWeapons();

  // 2. The engine moves everything and reports what touched what.
  for (Unit& u : units_) u.previous = u.position;
  for (Shot& s : shots_) s.previous = s.position;
  const StepEvents& events = physics_.step(kTickSeconds);
  stats_.stepSeconds.push_back(physics_.lastStepSeconds());
  stats_.stepCpuSeconds.push_back(physics_.lastStepCpuSeconds());
  stats_.stepCollisions.push_back(physics_.lastStepStats().eventsProcessed);
  stats_.stepImpactTests.push_back(physics_.lastStepStats().timeOfImpactTests);
  if (physics_.lastStepStats().eventBudgetReached) ++stats_.eventBudgetSteps;
  ++tick_;

  // 3. Read the new state and apply the events, in the engine's order.
  for (Unit& u : units_) {
    if (!u.alive) continue;
    u.position = physics_.position(u.body);
    u.velocity = physics_.velocity(u.body);
  }
  for (Shot& s : shots_) {
    s.position = physics_.position(s.body);
    s.velocity = physics_.velocity(s.body);
  }
  for (const ShotContact& c : events.shotContacts) onShotContact(c);
  for (const UnitContact& c : events.unitContacts) onBump(c);
  for (const SensorChange& c : events.sight) onSight(c);
  for (const SensorChange& c : events.doorways) onDoorway(c);
  expireShots();
  removeDead();
  updateRooms();
  std::erase_if(impacts_, [&](const Impact& i) { return i.tick + 12 < tick_; });
}

void Game::removeDead() {
  for (Unit& u : units_) {
    if (u.alive && u.hitPoints <= 0) {
      u.alive = false;
      --aliveCount_[u.team];
      ++stats_.losses[u.team];
      physics_.remove(u.body);
      u.order = Order{};
      u.inSensor.clear();
      u.doorways.clear();
    }
  }
  spentShots_.clear();
  for (Shot& s : shots_) {
    if (s.alive) continue;
    physics_.remove(s.body);
    spentShots_.push_back(s);
  }
  std::erase_if(shots_, [](const Shot& s) { return !s.alive; });
}

std::vector<Vec2> Game::gateOutline(size_t g) const {
  std::vector<Vec2> out = map_.gates[g].polygon;
  Vec2 at = physics_.gatePosition(g);
  for (Vec2& p : out) p += at;
  return out;
}

uint64_t Game::stateHash() const {
  uint64_t h = mix(physics_.stateHash(), tick_);
  for (const Unit& u : units_) {
    h = mix(h, uint64_t(u.alive) | uint64_t(u.hitPoints) << 8 | uint64_t(uint32_t(u.reloadTicks)) << 32);
    if (!u.alive) continue;
    h = mix(h, u.order.active ? bitsOf(u.order.target.x) ^ (bitsOf(u.order.target.y) << 1) : 0);
  }
  for (const Shot& s : shots_) h = mix(h, uint64_t(s.id) << 16 | uint64_t(uint32_t(s.ticksLeft)));
  for (const DoorwayState& d : doorways_) h = mix(h, uint64_t(uint32_t(d.crossings[0])) << 32 | uint32_t(d.crossings[1]));
  for (const RoomState& r : rooms_) h = mix(h, uint64_t(uint32_t(r.holder)));
  for (const GateState& g : gates_) h = mix(h, uint64_t(g.wantOpen) ^ bitsOf(g.openness));
  h = mix(h, uint64_t(stats_.shotsFired) ^ uint64_t(stats_.wallHits) << 20 ^ uint64_t(stats_.unitHits) << 40);
  return h;
}

}  // namespace rts
