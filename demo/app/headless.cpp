// Headless: the scripted opponent plays both teams; every N ticks a frame is drawn offscreen and saved.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string_view>

#include "app/run.h"
#include "game/opponent.h"
#include "game/tick_loop.h"
#include "render/offscreen.h"
#include "render/png.h"
#include "render/scene_builder.h"
#include "tool/recorder.h"

namespace rts {
namespace {

// frame_ and six or more digits and .png: exactly the names frame() below writes, nothing a person named.
bool isFrameName(const std::string& name) {
  constexpr std::string_view prefix = "frame_", suffix = ".png";
  if (name.size() < prefix.size() + 6 + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0) {
    return false;
  }
  const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  return std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// A shorter or sparser run into the same directory would leave an earlier game's frames between this
// one's, and a glob over the directory (frame_*.png into ffmpeg) would mix the two games.
bool removeEarlierFrames(const std::string& dir) {
  std::error_code ec;
  size_t removed = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    if (!entry.is_regular_file(ec) || !isFrameName(entry.path().filename().string())) continue;
    if (!std::filesystem::remove(entry.path(), ec)) {
      std::fprintf(stderr, "rattle-demo: --frames %s: cannot remove the earlier frame %s (%s)\n", dir.c_str(),
                   entry.path().filename().string().c_str(), ec.message().c_str());
      return false;
    }
    ++removed;
  }
  if (ec) {
    std::fprintf(stderr, "rattle-demo: --frames %s: cannot list the directory (%s)\n", dir.c_str(), ec.message().c_str());
    return false;
  }
  if (removed) std::fprintf(stderr, "rattle-demo: removed %zu frame_NNNNNN.png files of an earlier run from %s\n", removed, dir.c_str());
  return true;
}

}  // namespace

int runHeadless(Game& game, const Options& o, replay::Recorder* recorder) {
  std::unique_ptr<OffscreenRenderer> renderer;
  if (o.render) {
    std::error_code ec;
    std::filesystem::create_directories(o.framesDir, ec);
    if (ec) {
      std::fprintf(stderr, "rattle-demo: --frames %s: cannot create the directory (%s)\n", o.framesDir.c_str(), ec.message().c_str());
      return 1;
    }
    if (!removeEarlierFrames(o.framesDir)) return 1;
    renderer = std::make_unique<OffscreenRenderer>(o.width, o.height, o.supersample);
  }
  ScriptedOpponent opponent(o.seed);
  TickLoop loop(game);
  loop.add(opponent);
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
    const std::vector<Command>& commands = loop.tick();
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
