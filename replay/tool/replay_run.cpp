#include "tool/replay_run.h"

#include "format/snapshot_codec.h"
#include "map/map_loader.h"
#include "map/printable.h"
#include "tool/snapshot.h"

namespace rts::replay {

std::unique_ptr<Game> buildGame(const Replay& r) {
  Map map;
  try {
    map = parseMap(r.mapJson, "the replay's map (" + (r.mapName.empty() ? std::string("unnamed") : printable(r.mapName)) + ")");
  } catch (const MapError& e) {
    throw ReplaySetupError(std::string("bad embedded map: ") + e.what());
  }
  GameConfig config;
  config.unitsPerTeam = int(r.config.unitsPerTeam);
  config.stepMode = rattle::StepMode(r.config.stepMode);
  config.weapons = r.config.weapons;
  std::unique_ptr<Game> game;
  try {
    game = std::make_unique<Game>(std::move(map), config);
  } catch (const GameError& e) {
    throw ReplaySetupError(std::string("cannot start the replay's game: ") + e.what());
  } catch (const std::exception& e) {
    throw ReplaySetupError(std::string("cannot start the replay's game: ") + e.what());
  }
  const ReplayConfig built = configOf(*game);
  auto mismatch = [&](const char* what, uint32_t recorded, uint32_t actual) {
    if (recorded != actual) {
      throw ReplaySetupError(std::string("the replay's ") + what + " (" + std::to_string(recorded) + ") does not match its map's game (" +
                             std::to_string(actual) + ")");
    }
  };
  mismatch("unit count", r.config.unitCount, built.unitCount);
  mismatch("gate count", r.config.gateCount, built.gateCount);
  mismatch("doorway count", r.config.doorwayCount, built.doorwayCount);
  mismatch("room count", r.config.roomCount, built.roomCount);
  return game;
}

void RecordedCommands::commandsFor(uint32_t tick, const Game&, std::vector<Command>& out) {
  if (tick >= replay_.ticks.size()) return;
  const std::vector<Command>& recorded = replay_.ticks[tick].commands;
  out.insert(out.end(), recorded.begin(), recorded.end());
}

ReplayRun::ReplayRun(const Replay& replay)
    : replay_(replay), game_(buildGame(replay)), recorded_(replay), loop_(*game_) {
  loop_.add(recorded_);
}
ReplayRun::~ReplayRun() = default;

const Keyframe* ReplayRun::keyframeAt(uint32_t tick) const {
  // Keyframes ascend; nextKeyframe_ never points past the current tick's.
  for (size_t k = nextKeyframe_; k < replay_.keyframes.size() && replay_.keyframes[k].tick <= tick; ++k) {
    if (replay_.keyframes[k].tick == tick) return &replay_.keyframes[k];
  }
  return nullptr;
}

TickCheck ReplayRun::checkInitial() const {
  TickCheck c;
  c.tick = 0;
  c.recordedStateHash = replay_.initialStateHash;
  c.actualStateHash = game_->stateHash();
  c.recordedWorldHash = replay_.initialWorldHash;
  c.actualWorldHash = game_->worldHash();
  if (const Keyframe* k = keyframeAt(0)) {
    c.keyframe = true;
    c.fields = snapshotDifferences(k->state, snapshotOf(*game_), *game_);
  }
  return c;
}

TickCheck ReplayRun::step(bool check) {
  if (done()) throw std::logic_error("ReplayRun::step past the last tick");
  const TickRecord& record = replay_.ticks[tick()];
  loop_.tick();
  TickCheck c;
  c.tick = game_->tickCount();
  c.recordedStateHash = record.stateHash;
  c.actualStateHash = game_->stateHash();
  c.recordedWorldHash = record.worldHash;
  c.actualWorldHash = game_->worldHash();
  while (nextKeyframe_ < replay_.keyframes.size() && replay_.keyframes[nextKeyframe_].tick < c.tick) ++nextKeyframe_;
  if (!check) return c;
  const Snapshot now = snapshotOf(*game_);
  c.bodies = digestDifferences(record.digests, digestsOf(now), *game_);
  if (const Keyframe* k = keyframeAt(c.tick)) {
    c.keyframe = true;
    c.fields = snapshotDifferences(k->state, now, *game_);
  }
  return c;
}

}  // namespace rts::replay
