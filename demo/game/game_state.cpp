// A game's state between ticks as bytes (Game::saveState, Game::restoreState): what a spectator starts
// from (net/README.md, "Spectators").
//
// It holds everything a tick reads that the map and the config do not give: the tick, every unit (its
// order, the flow field's key, what it touched, who is in its sight, which doorways it stands in), the
// shots, the impacts, the doorways', rooms' and gates' states, the counters, a ReloadWorld still to apply,
// and the world (rattle::World::save). A unit's flow field is kept as its key (target cell, gates, layer):
// a field is a function of those alone, so the restored game asks Navigation for an equal one. What a
// tick rebuilds before it reads it (the unit grid) and the engine's timings are not kept.
//
// Format (the replay format's primitives, replay/FORMAT.md): "RTSG", u32 version, u32 tick, flag
// reload pending, the units (as many as the game has), the shots, the spent shots, the next shot id,
// the impacts, the doorways, rooms and gates (as many as the map has), the counters, and the world's
// bytes. restoreState reads it all into new values, checks every id, body and count against this game,
// and only then takes them; a bad state leaves the game as it was.
#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
#include <string>

#include "format/byte_reader.h"
#include "format/byte_writer.h"
#include "game/game.h"

namespace rts {
namespace {

constexpr char kMagic[4] = {'R', 'T', 'S', 'G'};
constexpr uint32_t kStateVersion = 1;
constexpr int64_t kCountLimit = int64_t{1} << 62;  // counters and tick counts: any value a game reaches

using replay::ByteReader;
using replay::ByteWriter;

void writeVec(ByteWriter& out, Vec2 v) {
  out.f64(v.x);
  out.f64(v.y);
}
// Every vector of a state within a limit: places within placeLimit of the origin, speeds, normals and the
// like within kMotionLimit. A hostile state of finite but huge values would otherwise overflow the
// game's arithmetic (squares, sums of distances) into infinities and NaNs; within these no product in the
// game comes near overflowing.
constexpr double kMotionLimit = 1e4;
// The map and as far again around it: nothing in a game goes further (walls hold units; shots are spent
// on walls or run out of range).
double placeLimit(const Map& map) { return 2 * std::max(map.width, map.height) + 100; }
Vec2 readVec(ByteReader& in, const std::string& field, double limit) {
  const size_t at = in.offset();
  const double x = in.finite(field + ".x");
  const double y = in.finite(field + ".y");
  if (std::fabs(x) > limit || std::fabs(y) > limit) {
    in.failAt(at, field, "(" + std::to_string(x) + ", " + std::to_string(y) + ") is beyond +-" + std::to_string(limit));
  }
  return {x, y};
}
double readBounded(ByteReader& in, const std::string& field, double lo, double hi) {
  const size_t at = in.offset();
  const double v = in.finite(field);
  if (v < lo || v > hi)
    in.failAt(at, field, std::to_string(v) + " is not in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return v;
}
void writeBody(ByteWriter& out, rattle::BodyId b) {
  out.u32(b.index);
  out.u32(b.generation);
}
rattle::BodyId readBody(ByteReader& in, const std::string& field) {
  const uint32_t index = in.u32(field + ".index");
  return {index, in.u32(field + ".generation")};
}

void writeShot(ByteWriter& out, const Shot& s) {
  out.varint(s.id);
  out.varint(s.team);
  out.varint(s.type);
  out.u8(s.alive ? 1 : 0);
  out.varint(s.shooter);
  writeBody(out, s.body);
  writeVec(out, s.position);
  writeVec(out, s.velocity);
  writeVec(out, s.previous);
  out.zigzag(s.ticksLeft);
}

Shot readShot(ByteReader& in, const std::string& f, size_t unitCount, double place) {
  Shot s;
  s.id = uint32_t(in.varint(f + ".id", 0, UINT32_MAX));
  s.team = uint8_t(in.varint(f + ".team", 0, 1));
  s.type = uint8_t(in.varint(f + ".type", 0, kUnitTypes.size() - 1));
  s.alive = in.flag(f + ".alive");
  s.shooter = uint32_t(in.varint(f + ".shooter", 0, unitCount > 0 ? unitCount - 1 : 0));
  s.body = readBody(in, f + ".body");
  s.position = readVec(in, f + ".position", place);
  s.velocity = readVec(in, f + ".velocity", kMotionLimit);
  s.previous = readVec(in, f + ".previous", place);
  s.ticksLeft = int(in.zigzag(f + ".ticksLeft", -1'000'000, 1'000'000));
  return s;
}

// A flow field as a state keeps it: a field is a function of these alone (Navigation::fieldForCell).
struct FieldKey {
  int cell;
  uint32_t gates;
  int layer;
};

// What a unit's fields are checked against: the game's sizes and the limits above.
struct UnitLimits {
  size_t cells;  // Navigation's
  int layers;
  double place;
  size_t unitCount;
  size_t doorwayCount;
};

// Reads unit i into u, which holds this game's unit i (its team and type must be the state's); returns
// its order's flow field, when it has one.
std::optional<FieldKey> readUnit(ByteReader& in, Unit& u, size_t i, const UnitLimits& l) {
  std::optional<FieldKey> field;
  const std::string f = "units[" + std::to_string(i) + "]";
  const size_t at = in.offset();
  const uint64_t team = in.varint(f + ".team", 0, 1), type = in.varint(f + ".type", 0, 255);
  if (team != u.team || type != u.type) {
    in.failAt(at, f + ".team",
              "team " + std::to_string(team) + ", type " + std::to_string(type) + ": this game's unit " +
                  std::to_string(i) + " is of team " + std::to_string(u.team) + ", type " + std::to_string(u.type));
  }
  u.alive = in.flag(f + ".alive");
  u.hitPoints = int(in.zigzag(f + ".hitPoints", -1'000'000, 1'000'000));
  u.reloadTicks = int(in.zigzag(f + ".reloadTicks", -1'000'000, 1'000'000));
  u.body = readBody(in, f + ".body");
  u.position = readVec(in, f + ".position", l.place);
  u.previous = readVec(in, f + ".previous", l.place);
  u.velocity = readVec(in, f + ".velocity", kMotionLimit);
  Order& o = u.order;
  o = Order{};
  o.active = in.flag(f + ".order.active");
  o.target = readVec(in, f + ".order.target", l.place);
  o.arrivalRadius = readBounded(in, f + ".order.arrivalRadius", 0, l.place);
  if (in.flag(f + ".order.field")) {
    FieldKey key;
    key.cell = int(in.varint(f + ".order.field.cell", 0, l.cells > 0 ? l.cells - 1 : 0));
    key.gates = in.u32(f + ".order.field.gates");
    key.layer = int(in.varint(f + ".order.field.layer", 0, uint64_t(l.layers - 1)));
    field = key;
  } else if (o.active) {
    in.failAt(in.offset() - 1, f + ".order.field", "an order under way has a flow field");
  }
  const size_t bestAt = in.offset();
  o.bestDistance = in.f64(f + ".order.bestDistance");
  if (!(o.bestDistance >= 0)) in.failAt(bestAt, f + ".order.bestDistance", "must be >= 0 (or infinity)");
  o.stuckTicks = int(in.zigzag(f + ".order.stuckTicks", 0, 1'000'000'000));
  o.stuckSpells = int(in.zigzag(f + ".order.stuckSpells", 0, 1'000'000'000));
  for (size_t k = 0; k < u.touches.size(); ++k) {
    const std::string t = f + ".touches[" + std::to_string(k) + "]";
    u.touches[k].normal = readVec(in, t + ".normal", kMotionLimit);
    u.touches[k].ticksLeft = int(in.zigzag(t + ".ticksLeft", -1'000'000, 1'000'000));
  }
  u.makeWay = readVec(in, f + ".makeWay", kMotionLimit);
  u.inSensor.resize(in.count(f + ".inSensor count", 1, l.unitCount));
  for (uint32_t& id : u.inSensor) id = uint32_t(in.varint(f + ".inSensor", 0, l.unitCount - 1));
  u.doorways.resize(in.count(f + ".doorways count", 2, l.doorwayCount));
  for (Unit::DoorTouch& d : u.doorways) {
    d.doorway = uint32_t(in.varint(f + ".doorways.doorway", 0, l.doorwayCount == 0 ? 0 : l.doorwayCount - 1));
    d.entrySide = int8_t(in.zigzag(f + ".doorways.entrySide", -128, 127));
  }
  return field;
}

}  // namespace

std::string Game::saveState() const {
  ByteWriter out;
  out.bytes(std::string_view(kMagic, 4));
  out.u32(kStateVersion);
  out.u32(tick_);
  out.u8(reloadPending_ ? 1 : 0);
  out.varint(units_.size());
  for (const Unit& u : units_) {
    out.varint(u.team);
    out.varint(u.type);
    out.u8(u.alive ? 1 : 0);
    out.zigzag(u.hitPoints);
    out.zigzag(u.reloadTicks);
    writeBody(out, u.body);
    writeVec(out, u.position);
    writeVec(out, u.previous);
    writeVec(out, u.velocity);
    const Order& o = u.order;
    out.u8(o.active ? 1 : 0);
    writeVec(out, o.target);
    out.f64(o.arrivalRadius);
    out.u8(o.field ? 1 : 0);
    if (o.field) {
      out.varint(uint64_t(o.field->targetCell));
      out.u32(o.field->gatesOpen);
      out.varint(uint64_t(o.field->layer));
    }
    out.f64(o.bestDistance);
    out.zigzag(o.stuckTicks);
    out.zigzag(o.stuckSpells);
    for (const Unit::Touch& t : u.touches) {
      writeVec(out, t.normal);
      out.zigzag(t.ticksLeft);
    }
    writeVec(out, u.makeWay);
    out.varint(u.inSensor.size());
    for (uint32_t id : u.inSensor) out.varint(id);
    out.varint(u.doorways.size());
    for (const Unit::DoorTouch& d : u.doorways) {
      out.varint(d.doorway);
      out.zigzag(d.entrySide);
    }
  }
  for (const std::vector<Shot>* list : {&shots_, &spentShots_}) {
    out.varint(list->size());
    for (const Shot& s : *list) writeShot(out, s);
  }
  out.varint(nextShotId_);
  out.varint(impacts_.size());
  for (const Impact& i : impacts_) {
    writeVec(out, i.point);
    out.u32(i.tick);
    out.u8(i.wall ? 1 : 0);
  }
  for (const DoorwayState& d : doorways_) {
    out.zigzag(d.crossings[0]);
    out.zigzag(d.crossings[1]);
    out.zigzag(d.lastCrossTick);
    out.zigzag(d.lastCrossTeam);
  }
  for (const RoomState& r : rooms_) {
    out.zigzag(r.inside[0]);
    out.zigzag(r.inside[1]);
    out.zigzag(r.holder);
  }
  for (const GateState& g : gates_) {
    out.u8(g.wantOpen ? 1 : 0);
    out.u32(g.nextToggleTick);
    out.f64(g.openness);
    out.zigzag(g.toggles);
  }
  for (long v : {stats_.shotsFired, stats_.wallHits, stats_.unitHits, stats_.losses[0], stats_.losses[1],
                 stats_.crossings, stats_.commandsApplied, stats_.commandsIgnored, stats_.eventBudgetSteps}) {
    out.zigzag(v);
  }
  const std::vector<uint8_t> world = physics_.saveWorld();
  out.varint(world.size());
  out.bytes(std::string_view(reinterpret_cast<const char*>(world.data()), world.size()));
  return std::move(out.data());
}

void Game::restoreState(std::string_view bytes) {
  // Everything into new values first; the game changes only once all of it is checked.
  std::vector<Unit> units = units_;
  std::vector<Shot> shots, spent;
  std::vector<Impact> impacts;
  std::vector<DoorwayState> doorways(doorways_.size());
  std::vector<RoomState> rooms(rooms_.size());
  std::vector<GateState> gates(gates_.size());
  GameStats stats;
  uint32_t tick = 0, nextShotId = 0;
  bool reloadPending = false;
  std::vector<std::optional<FieldKey>> fields(units.size());
  std::optional<rattle::World> world;
  try {
    ByteReader in(bytes, 0);
    if (in.bytes("magic", std::min<size_t>(4, in.remaining())) != std::string_view(kMagic, 4)) {
      in.failAt(0, "magic", "not a game's state (it does not start with \"RTSG\")");
    }
    const uint32_t version = in.u32("version");
    if (version != kStateVersion) {
      in.failAt(4, "version", std::to_string(version) + ": this build reads version " + std::to_string(kStateVersion));
    }
    tick = in.u32("tick");
    reloadPending = in.flag("reload pending");
    const size_t unitAt = in.offset();
    const size_t unitCount = in.count("unit count", 60, units.size());
    if (unitCount != units.size()) {
      in.failAt(unitAt, "unit count", std::to_string(unitCount) + ": this game has " + std::to_string(units.size()));
    }
    const double place = placeLimit(map_);
    const UnitLimits limits{size_t(navigation_.cellCount()), navigation_.layers(), place, units.size(),
                            doorways.size()};
    for (size_t i = 0; i < units.size(); ++i) fields[i] = readUnit(in, units[i], i, limits);
    for (std::vector<Shot>* list : {&shots, &spent}) {
      const char* name = list == &shots ? "shots" : "spentShots";
      list->resize(in.count(std::string(name) + " count", 40, SIZE_MAX));
      for (size_t k = 0; k < list->size(); ++k) {
        const size_t at = in.offset();
        const std::string f = std::string(name) + "[" + std::to_string(k) + "]";
        (*list)[k] = readShot(in, f, units.size(), place);
        if (list == &shots && (!(*list)[k].alive || (k > 0 && (*list)[k].id <= (*list)[k - 1].id))) {
          in.failAt(at, f, "live shots are alive and in ascending id order");
        }
      }
    }
    const size_t nextAt = in.offset();
    nextShotId = uint32_t(in.varint("nextShotId", 0, UINT32_MAX));
    if (!shots.empty() && nextShotId <= shots.back().id) {
      in.failAt(nextAt, "nextShotId",
                std::to_string(nextShotId) + ": a live shot has id " + std::to_string(shots.back().id));
    }
    impacts.resize(in.count("impact count", 21, SIZE_MAX));
    for (Impact& i : impacts) {
      i.point = readVec(in, "impacts.point", place);
      i.tick = in.u32("impacts.tick");
      i.wall = in.flag("impacts.wall");
    }
    for (DoorwayState& d : doorways) {
      d.crossings[0] = int(in.zigzag("doorways.crossings", 0, INT32_MAX));
      d.crossings[1] = int(in.zigzag("doorways.crossings", 0, INT32_MAX));
      d.lastCrossTick = int(in.zigzag("doorways.lastCrossTick", INT32_MIN, INT32_MAX));
      d.lastCrossTeam = int(in.zigzag("doorways.lastCrossTeam", 0, 1));
    }
    for (RoomState& r : rooms) {
      r.inside[0] = int(in.zigzag("rooms.inside", 0, INT32_MAX));
      r.inside[1] = int(in.zigzag("rooms.inside", 0, INT32_MAX));
      r.holder = int(in.zigzag("rooms.holder", -1, 2));
    }
    for (GateState& g : gates) {
      g.wantOpen = in.flag("gates.wantOpen");
      g.nextToggleTick = in.u32("gates.nextToggleTick");
      const size_t at = in.offset();
      g.openness = in.finite("gates.openness");
      if (g.openness < 0 || g.openness > 1)
        in.failAt(at, "gates.openness", std::to_string(g.openness) + ": not in [0, 1]");
      g.toggles = int(in.zigzag("gates.toggles", 0, INT32_MAX));
    }
    for (long* v : {&stats.shotsFired, &stats.wallHits, &stats.unitHits, &stats.losses[0], &stats.losses[1],
                    &stats.crossings, &stats.commandsApplied, &stats.commandsIgnored, &stats.eventBudgetSteps}) {
      *v = long(in.zigzag("stats", 0, kCountLimit));
    }
    const size_t worldSize = in.count("world size", 1, SIZE_MAX);
    const size_t worldAt = in.offset();
    const std::string_view worldBytes = in.bytes("world", worldSize);
    in.expectEnd("the game's state");
    try {
      world.emplace(
          rattle::World::load(std::span(reinterpret_cast<const uint8_t*>(worldBytes.data()), worldBytes.size())));
    } catch (const rattle::Error& e) {
      in.failAt(worldAt, "world", e.what());
    }
  } catch (const replay::FormatError& e) {
    throw GameError("game state: byte " + std::to_string(e.offset()) + ": " + e.field() + ": " + e.what());
  }

  std::vector<std::pair<rattle::BodyId, uint32_t>> unitBodies, shotBodies;
  for (const Unit& u : units) {
    if (u.alive) unitBodies.push_back({u.body, u.id});
  }
  for (const Shot& s : shots) shotBodies.push_back({s.body, s.id});
  try {
    physics_.adopt(std::move(*world), unitBodies, shotBodies, placeLimit(map_), kMotionLimit);
  } catch (const GameError& e) {
    throw GameError(std::string("game state: ") + e.what());
  }
  // Taken: from here on nothing fails but for memory.
  for (size_t i = 0; i < units.size(); ++i) {
    if (fields[i]) {
      units[i].order.field = navigation_.fieldForCell(fields[i]->cell, fields[i]->gates, tick, fields[i]->layer);
    }
  }
  units_ = std::move(units);
  shots_ = std::move(shots);
  spentShots_ = std::move(spent);
  impacts_ = std::move(impacts);
  doorways_ = std::move(doorways);
  rooms_ = std::move(rooms);
  gates_ = std::move(gates);
  stats_ = std::move(stats);
  tick_ = tick;
  nextShotId_ = nextShotId;
  reloadPending_ = reloadPending;
  aliveCount_ = {0, 0};
  for (const Unit& u : units_) aliveCount_[u.team & 1] += u.alive ? 1 : 0;
}

}  // namespace rts
