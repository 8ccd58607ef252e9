// Headless: the scripted opponent plays both teams, or with --host / --join this side's team against the
// peer's over the network; every N ticks a frame is drawn offscreen and saved.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string_view>

#include "app/network_play.h"
#include "app/run.h"
#include "game/opponent.h"
#include "game/tick_loop.h"
#include "net/lockstep.h"
#include "net/spectator.h"
#include "net/transport.h"
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

int runHeadless(Game& game, const Options& o, const std::string& mapJson, replay::Recorder* recorder) {
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
  const bool networked = o.network != Options::Network::None;
  // Networked, each side's opponent plays its own team only; its commands reach the game through the
  // session, which applies both teams' in one order on both sides.
  ScriptedOpponent opponent(o.seed, networked ? 1u << o.team() : 3u);  // not asked when watching
  TickLoop loop(game);
  Network network;
  if (networked) {
    try {
      network = connectNetwork(game, o, mapJson, opponent);
    } catch (const net::SessionError& e) {
      printSessionError(e);
      return exitStatus(e.kind());
    }
    if (network.session) {
      loop.add(*network.session);
    } else {
      loop.add(*network.spectator);
    }
  } else {
    loop.add(opponent);
  }
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
  try {
    // To the game's length from where it is: a spectator's game starts at the host's tick.
    while (long(game.tickCount()) < o.ticks) {
      const std::vector<Command>& commands = loop.tick();
      // Recorded before the hashes are compared: a desync's replay holds the tick that differs.
      if (recorder) recorder->afterTick(game, commands);
      if (network.session) network.session->afterTick(game);
      if (network.spectator) network.spectator->afterTick(game);
      if (renderer && game.tickCount() % unsigned(o.every) == 0 && !frame()) return 1;
      if (!o.quiet) progress(game, o.ticks, false);
    }
    if (network.session) network.session->finish(game);
    if (network.spectator) network.spectator->finish(game);
  } catch (const net::SessionError& e) {
    if (!o.quiet) progress(game, o.ticks, true);
    return endedEarly(e, game, o, recorder);
  }
  if (!o.quiet) progress(game, o.ticks, true);
  if (recorder) recorder->finish(game);
  std::sort(frameSeconds.begin(), frameSeconds.end());
  std::sort(drawSeconds.begin(), drawSeconds.end());
  printSummary(game, o, frames, frameSeconds.empty() ? 0 : frameSeconds[frameSeconds.size() / 2],
               drawSeconds.empty() ? 0 : drawSeconds[drawSeconds.size() / 2]);
  printNetworkEnd(network, game, o);
  return 0;
}

}  // namespace rts
