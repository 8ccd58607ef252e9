// Headless: the scripted opponent plays both teams; every N ticks a frame is drawn offscreen and saved.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "app/run.h"
#include "game/opponent.h"
#include "render/offscreen.h"
#include "render/png.h"
#include "render/scene_builder.h"
#include "tool/recorder.h"

namespace rts {

int runHeadless(Game& game, const Options& o, replay::Recorder* recorder) {
  std::unique_ptr<OffscreenRenderer> renderer;
  if (o.render) {
    std::error_code ec;
    std::filesystem::create_directories(o.framesDir, ec);
    if (ec) {
      std::fprintf(stderr, "rattle-demo: --frames %s: cannot create the directory (%s)\n", o.framesDir.c_str(), ec.message().c_str());
      return 1;
    }
    renderer = std::make_unique<OffscreenRenderer>(o.width, o.height, o.supersample);
  }
  ScriptedOpponent opponent(o.seed);
  std::vector<Command> commands;
  std::vector<double> frameSeconds, drawSeconds;
  int frames = 0;
  SceneOptions view;
  view.fogTeam = o.fogTeam;
  view.showSight = o.showSight;
  view.showTimes = o.showTimes;

  auto frame = [&]() -> bool {
    const auto start = std::chrono::steady_clock::now();
    char name[64];
    std::snprintf(name, sizeof name, "/frame_%06u.png", game.tickCount());
    const std::string path = o.framesDir + name;
    const std::vector<uint8_t>& pixels = renderer->render(buildScene(game, view));
    drawSeconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    const std::string error = writePng(path, o.width, o.height, pixels);
    if (!error.empty()) {
      std::fprintf(stderr, "\nrattle-demo: %s\n", error.c_str());
      return false;
    }
    ++frames;
    frameSeconds.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
    return true;
  };

  if (renderer && !frame()) return 1;
  for (long t = 0; t < o.ticks; ++t) {
    // The loop a replay plugs into: commands for this tick (recorded here, or read back), then the tick.
    commands.clear();
    opponent.commandsFor(game.tickCount(), game, commands);
    for (const Command& c : commands) game.apply(c);
    game.tick();
    if (recorder) recorder->afterTick(game, commands);
    if (renderer && game.tickCount() % unsigned(o.every) == 0 && !frame()) return 1;
    if (!o.quiet) progress(game, o.ticks, false);
  }
  if (!o.quiet) progress(game, o.ticks, true);
  if (recorder) recorder->finish(game);
  std::sort(frameSeconds.begin(), frameSeconds.end());
  std::sort(drawSeconds.begin(), drawSeconds.end());
  printSummary(game, o, frames, frameSeconds.empty() ? 0 : frameSeconds[frameSeconds.size() / 2],
               drawSeconds.empty() ? 0 : drawSeconds[drawSeconds.size() / 2]);
  return 0;
}

}  // namespace rts
