#include "tool/verify.h"

#include <cstdio>

#include "tool/build_facts.h"

namespace rts::replay {
namespace {

constexpr size_t kMaxBodiesListed = 12;
constexpr size_t kMaxFieldsListed = 40;

void describeFields(std::string& out, const TickCheck& c) {
  if (c.fields.empty()) {
    out += "    every stored field matches (the difference is in state the keyframe does not hold)\n";
    return;
  }
  for (size_t i = 0; i < c.fields.size() && i < kMaxFieldsListed; ++i) {
    const FieldDiff& f = c.fields[i];
    out += "    " + f.body + " " + f.field + ": recorded " + f.recorded + ", now " + f.actual + (f.delta.empty() ? "" : " (" + f.delta + ")") + "\n";
  }
  if (c.fields.size() > kMaxFieldsListed) out += "    ... and " + std::to_string(c.fields.size() - kMaxFieldsListed) + " more fields\n";
}

}  // namespace

std::string hex64(uint64_t v) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

VerifyReport verifyReplay(const Replay& replay, const std::function<void(uint32_t, uint32_t)>& progress) {
  VerifyReport report;
  report.buildDifferences = buildDifferences(replay.build, thisBuild());
  report.ticks = replay.tickCount();
  ReplayRun run(replay);
  TickCheck initial = run.checkInitial();
  if (!initial.ok()) {
    report.divergence = std::move(initial);
    return report;
  }
  while (!run.done()) {
    TickCheck c = run.step();
    if (progress) progress(c.tick, report.ticks);
    if (!report.divergence) {
      if (c.ok()) {
        ++report.ticksMatched;
        continue;
      }
      const bool atKeyframe = c.keyframe;
      report.divergence = std::move(c);
      if (atKeyframe) break;
      continue;
    }
    // Diverged earlier: play on to the next keyframe for the fields.
    if (c.keyframe) {
      report.keyframeAfter = std::move(c);
      break;
    }
  }
  return report;
}

std::string VerifyReport::text(const std::string& name) const {
  std::string out;
  if (!buildDifferences.empty()) {
    out += name + ": recorded by a different build:\n";
    for (const std::string& d : buildDifferences) out += "  " + d + "\n";
  }
  if (!divergence) {
    out += name + ": all " + std::to_string(ticks) + " ticks match (every state hash, body digest and keyframe)" +
           (buildDifferences.empty() ? "" : ", although the build differs") + "\n";
    return out;
  }
  const TickCheck& d = *divergence;
  out += name + ": diverges at tick " + std::to_string(d.tick) + " of " + std::to_string(ticks) +
         (ticksMatched == 0 ? std::string(" (no tick matches)")
                            : " (ticks 1 to " + std::to_string(ticksMatched) + " match)") +
         "\n";
  if (d.recordedStateHash != d.actualStateHash) {
    out += "  state hash: recorded " + hex64(d.recordedStateHash) + ", now " + hex64(d.actualStateHash) + "\n";
  }
  out += d.recordedWorldHash != d.actualWorldHash
             ? "  engine world hash: recorded " + hex64(d.recordedWorldHash) + ", now " + hex64(d.actualWorldHash) + "\n"
             : "  engine world hash: matches (the difference is in the game's own state)\n";
  if (!d.bodies.empty()) {
    out += "  bodies that differ at tick " + std::to_string(d.tick) + " (" + std::to_string(d.bodies.size()) + "): ";
    for (size_t i = 0; i < d.bodies.size() && i < kMaxBodiesListed; ++i) out += (i ? ", " : "") + d.bodies[i];
    if (d.bodies.size() > kMaxBodiesListed) out += ", ... (" + std::to_string(d.bodies.size() - kMaxBodiesListed) + " more)";
    out += "\n";
  }
  if (d.keyframe) {
    out += "  fields at tick " + std::to_string(d.tick) + " (a keyframe):\n";
    describeFields(out, d);
  } else if (keyframeAfter) {
    out += "  fields at tick " + std::to_string(keyframeAfter->tick) + ", the next keyframe (" +
           std::to_string(keyframeAfter->tick - d.tick) + " ticks later; differences may have spread):\n";
    describeFields(out, *keyframeAfter);
  }
  return out;
}

}  // namespace rts::replay
