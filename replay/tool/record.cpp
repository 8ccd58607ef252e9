#include "tool/record.h"

#include <filesystem>
#include <optional>

#include "game/game.h"
#include "game/opponent.h"
#include "game/tick_loop.h"
#include "map/map_loader.h"
#include "tool/command_script.h"
#include "tool/recorder.h"

namespace rts::replay {

RecordOutcome recordGame(const RecordRequest& r, const std::function<void(uint32_t, uint32_t)>& progress) {
  RecordingInfo info;
  info.mapJson = readMapFile(r.mapPath);
  info.mapName = std::filesystem::path(r.mapPath).filename().string();
  info.seed = r.seed;
  info.opponentTeams = uint8_t(r.opponentTeams & 3);
  info.keyframeEvery = r.keyframeEvery;
  info.recordedBy = "rattle-replay record";
  std::optional<CommandScript> script;
  if (!r.scriptPath.empty()) {
    script = CommandScript::load(r.scriptPath);
    info.recordedBy += " --script " + std::filesystem::path(r.scriptPath).filename().string();
  }
  GameConfig config;
  config.unitsPerTeam = r.unitsPerTeam;
  config.stepMode = r.mode;
  config.weapons = r.weapons;
  Game game(parseMap(info.mapJson, r.mapPath), config);
  if (script) script->checkAgainst(game);
  ScriptedOpponent opponent(r.seed, r.opponentTeams & 3);
  Recorder recorder(r.output, info, game);
  RecordOutcome out;
  TickLoop loop(game);
  if (r.opponentTeams & 3) loop.add(opponent);
  if (script) loop.add(*script);
  for (uint32_t t = 0; t < r.ticks; ++t) {
    const std::vector<Command>& commands = loop.tick();
    recorder.afterTick(game, commands);
    out.commands += commands.size();
    if (progress) progress(game.tickCount(), r.ticks);
  }
  recorder.finish(game);
  out.ticks = game.tickCount();
  out.finalStateHash = game.stateHash();
  return out;
}

}  // namespace rts::replay
