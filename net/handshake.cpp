// handshakeMismatch: whether two Hellos describe the same game, and if not, one line saying how.
#include <cstdio>

#include "net/protocol.h"

namespace rts::net {
namespace {

std::string hex64(uint64_t v) {
  char text[24];
  std::snprintf(text, sizeof text, "0x%016llx", static_cast<unsigned long long>(v));
  return text;
}

std::string quoted(const std::string& s) { return "\"" + s + "\""; }

std::string stepModeName(rattle::StepMode m) {
  switch (m) {
    case rattle::StepMode::Hybrid:
      return "hybrid";
    case rattle::StepMode::Discrete:
      return "discrete";
    case rattle::StepMode::Predictive:
      return "predictive";
  }
  return "step mode " + std::to_string(uint8_t(m));
}

std::string steeringName(Steering s) {
  switch (s) {
    case Steering::KeepApart:
      return "keep-apart";
    case Steering::Naive:
      return "naive";
  }
  return "steering " + std::to_string(uint8_t(s));
}

std::string teamName(uint8_t team) { return team == 0 ? "0 (blue)" : team == 1 ? "1 (red)" : std::to_string(team); }

class Differences {
 public:
  void add(const std::string& what, const std::string& mine, const std::string& theirs) {
    if (mine == theirs) return;
    note(what + ": mine " + mine + ", theirs " + theirs);
  }
  void note(const std::string& text) { line_ += (line_.empty() ? "" : "; ") + text; }
  std::optional<std::string> result() const {
    if (line_.empty()) return std::nullopt;
    return line_;
  }

 private:
  std::string line_;
};

}  // namespace

std::optional<std::string> handshakeMismatch(const Hello& mine, const Hello& theirs) {
  using std::to_string;
  Differences d;
  // In the order a person would fix them: a different build first, then a different game.
  d.add("protocol version", to_string(mine.protocolVersion), to_string(theirs.protocolVersion));
  d.add("engine version", quoted(mine.engineVersion), quoted(theirs.engineVersion));
  d.add("map digest", hex64(mine.mapDigest), hex64(theirs.mapDigest));
  d.add("seed", to_string(mine.seed), to_string(theirs.seed));
  d.add("units a team", to_string(mine.unitsPerTeam), to_string(theirs.unitsPerTeam));
  d.add("step mode", stepModeName(mine.stepMode), stepModeName(theirs.stepMode));
  d.add("steering", steeringName(mine.steering), steeringName(theirs.steering));
  d.add("ticks", to_string(mine.ticks), to_string(theirs.ticks));
  d.add("input delay", to_string(mine.inputDelayTicks) + " ticks", to_string(theirs.inputDelayTicks) + " ticks");
  d.add("hash interval", to_string(mine.hashIntervalTicks) + " ticks", to_string(theirs.hashIntervalTicks) + " ticks");
  if (mine.role == Role::Player && theirs.role == Role::Player && mine.team == theirs.team) {
    d.note("team: both players are on team " + teamName(mine.team));
  }
  // A spectator follows a player's game: two of them have no game to follow.
  if (mine.role == Role::Spectator && theirs.role == Role::Spectator) d.note("role: both sides are spectators");
  return d.result();
}

}  // namespace rts::net
