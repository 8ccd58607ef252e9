// rattle-replay verify FILE [--quiet]
#include <cstdio>

#include "app/cli.h"
#include "tool/verify.h"

namespace rts::replay::cli {
namespace {

const char* kHelp =
    "usage: rattle-replay verify FILE [--quiet]\n"
    "\n"
    "Re-runs the recorded game (its map and configuration, with the recorded commands before every tick; no\n"
    "opponent) and checks every tick against the recording: the game's state hash, the engine's world hash,\n"
    "each body's 16-bit digest, and every keyframe field by field.\n"
    "\n"
    "When the replay was recorded by a different build (compiler, flags, engine version, ...), the\n"
    "differences are listed first; then whether the hashes still agree.\n"
    "\n"
    "At the first tick that differs it names the tick, the bodies whose digests differ, and the fields that\n"
    "differ with both values and the difference (and, while it is small, the distance in ulps): exactly\n"
    "at that tick if it has a keyframe, else at the next keyframe.\n"
    "\n"
    "  --quiet   no progress line\n"
    "  --help    this text\n"
    "\n"
    "Exit status: 0 every tick matches, 1 a divergence (the report is on stdout), 2 FILE is not a valid\n"
    "replay (the message gives the byte offset and field, or what is wrong with its map or game).\n";

}  // namespace

int runVerify(const std::vector<std::string>& args) {
  std::string file;
  bool quiet = false;
  for (const std::string& a : args) {
    if (a == "--help" || a == "-h") {
      std::fputs(kHelp, stdout);
      return kOk;
    } else if (a == "--quiet") {
      quiet = true;
    } else if (!a.empty() && a[0] == '-') {
      return usageError("verify", "unknown option '" + a + "'");
    } else if (file.empty()) {
      file = a;
    } else {
      return usageError("verify", "one FILE only ('" + a + "' is a second)");
    }
  }
  if (file.empty()) return usageError("verify", "expected a replay FILE");
  std::optional<Replay> replay = loadReplay("verify", file);
  if (!replay) return kBadInput;
  Progress progress("verify " + file, !quiet);
  try {
    const VerifyReport report = verifyReplay(*replay, [&](uint32_t t, uint32_t n) { progress.update(t, n); });
    progress.done();
    std::fputs(report.text(file).c_str(), stdout);
    return report.ok() ? kOk : kFailed;
  } catch (const ReplaySetupError& e) {
    progress.done();
    std::fprintf(stderr, "rattle-replay verify: %s: %s\n", file.c_str(), e.what());
    return kBadInput;
  }
}

}  // namespace rts::replay::cli
