#include "format/replay_writer.h"

#include <sstream>
#include <stdexcept>

#include "format/byte_writer.h"
#include "format/checksum.h"
#include "format/command_codec.h"
#include "format/limits.h"
#include "format/snapshot_codec.h"

namespace rts::replay {
namespace {

std::string header() {
  ByteWriter w;
  w.bytes(std::string_view(kMagic, 8));
  w.u16(kFormatVersion);
  return w.data();
}

std::string buildPayload(const std::vector<BuildFact>& build) {
  ByteWriter w;
  w.varint(build.size());
  for (const BuildFact& f : build) {
    w.str(f.key);
    w.str(f.value);
  }
  return w.data();
}

std::string mapPayload(const std::string& name, const std::string& json) {
  ByteWriter w;
  w.str(name);
  w.u64(fnv1a64(json));
  w.bytes(json);
  return w.data();
}

std::string configPayload(const ReplayConfig& c) {
  ByteWriter w;
  w.u64(c.seed);
  w.varint(c.unitsPerTeam);
  w.u8(c.stepMode);
  w.u8(c.weapons);
  w.u8(c.opponentTeams);
  w.varint(c.keyframeEvery);
  w.varint(c.unitCount);
  w.varint(c.gateCount);
  w.varint(c.doorwayCount);
  w.varint(c.roomCount);
  w.str(c.recordedBy);
  return w.data();
}

std::string initPayload(uint64_t stateHash, uint64_t worldHash) {
  ByteWriter w;
  w.u64(stateHash);
  w.u64(worldHash);
  return w.data();
}

std::string keyframePayload(uint32_t tick, const Snapshot& s) {
  ByteWriter w;
  w.varint(tick);
  encodeSnapshot(w, s);
  return w.data();
}

std::string tickPayload(const TickRecord& t) {
  ByteWriter w;
  w.varint(t.tick);
  w.u64(t.stateHash);
  w.u64(t.worldHash);
  w.varint(t.commands.size());
  for (const Command& c : t.commands) encodeCommand(w, c);
  w.u16(t.digests.counters);
  for (uint16_t d : t.digests.units) w.u16(d);
  w.varint(t.digests.shots.size());
  uint32_t previous = 0;
  for (size_t i = 0; i < t.digests.shots.size(); ++i) {
    const ShotDigest& s = t.digests.shots[i];
    w.varint(i == 0 ? s.id : s.id - previous - 1);
    w.u16(s.digest);
    previous = s.id;
  }
  for (uint16_t d : t.digests.gates) w.u16(d);
  return w.data();
}

std::string endPayload(uint32_t tickCount, uint64_t finalHash) {
  ByteWriter w;
  w.varint(tickCount);
  w.u64(finalHash);
  return w.data();
}

}  // namespace

std::string encodeChunk(const char tag[4], const std::string& payload) {
  ByteWriter w;
  w.bytes(std::string_view(tag, 4));
  w.u32(uint32_t(payload.size()));
  w.bytes(payload);
  w.u32(crc32(w.data().data(), w.size()));
  return w.data();
}

void ReplayWriter::chunk(const char tag[4], const std::string& payload) {
  if (payload.size() > kMaxChunkBytes) throw std::runtime_error(std::string("replay chunk ") + std::string(tag, 4) + " too large");
  const std::string bytes = encodeChunk(tag, payload);
  out_.write(bytes.data(), std::streamsize(bytes.size()));
  if (!out_) throw std::runtime_error("cannot write the replay");
}

void ReplayWriter::begin(const std::vector<BuildFact>& build, const std::string& mapName, const std::string& mapJson,
                         const ReplayConfig& config, uint64_t initialStateHash, uint64_t initialWorldHash, const Snapshot& initial) {
  config_ = config;
  const std::string h = header();
  out_.write(h.data(), std::streamsize(h.size()));
  chunk("BILD", buildPayload(build));
  chunk("MAPJ", mapPayload(mapName, mapJson));
  chunk("CONF", configPayload(config));
  chunk("INIT", initPayload(initialStateHash, initialWorldHash));
  chunk("KEYF", keyframePayload(0, initial));
  lastHash_ = initialStateHash;
}

void ReplayWriter::tick(const TickRecord& record, const Snapshot* keyframe) {
  chunk("TICK", tickPayload(record));
  ticks_ = record.tick;
  lastHash_ = record.stateHash;
  if (keyframe) {
    chunk("KEYF", keyframePayload(record.tick, *keyframe));
    lastKeyframe_ = record.tick;
  }
}

void ReplayWriter::end(const Snapshot& last) {
  if (lastKeyframe_ != ticks_) chunk("KEYF", keyframePayload(ticks_, last));
  chunk("END!", endPayload(ticks_, lastHash_));
  out_.flush();
  if (!out_) throw std::runtime_error("cannot write the replay");
}

std::string encodeReplay(const Replay& r) {
  std::string out = header();
  out += encodeChunk("BILD", buildPayload(r.build));
  ByteWriter map;
  map.str(r.mapName);
  map.u64(r.mapHash);
  map.bytes(r.mapJson);
  out += encodeChunk("MAPJ", map.data());
  out += encodeChunk("CONF", configPayload(r.config));
  out += encodeChunk("INIT", initPayload(r.initialStateHash, r.initialWorldHash));
  size_t k = 0;
  auto keyframesAt = [&](uint32_t tick) {
    for (; k < r.keyframes.size() && r.keyframes[k].tick <= tick; ++k) {
      out += encodeChunk("KEYF", keyframePayload(r.keyframes[k].tick, r.keyframes[k].state));
    }
  };
  keyframesAt(0);
  for (const TickRecord& t : r.ticks) {
    out += encodeChunk("TICK", tickPayload(t));
    keyframesAt(t.tick);
  }
  out += encodeChunk("END!", endPayload(r.tickCount(), r.ticks.empty() ? r.initialStateHash : r.ticks.back().stateHash));
  return out;
}

}  // namespace rts::replay
