// rattle-replay: inspect, verify, render and record replays of the RTS demo (replay/README.md).
#include <cstdio>
#include <string>
#include <vector>

#include "app/cli.h"

namespace {

const char* kUsage =
    "usage: rattle-replay COMMAND [options] FILE\n"
    "\n"
    "Replays of the rattle RTS demo (recorded with rattle-demo --record FILE, or with `record` below):\n"
    "\n"
    "  info FILE               the map, the game, the ticks and commands, the build that recorded it\n"
    "  verify FILE             re-run the game and check every tick's hashes; exit 0 when all match, 1 naming\n"
    "                          the first tick, the bodies and the fields that differ\n"
    "  render FILE --frames DIR [--from T] [--to T] [--every N] [--size WxH]\n"
    "                          PNG frames of the replayed game\n"
    "  record --map M --seed S --ticks N [--units N] FILE\n"
    "                          play the scripted game headless and record it\n"
    "\n"
    "`rattle-replay COMMAND --help` describes each. Exit status: 0 done, 1 a divergence (verify) or a file\n"
    "that could not be written, 2 bad usage or a malformed replay. The format is in replay/FORMAT.md.\n";

}  // namespace

int main(int argc, char** argv) {
  using namespace rts::replay::cli;
  if (argc < 2) {
    std::fputs(kUsage, stderr);
    return kBadInput;
  }
  const std::string command = argv[1];
  const std::vector<std::string> args(argv + 2, argv + argc);
  if (command == "--help" || command == "-h" || command == "help") {
    std::fputs(kUsage, stdout);
    return kOk;
  }
  if (command == "info") return runInfo(args);
  if (command == "verify") return runVerify(args);
  if (command == "render") return runRender(args);
  if (command == "record") return runRecord(args);
  std::fprintf(stderr, "rattle-replay: unknown command '%s' (info, verify, render or record)\nTry 'rattle-replay --help'.\n", command.c_str());
  return kBadInput;
}
