// rattle-replay render FILE --frames DIR [--from T] [--to T] [--every N] [--size WxH] ...
#include <cstdio>

#include "app/cli.h"
#include "render/offscreen.h"
#include "tool/frames.h"
#include "tool/replay_run.h"

namespace rts::replay::cli {
namespace {

const char* kHelp =
    "usage: rattle-replay render FILE --frames DIR [options]\n"
    "\n"
    "Re-runs the recorded game and writes PNG frames of it (drawn offscreen with OSMesa, as rattle-demo\n"
    "draws them) to DIR/frame_NNNNNN.png, NNNNNN the tick. Frames never show the measured step time, so\n"
    "the same replay gives the same bytes on the same build and Mesa.\n"
    "\n"
    "  --frames DIR     where the frames go (required; created if missing)\n"
    "  --from T         first tick to draw (default 0: the state before the first tick)\n"
    "  --to T           last tick to draw (default: the replay's last)\n"
    "  --every N        draw every N-th tick from --from (default 1)\n"
    "  --size WxH       frame size in pixels, each 16 to 8192 (default 1280x720)\n"
    "  --supersample N  N x N samples a pixel, 1 to 4 (default 2)\n"
    "  --fog TEAM       whose fog of war: 0 (blue, default), 1 (red) or none\n"
    "  --no-sight       leave out the faint sight ranges\n"
    "  --quiet          no progress line\n"
    "  --help           this text\n"
    "\n"
    "When the re-run stops matching the recording, a warning names the first tick that differs (the frames\n"
    "after it show this build's game); the exit status stays 0. Exit status: 0 done, 1 a frame could not\n"
    "be written, 2 bad options or FILE is not a valid replay.\n";

}  // namespace

int runRender(const std::vector<std::string>& args) {
  std::string file;
  RenderRequest req;
  bool quiet = false;
  bool toGiven = false;  // --to past the replay's end is refused, as --from is
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&] { return nextValue(args, i); };
    auto number = [&](uint64_t lo, uint64_t hi, uint64_t& out) { return nextNumber("render", args, i, lo, hi, out); };
    uint64_t n = 0;
    int bad = -1;
    if (a == "--help" || a == "-h") {
      std::fputs(kHelp, stdout);
      return kOk;
    } else if (a == "--frames") {
      const std::string* v = value();
      if (!v || v->empty()) return usageError("render", "--frames: expected a directory");
      req.dir = *v;
    } else if (a == "--from") {
      if ((bad = number(0, UINT32_MAX, n)) >= 0) return bad;
      req.from = uint32_t(n);
    } else if (a == "--to") {
      if ((bad = number(0, UINT32_MAX, n)) >= 0) return bad;
      req.to = uint32_t(n);
      toGiven = true;
    } else if (a == "--every") {
      if ((bad = number(1, UINT32_MAX, n)) >= 0) return bad;
      req.every = uint32_t(n);
    } else if (a == "--supersample") {
      if ((bad = number(1, 4, n)) >= 0) return bad;
      req.frame.supersample = int(n);
    } else if (a == "--size") {
      const std::string* v = value();
      if (!v || !parseSize(*v, req.frame.width, req.frame.height)) {
        return usageError("render", "--size " + (v ? *v : "(missing)") + ": expected WIDTHxHEIGHT, each 16 to 8192 (e.g. 1280x720)");
      }
    } else if (a == "--fog") {
      const std::string* v = value();
      const std::string f = v ? *v : "";
      if (f == "0" || f == "blue") {
        req.frame.fogTeam = 0;
      } else if (f == "1" || f == "red") {
        req.frame.fogTeam = 1;
      } else if (f == "none") {
        req.frame.fogTeam = -1;
      } else {
        return usageError("render", "--fog " + (v ? *v : "(missing)") + ": expected 0, 1 or none");
      }
    } else if (a == "--no-sight") {
      req.frame.showSight = false;
    } else if (a == "--quiet") {
      quiet = true;
    } else if (!a.empty() && a[0] == '-') {
      return usageError("render", "unknown option '" + a + "'");
    } else if (file.empty()) {
      file = a;
    } else {
      return usageError("render", "one FILE only ('" + a + "' is a second)");
    }
  }
  if (file.empty()) return usageError("render", "expected a replay FILE");
  if (req.dir.empty()) return usageError("render", "--frames DIR is required");
  if (req.to < req.from) return usageError("render", "--to " + std::to_string(req.to) + " is before --from " + std::to_string(req.from));
  std::optional<Replay> replay = loadReplay("render", file);
  if (!replay) return kBadInput;
  if (req.from > replay->tickCount()) {
    return usageError("render", "--from " + std::to_string(req.from) + ": the replay has " + std::to_string(replay->tickCount()) + " ticks");
  }
  if (toGiven && req.to > replay->tickCount()) {
    return usageError("render", "--to " + std::to_string(req.to) + ": the replay has " +
                                    std::to_string(replay->tickCount()) + " ticks");
  }
  Progress progress("render " + file, !quiet);
  try {
    const RenderOutcome out = renderReplay(*replay, req, [&](uint32_t t, uint32_t n) { progress.update(t, n); });
    progress.done();
    if (!out.error.empty()) {
      std::fprintf(stderr, "rattle-replay render: %s\n", out.error.c_str());
      return kFailed;
    }
    if (out.firstDivergence) {
      std::fprintf(stderr, "rattle-replay render: warning: %s diverges from its recording at tick %u (run verify for the details); "
                   "frames from there on show this build's game\n", file.c_str(), *out.firstDivergence);
    }
    std::printf("%d frames in %s/\n", out.framesWritten, req.dir.c_str());
    return kOk;
  } catch (const ReplaySetupError& e) {
    progress.done();
    std::fprintf(stderr, "rattle-replay render: %s: %s\n", file.c_str(), e.what());
    return kBadInput;
  } catch (const RenderError& e) {
    progress.done();
    std::fprintf(stderr, "rattle-replay render: cannot render: %s\n", e.what());
    return kFailed;
  }
}

}  // namespace rts::replay::cli
