#include "net/desync_report.h"

#include <cstdio>
#include <vector>

#include "format/snapshot_codec.h"
#include "net/protocol.h"
#include "net/text.h"
#include "tool/divergence.h"

namespace rts::net {
namespace {

// As many as rattle-replay verify lists (replay/tool/verify.cpp): a report for a person, not a dump.
constexpr size_t kMaxBodiesListed = 12;
constexpr size_t kMaxFieldsListed = 40;

// divergence.h names a shot only one side has from a replay's point of view; here the recording is
// this side and the run is the peer.
std::string sides(std::string name) {
  const std::pair<const char*, const char*> words[] = {{" (only in this run)", " (only in theirs)"},
                                                       {" (only in the recording)", " (only in mine)"}};
  for (const auto& [replayWords, ours] : words) {
    const size_t at = name.find(replayWords);
    if (at != std::string::npos) name.replace(at, std::string(replayWords).size(), ours);
  }
  return name;
}

}  // namespace

std::string desyncDetails(uint32_t tick, const SideState& mine, const SideState& theirs, const Game& game,
                          uint32_t hashEvery) {
  const std::string t = std::to_string(tick);
  std::string out;
  // The tick compared before this one matched; any tick after it may be the first that differs.
  const uint32_t matched = hashEvery > 0 && tick > 0 ? (tick - 1) / hashEvery * hashEvery : tick;
  if (tick > 0 && matched + 1 < tick) {
    out += "  hashes are compared every " + std::to_string(hashEvery) + " ticks: tick " + std::to_string(matched) +
           " matched, so the games parted at one of ticks " + std::to_string(matched + 1) + " to " + t + "\n";
  }
  out += mine.worldHash != theirs.worldHash
             ? "  engine world hash: mine " + hexHash(mine.worldHash) + ", theirs " + hexHash(theirs.worldHash) + "\n"
             : "  engine world hash: matches (the difference is in the game's own state)\n";
  if (!mine.state || !theirs.state) {
    out += std::string("  bodies and fields: ") + (theirs.state ? "this side's" : "the peer's") + " state at tick " +
           t + " is over the " + std::to_string(kMaxSnapshotStateBytes) +
           " bytes a message carries; the two sides' replays (--record) hold every body's digest at every tick\n";
    return out;
  }

  const std::vector<std::string> bodies =
      replay::digestDifferences(replay::digestsOf(*mine.state), replay::digestsOf(*theirs.state), game);
  if (!bodies.empty()) {
    out += "  bodies that differ at tick " + t + " (" + std::to_string(bodies.size()) + "): ";
    for (size_t i = 0; i < bodies.size() && i < kMaxBodiesListed; ++i) out += (i ? ", " : "") + sides(bodies[i]);
    if (bodies.size() > kMaxBodiesListed)
      out += ", ... (" + std::to_string(bodies.size() - kMaxBodiesListed) + " more)";
    out += "\n";
  }

  const std::vector<replay::FieldDiff> fields = replay::snapshotDifferences(*mine.state, *theirs.state, game);
  out += "  fields at tick " + t + ":\n";
  if (fields.empty()) {
    // The state hash covers more than a keyframe holds (orders' routes, sensors): as verify says it.
    out += "    every stored field matches (the difference is in state the keyframe does not hold)\n";
  }
  for (size_t i = 0; i < fields.size() && i < kMaxFieldsListed; ++i) {
    const replay::FieldDiff& f = fields[i];
    out += "    " + f.body + " " + f.field + ": mine " + f.recorded + ", theirs " + f.actual +
           (f.delta.empty() ? "" : " (" + f.delta + ")") + "\n";
  }
  if (fields.size() > kMaxFieldsListed) {
    out += "    ... and " + std::to_string(fields.size() - kMaxFieldsListed) + " more fields\n";
  }
  return out;
}

}  // namespace rts::net
