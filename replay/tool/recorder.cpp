#include "tool/recorder.h"

#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "format/snapshot_codec.h"
#include "tool/build_facts.h"
#include "tool/snapshot.h"

namespace rts::replay {

Recorder::Recorder(const std::string& path, const RecordingInfo& info, const Game& game) : path_(path), partPath_(path + ".part") {
  if (game.tickCount() != 0) throw std::logic_error("Recorder: start recording before the first tick");
  // Found out now rather than when the game ends, where the rename of the finished file would fail.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw std::runtime_error(path + ": is a directory; the replay needs a file name");
  out_.open(partPath_, std::ios::binary | std::ios::trunc);
  if (!out_) throw std::runtime_error(partPath_ + ": cannot create the replay file");
  ReplayConfig config = configOf(game);
  config.seed = info.seed;
  config.opponentTeams = info.opponentTeams;
  config.keyframeEvery = std::max<uint32_t>(1, info.keyframeEvery);
  config.recordedBy = info.recordedBy;
  writer_ = std::make_unique<ReplayWriter>(out_);
  try {
    writer_->begin(thisBuild(), info.mapName, info.mapJson, config, game.stateHash(), game.worldHash(), snapshotOf(game));
  } catch (const std::exception&) {
    throw std::runtime_error(partPath_ + ": cannot write the replay");
  }
}

Recorder::~Recorder() {
  if (!finished_) {
    out_.close();
    std::error_code ec;
    std::filesystem::remove(partPath_, ec);
  }
}

void Recorder::afterTick(const Game& game, const std::vector<Command>& applied) {
  TickRecord t;
  t.tick = game.tickCount();
  t.stateHash = game.stateHash();
  t.worldHash = game.worldHash();
  t.commands = applied;
  for (Command& c : t.commands) c.tick = t.tick - 1;
  const Snapshot s = snapshotOf(game);
  t.digests = digestsOf(s);
  try {
    writer_->tick(t, writer_->keyframeDue(t.tick) ? &s : nullptr);
  } catch (const std::exception&) {
    throw std::runtime_error(partPath_ + ": cannot write the replay (disk full?)");
  }
}

void Recorder::finish(const Game& game) {
  try {
    writer_->end(snapshotOf(game));
  } catch (const std::exception&) {
    throw std::runtime_error(partPath_ + ": cannot write the replay (disk full?)");
  }
  out_.close();
  if (!out_) throw std::runtime_error(partPath_ + ": cannot write the replay");
  std::error_code ec;
  std::filesystem::rename(partPath_, path_, ec);
  if (ec) throw std::runtime_error(path_ + ": cannot rename " + partPath_ + " to it (" + ec.message() + ")");
  finished_ = true;
}

}  // namespace rts::replay
