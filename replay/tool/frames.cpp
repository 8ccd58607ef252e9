#include "tool/frames.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "render/png.h"
#include "render/scene_builder.h"
#include "tool/replay_run.h"

namespace rts::replay {

std::vector<uint8_t> drawFrame(OffscreenRenderer& renderer, const Game& game, const FrameOptions& o) {
  SceneOptions view;
  view.fogTeam = o.fogTeam;
  view.showSight = o.showSight;
  view.showTimes = false;  // the one wall-clock number: never on a replay's frames
  return renderer.render(buildScene(game, view));
}

RenderOutcome renderReplay(const Replay& replay, const RenderRequest& request, const std::function<void(uint32_t, uint32_t)>& progress) {
  RenderOutcome out;
  std::error_code ec;
  std::filesystem::create_directories(request.dir, ec);
  if (ec) {
    out.error = request.dir + ": cannot create the directory (" + ec.message() + ")";
    return out;
  }
  ReplayRun run(replay);
  OffscreenRenderer renderer(request.frame.width, request.frame.height, request.frame.supersample);
  const uint32_t last = std::min(request.to, run.lastTick());
  const uint32_t every = std::max<uint32_t>(1, request.every);
  auto wanted = [&](uint32_t t) { return t >= request.from && t <= last && (t - request.from) % every == 0; };
  auto frame = [&]() -> bool {
    char name[32];
    std::snprintf(name, sizeof name, "/frame_%06u.png", run.tick());
    const std::string path = request.dir + name;
    const std::string error = writePng(path, request.frame.width, request.frame.height, drawFrame(renderer, run.game(), request.frame));
    if (!error.empty()) {
      out.error = error;
      return false;
    }
    ++out.framesWritten;
    return true;
  };
  if (!run.checkInitial().ok()) out.firstDivergence = 0;
  if (wanted(0) && !frame()) return out;
  while (run.tick() < last) {
    const TickCheck c = run.step(false);
    if (!out.firstDivergence && (c.recordedStateHash != c.actualStateHash || c.recordedWorldHash != c.actualWorldHash)) {
      out.firstDivergence = c.tick;
    }
    if (progress) progress(c.tick, last);
    if (wanted(c.tick) && !frame()) return out;
  }
  return out;
}

}  // namespace rts::replay
