#include "tool/divergence.h"

#include <bit>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>

namespace rts::replay {
namespace {

constexpr int64_t kMaxUlpsShown = 1 << 20;

const char* teamName(int team) { return team == 0 ? "blue" : "red"; }

std::string exact(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

class Differ {
 public:
  explicit Differ(std::vector<FieldDiff>& out) : out_(out) {}
  void motion(const std::string& body, const MotionState& was, const MotionState& now) {
    real(body, "position.x", was.px, now.px);
    real(body, "position.y", was.py, now.py);
    real(body, "velocity.x", was.vx, now.vx);
    real(body, "velocity.y", was.vy, now.vy);
  }
  void real(const std::string& body, const char* field, double was, double now) {
    if (std::bit_cast<uint64_t>(was) == std::bit_cast<uint64_t>(now)) return;
    // The distance in ulps says "rounding" (a few) or "something else" (many): shown while it is small.
    char delta[80];
    const int64_t ulps = ulpDistance(was, now);
    if (ulps <= kMaxUlpsShown) {
      std::snprintf(delta, sizeof delta, "%+.3g, %" PRId64 " ulp%s", now - was, ulps, ulps == 1 ? "" : "s");
    } else {
      std::snprintf(delta, sizeof delta, "%+.3g", now - was);
    }
    out_.push_back({body, field, exact(was), exact(now), delta});
  }
  void integer(const std::string& body, const char* field, int64_t was, int64_t now) {
    if (was == now) return;
    char delta[40];
    std::snprintf(delta, sizeof delta, "%+" PRId64, now - was);
    out_.push_back({body, field, std::to_string(was), std::to_string(now), delta});
  }
  void flag(const std::string& body, const char* field, bool was, bool now) {
    if (was != now) out_.push_back({body, field, was ? "true" : "false", now ? "true" : "false", ""});
  }
  void presence(const std::string& body, bool inRecording) {
    out_.push_back({body, "exists", inRecording ? "yes" : "no", inRecording ? "no" : "yes", ""});
  }

 private:
  std::vector<FieldDiff>& out_;
};

}  // namespace

int64_t ulpDistance(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<int64_t>::max();
  // Map the bits onto a line where neighbouring doubles are neighbouring integers (-0 and +0 meet).
  auto ordered = [](double d) {
    const int64_t i = std::bit_cast<int64_t>(d);
    return i < 0 ? std::numeric_limits<int64_t>::min() - i : i;
  };
  const int64_t x = ordered(a), y = ordered(b);
  const uint64_t d = x > y ? uint64_t(x) - uint64_t(y) : uint64_t(y) - uint64_t(x);
  return d > uint64_t(std::numeric_limits<int64_t>::max()) ? std::numeric_limits<int64_t>::max() : int64_t(d);
}

std::string unitName(const Game& game, uint32_t id) {
  if (id < game.units().size()) return "unit " + std::to_string(id) + " (" + teamName(game.units()[id].team) + ")";
  return "unit " + std::to_string(id);
}

std::string gateName(const Game& game, size_t gate) {
  std::string name = "gate " + std::to_string(gate);
  if (gate < game.map().gates.size() && !game.map().gates[gate].name.empty()) name += " (" + game.map().gates[gate].name + ")";
  return name;
}

std::vector<std::string> digestDifferences(const Digests& recorded, const Digests& actual, const Game& game) {
  std::vector<std::string> out;
  if (recorded.counters != actual.counters) out.push_back("the game's counters");
  for (size_t i = 0; i < std::max(recorded.units.size(), actual.units.size()); ++i) {
    if (i >= recorded.units.size() || i >= actual.units.size() || recorded.units[i] != actual.units[i]) out.push_back(unitName(game, uint32_t(i)));
  }
  std::map<uint32_t, std::pair<int, int>> shots;  // id -> (recorded digest or -1, actual or -1)
  for (const ShotDigest& s : recorded.shots) shots[s.id] = {s.digest, -1};
  for (const ShotDigest& s : actual.shots) {
    auto it = shots.find(s.id);
    if (it == shots.end()) {
      shots[s.id] = {-1, s.digest};
    } else {
      it->second.second = s.digest;
    }
  }
  for (const auto& [id, d] : shots) {
    if (d.first == d.second) continue;
    std::string name = "shot " + std::to_string(id);
    if (d.first < 0) name += " (only in this run)";
    if (d.second < 0) name += " (only in the recording)";
    out.push_back(name);
  }
  for (size_t g = 0; g < std::max(recorded.gates.size(), actual.gates.size()); ++g) {
    if (g >= recorded.gates.size() || g >= actual.gates.size() || recorded.gates[g] != actual.gates[g]) out.push_back(gateName(game, g));
  }
  return out;
}

std::vector<FieldDiff> snapshotDifferences(const Snapshot& was, const Snapshot& now, const Game& game) {
  std::vector<FieldDiff> out;
  Differ d(out);
  const std::string counters = "counters";
  d.integer(counters, "shotsFired", was.counters.shotsFired, now.counters.shotsFired);
  d.integer(counters, "wallHits", was.counters.wallHits, now.counters.wallHits);
  d.integer(counters, "unitHits", was.counters.unitHits, now.counters.unitHits);
  d.integer(counters, "crossings", was.counters.crossings, now.counters.crossings);
  d.integer(counters, "losses[blue]", was.counters.losses[0], now.counters.losses[0]);
  d.integer(counters, "losses[red]", was.counters.losses[1], now.counters.losses[1]);
  for (size_t i = 0; i < std::min(was.counters.doorwayCrossings.size(), now.counters.doorwayCrossings.size()); ++i) {
    const std::string body = "doorway " + std::to_string(i);
    d.integer(body, "crossings[blue]", was.counters.doorwayCrossings[i][0], now.counters.doorwayCrossings[i][0]);
    d.integer(body, "crossings[red]", was.counters.doorwayCrossings[i][1], now.counters.doorwayCrossings[i][1]);
  }
  for (size_t i = 0; i < std::min(was.counters.roomHolders.size(), now.counters.roomHolders.size()); ++i) {
    d.integer("room " + std::to_string(i), "holder", was.counters.roomHolders[i], now.counters.roomHolders[i]);
  }
  for (size_t i = 0; i < std::max(was.units.size(), now.units.size()); ++i) {
    const std::string body = unitName(game, uint32_t(i));
    if (i >= was.units.size() || i >= now.units.size()) {
      d.presence(body, i < was.units.size());
      continue;
    }
    const UnitState &a = was.units[i], &b = now.units[i];
    d.flag(body, "alive", a.alive, b.alive);
    d.integer(body, "hitPoints", a.hitPoints, b.hitPoints);
    d.integer(body, "reloadTicks", a.reloadTicks, b.reloadTicks);
    if (a.alive && b.alive) {
      d.integer(body, "body.index", a.bodyIndex, b.bodyIndex);
      d.integer(body, "body.generation", a.bodyGeneration, b.bodyGeneration);
      d.motion(body, a.motion, b.motion);
      d.flag(body, "order.active", a.orderActive, b.orderActive);
      if (a.orderActive && b.orderActive) {
        d.real(body, "order.target.x", a.targetX, b.targetX);
        d.real(body, "order.target.y", a.targetY, b.targetY);
      }
    }
  }
  size_t i = 0, j = 0;
  while (i < was.shots.size() || j < now.shots.size()) {
    if (j >= now.shots.size() || (i < was.shots.size() && was.shots[i].id < now.shots[j].id)) {
      d.presence("shot " + std::to_string(was.shots[i].id) + " (" + teamName(was.shots[i].team) + ")", true);
      ++i;
    } else if (i >= was.shots.size() || now.shots[j].id < was.shots[i].id) {
      d.presence("shot " + std::to_string(now.shots[j].id) + " (" + teamName(now.shots[j].team) + ")", false);
      ++j;
    } else {
      const ShotState &a = was.shots[i++], &b = now.shots[j++];
      const std::string body = "shot " + std::to_string(a.id) + " (" + teamName(a.team) + ")";
      d.integer(body, "team", a.team, b.team);
      d.integer(body, "shooter", a.shooter, b.shooter);
      d.integer(body, "ticksLeft", a.ticksLeft, b.ticksLeft);
      d.integer(body, "body.index", a.bodyIndex, b.bodyIndex);
      d.integer(body, "body.generation", a.bodyGeneration, b.bodyGeneration);
      d.motion(body, a.motion, b.motion);
    }
  }
  for (size_t g = 0; g < std::min(was.gates.size(), now.gates.size()); ++g) {
    const std::string body = gateName(game, g);
    const GateBodyState &a = was.gates[g], &b = now.gates[g];
    d.flag(body, "wantOpen", a.wantOpen, b.wantOpen);
    d.real(body, "openness", a.openness, b.openness);
    d.motion(body, a.motion, b.motion);
  }
  return out;
}

}  // namespace rts::replay
