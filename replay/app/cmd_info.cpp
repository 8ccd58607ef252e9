// rattle-replay info FILE [--commands]
#include <cstdio>
#include <filesystem>

#include "app/cli.h"
#include "map/printable.h"
#include "tool/verify.h"

namespace rts::replay::cli {
namespace {

const char* kHelp =
    "usage: rattle-replay info FILE [--commands]\n"
    "\n"
    "Prints what a replay holds: the map (name, size, hash), the game (units per team, step mode, seed, who\n"
    "played), the ticks, the commands by type, the keyframes, the first and last state hashes, and the\n"
    "build that recorded it. Reads the file only; plays nothing.\n"
    "\n"
    "  --commands   also list every command, one a line, as a command script would write it\n"
    "               (TICK move TEAM X Y IDS, TICK stop TEAM IDS, TICK gate TEAM GATE, TICK reload TEAM)\n"
    "  --help       this text\n"
    "\n"
    "Exit status: 0, or 2 when FILE is not a valid replay (the message gives the byte offset and field).\n";

const char* modeName(uint8_t m) { return m == 0 ? "hybrid" : m == 1 ? "discrete" : "predictive"; }
const char* teamName(int t) { return t == 0 ? "blue" : "red"; }

std::string played(uint8_t teams) {
  switch (teams & 3) {
    case 0: return "nobody";
    case 1: return "blue";
    case 2: return "red";
    default: return "blue and red";
  }
}

}  // namespace

int runInfo(const std::vector<std::string>& args) {
  std::string file;
  bool listCommands = false;
  for (const std::string& a : args) {
    if (a == "--help" || a == "-h") {
      std::fputs(kHelp, stdout);
      return kOk;
    } else if (a == "--commands") {
      listCommands = true;
    } else if (!a.empty() && a[0] == '-') {
      return usageError("info", "unknown option '" + a + "'");
    } else if (file.empty()) {
      file = a;
    } else {
      return usageError("info", "one FILE only ('" + a + "' is a second)");
    }
  }
  if (file.empty()) return usageError("info", "expected a replay FILE");
  std::optional<Replay> loaded = loadReplay("info", file);
  if (!loaded) return kBadInput;
  const Replay& r = *loaded;
  const ReplayConfig& c = r.config;
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(file, ec);
  size_t moves = 0, stops = 0, gates = 0, reloads = 0;
  for (const TickRecord& t : r.ticks) {
    for (const Command& cmd : t.commands) {
      moves += cmd.type == CommandType::Move;
      stops += cmd.type == CommandType::Stop;
      gates += cmd.type == CommandType::ToggleGate;
      reloads += cmd.type == CommandType::ReloadWorld;
    }
  }
  std::printf("replay    %s (%llu bytes, format version %u)\n", file.c_str(), static_cast<unsigned long long>(ec ? 0 : bytes), r.version);
  std::printf("map       %s (%zu bytes embedded, FNV-1a %s)\n", printable(r.mapName).c_str(), r.mapJson.size(), hex64(r.mapHash).c_str());
  std::printf("game      %u units per team, %s step mode, weapons %s, %u gates, %u doorways, %u rooms\n", c.unitsPerTeam, modeName(c.stepMode),
              c.weapons ? "on" : "off", c.gateCount, c.doorwayCount, c.roomCount);
  if (c.opponentTeams & 3) {
    std::printf("played by the scripted opponent for %s (seed %llu); recorded by %s\n", played(c.opponentTeams).c_str(),
                static_cast<unsigned long long>(c.seed), printable(c.recordedBy).c_str());
  } else {
    std::printf("played by commands from a script or a person only; recorded by %s\n", printable(c.recordedBy).c_str());
  }
  std::printf("ticks     %u (%.1f s of game time at 30 ticks a second)\n", r.tickCount(), r.tickCount() / 30.0);
  std::printf("commands  %zu (%zu move, %zu stop, %zu gate, %zu reload)\n", r.commandCount(), moves, stops, gates,
              reloads);
  std::printf("keyframes %zu (every %u ticks, and the last tick)\n", r.keyframes.size(), c.keyframeEvery);
  const Snapshot& last = r.keyframes.back().state;  // the reader guarantees one at the last tick
  int alive[2] = {0, 0};
  for (size_t u = 0; u < last.units.size(); ++u) alive[u % 2] += last.units[u].alive;  // ids alternate blue, red
  std::printf("at the end blue %d, red %d units; %lld shots (%lld hit walls, %lld hit units); %lld doorway crossings\n", alive[0], alive[1],
              static_cast<long long>(last.counters.shotsFired), static_cast<long long>(last.counters.wallHits),
              static_cast<long long>(last.counters.unitHits), static_cast<long long>(last.counters.crossings));
  std::printf("hashes    tick 0 %s, tick %u %s\n", hex64(r.initialStateHash).c_str(), r.tickCount(),
              hex64(r.ticks.empty() ? r.initialStateHash : r.ticks.back().stateHash).c_str());
  std::printf("build\n");
  // Every string from the file goes through printable(): a replay is untrusted, and its names reach a terminal.
  for (const BuildFact& f : r.build) std::printf("  %-16s %s\n", printable(f.key).c_str(), printable(f.value).c_str());
  if (listCommands) {
    std::printf("commands (as a command script: TICK TYPE TEAM ...)\n");
    for (const TickRecord& t : r.ticks) {
      for (const Command& cmd : t.commands) {
        if (cmd.type == CommandType::ToggleGate) {
          std::printf("  %u gate %s %u\n", cmd.tick, teamName(cmd.team), cmd.gate);
          continue;
        }
        if (cmd.type == CommandType::ReloadWorld) {
          std::printf("  %u reload %s\n", cmd.tick, teamName(cmd.team));
          continue;
        }
        std::string units;
        for (size_t i = 0; i < cmd.units.size(); ++i) units += (i ? "," : "") + std::to_string(cmd.units[i]);
        if (cmd.type == CommandType::Move) {
          std::printf("  %u move %s %.17g %.17g %s\n", cmd.tick, teamName(cmd.team), cmd.target.x, cmd.target.y, units.c_str());
        } else {
          std::printf("  %u stop %s %s\n", cmd.tick, teamName(cmd.team), units.c_str());
        }
      }
    }
  }
  return kOk;
}

}  // namespace rts::replay::cli
