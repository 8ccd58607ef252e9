// rattle-demo: reads the options and the map, makes the game, and hands it to the headless loop or the
// window. Every error a user can cause ends here as one line naming the problem, with exit status 1
// (2 for bad options; 3 to 6 for a networked game that ended early: app/run.h).
#include <cstdio>
#include <filesystem>
#include <memory>

#include "app/options.h"
#include "app/run.h"
#include "map/map_loader.h"
#include "render/offscreen.h"
#include "tool/recorder.h"

namespace {

std::string defaultMap() {
  // The source tree's arena when run from a build, else the one under the current directory.
  const std::string built = RATTLE_DEMO_DEFAULT_MAP;
  return std::filesystem::exists(built) ? built : "assets/maps/arena.json";
}

}  // namespace

int main(int argc, char** argv) {
  rts::ParseResult parsed = rts::parseOptions(argc, argv);
  if (parsed.action == rts::ParseResult::Action::Exit) return parsed.exitCode;
  rts::Options& o = parsed.options;
  if (o.map.empty()) o.map = defaultMap();
  // A network game's length is agreed in the handshake: a window plays the same 600 ticks as a headless
  // side unless told otherwise.
  if (o.window && !o.ticksGiven && o.network == rts::Options::Network::None) o.ticks = 0;
  if (o.window && !o.supersampleGiven) o.supersample = 1;  // frames per second over the last bit of polish
  try {
    rts::GameConfig config;
    config.unitsPerTeam = o.units;
    config.stepMode = o.mode;
    config.steering = o.steering;
    // Read the map's bytes once: a replay embeds exactly the bytes the game was built from.
    const std::string mapJson = rts::readMapFile(o.map);
    rts::Game game(rts::parseMap(mapJson, o.map), config);
    std::unique_ptr<rts::replay::Recorder> recorder;
    if (!o.record.empty()) {
      rts::replay::RecordingInfo info;
      info.mapName = std::filesystem::path(o.map).filename().string();
      info.mapJson = mapJson;
      info.seed = o.seed;
      // Networked, this side's opponent plays its own team (in a window the person does, and the opponent
      // none); the other team's commands came from the peer. A spectator's commands all came from the host.
      info.opponentTeams = o.network == rts::Options::Network::Watch  ? 0
                           : o.network != rts::Options::Network::None ? (o.window ? 0 : uint8_t(1u << o.team()))
                           : o.window                                 ? 2
                                                                      : 3;
      info.keyframeEvery = uint32_t(o.keyframeEvery);
      info.recordedBy = o.network == rts::Options::Network::Host    ? "rattle-demo --host"
                        : o.network == rts::Options::Network::Join  ? "rattle-demo --join"
                        : o.network == rts::Options::Network::Watch ? "rattle-demo --watch"
                                                                    : "rattle-demo";
      if (o.window) {
        info.recordedBy = o.network == rts::Options::Network::None ? "rattle-demo --window"
                                                                   : info.recordedBy + " --window";
      }
      recorder = std::make_unique<rts::replay::Recorder>(o.record, info, game);
    }
    const int status =
        o.window ? rts::runWindow(game, o, mapJson, recorder.get()) : rts::runHeadless(game, o, mapJson, recorder.get());
    if (recorder && status == 0) std::fprintf(stderr, "rattle-demo: replay written to %s\n", o.record.c_str());
    return status;
  } catch (const rts::MapError& e) {
    std::fprintf(stderr, "rattle-demo: bad map: %s\n", e.what());
  } catch (const rts::GameError& e) {
    std::fprintf(stderr, "rattle-demo: cannot start the game: %s\n", e.what());
  } catch (const rts::RenderError& e) {
    std::fprintf(stderr, "rattle-demo: cannot render: %s\n", e.what());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rattle-demo: %s\n", e.what());
  }
  return 1;
}
