// rattle-replay record --map M --seed S --ticks N [--units N] ... FILE
#include <cstdio>

#include "app/cli.h"
#include "game/game.h"
#include "map/map_loader.h"
#include "tool/record.h"
#include "tool/verify.h"

namespace rts::replay::cli {
namespace {

const char* kHelp =
    "usage: rattle-replay record --map M --seed S --ticks N [options] FILE\n"
    "\n"
    "Plays the RTS demo headless (the scripted opponent, as rattle-demo without a window) and records it to\n"
    "FILE: the map embedded, the configuration, every command at its tick, the state hash and body digests\n"
    "of every tick, and keyframes. rattle-demo --record FILE records the same way while it plays.\n"
    "\n"
    "  --map M             Tiled JSON map (required)\n"
    "  --seed S            the scripted opponent's seed, 0 to 2^64-1 (required)\n"
    "  --ticks N           ticks to play, 0 to 100000000 (required)\n"
    "  --units N           units per team, 1 to 200000 (default 100)\n"
    "  --mode M            engine step mode: hybrid (default), discrete or predictive\n"
    "  --no-weapons        nobody fires\n"
    "  --opponent TEAMS    which teams the scripted opponent plays: both (default), blue, red or none\n"
    "  --script FILE       also apply the commands of a command script (replay/README.md)\n"
    "  --keyframe-every K  a keyframe (every body's exact state) every K ticks, 1 to 100000000 (default 30)\n"
    "  --quiet             no progress line\n"
    "  --help              this text\n"
    "\n"
    "Exit status: 0 recorded, 1 the map, the script or the game could not be used or FILE not written,\n"
    "2 bad options.\n";

}  // namespace

int runRecord(const std::vector<std::string>& args) {
  RecordRequest req;
  bool haveMap = false, haveSeed = false, haveTicks = false, quiet = false;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&] { return nextValue(args, i); };
    auto number = [&](uint64_t lo, uint64_t hi, uint64_t& out) { return nextNumber("record", args, i, lo, hi, out); };
    uint64_t n = 0;
    int bad = -1;
    if (a == "--help" || a == "-h") {
      std::fputs(kHelp, stdout);
      return kOk;
    } else if (a == "--map") {
      const std::string* v = value();
      if (!v || v->empty()) return usageError("record", "--map: expected a file name");
      req.mapPath = *v;
      haveMap = true;
    } else if (a == "--seed") {
      if ((bad = number(0, UINT64_MAX, n)) >= 0) return bad;
      req.seed = n;
      haveSeed = true;
    } else if (a == "--ticks") {
      if ((bad = number(0, 100'000'000, n)) >= 0) return bad;
      req.ticks = uint32_t(n);
      haveTicks = true;
    } else if (a == "--units") {
      if ((bad = number(1, 200'000, n)) >= 0) return bad;
      req.unitsPerTeam = int(n);
    } else if (a == "--keyframe-every") {
      if ((bad = number(1, 100'000'000, n)) >= 0) return bad;
      req.keyframeEvery = uint32_t(n);
    } else if (a == "--mode") {
      const std::string* v = value();
      const std::string m = v ? *v : "";
      if (m == "hybrid") {
        req.mode = rattle::StepMode::Hybrid;
      } else if (m == "discrete") {
        req.mode = rattle::StepMode::Discrete;
      } else if (m == "predictive") {
        req.mode = rattle::StepMode::Predictive;
      } else {
        return usageError("record", "--mode " + (v ? *v : "(missing)") + ": expected hybrid, discrete or predictive");
      }
    } else if (a == "--no-weapons") {
      req.weapons = false;
    } else if (a == "--opponent") {
      const std::string* v = value();
      const std::string t = v ? *v : "";
      if (t == "both") {
        req.opponentTeams = 3;
      } else if (t == "blue") {
        req.opponentTeams = 1;
      } else if (t == "red") {
        req.opponentTeams = 2;
      } else if (t == "none") {
        req.opponentTeams = 0;
      } else {
        return usageError("record", "--opponent " + (v ? *v : "(missing)") + ": expected both, blue, red or none");
      }
    } else if (a == "--script") {
      const std::string* v = value();
      if (!v || v->empty()) return usageError("record", "--script: expected a file name");
      req.scriptPath = *v;
    } else if (a == "--quiet") {
      quiet = true;
    } else if (!a.empty() && a[0] == '-') {
      return usageError("record", "unknown option '" + a + "'");
    } else if (req.output.empty()) {
      req.output = a;
    } else {
      return usageError("record", "one FILE only ('" + a + "' is a second)");
    }
  }
  if (!haveMap) return usageError("record", "--map M is required");
  if (!haveSeed) return usageError("record", "--seed S is required");
  if (!haveTicks) return usageError("record", "--ticks N is required");
  if (req.output.empty()) return usageError("record", "expected the replay FILE to write");
  Progress progress("record " + req.output, !quiet);
  try {
    const RecordOutcome out = recordGame(req, [&](uint32_t t, uint32_t total) { progress.update(t, total); });
    progress.done();
    std::printf("recorded %u ticks, %zu commands to %s (final state hash %s)\n", out.ticks, out.commands, req.output.c_str(),
                hex64(out.finalStateHash).c_str());
    return kOk;
  } catch (const MapError& e) {
    progress.done();
    std::fprintf(stderr, "rattle-replay record: bad map: %s\n", e.what());
  } catch (const GameError& e) {
    progress.done();
    std::fprintf(stderr, "rattle-replay record: cannot start the game: %s\n", e.what());
  } catch (const std::exception& e) {
    progress.done();
    std::fprintf(stderr, "rattle-replay record: %s\n", e.what());
  }
  return kFailed;
}

}  // namespace rts::replay::cli
