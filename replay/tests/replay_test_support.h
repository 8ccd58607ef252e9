// Shared by the replay tests: paths, files, a small real replay recorded on the spot.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "format/replay_reader.h"
#include "format/replay_writer.h"
#include "tool/record.h"

namespace replay_test {

inline std::string sourcePath(const std::string& relative) { return std::string(RATTLE_SOURCE_DIR) + "/" + relative; }

inline std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

inline void writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

/// A per-test scratch path (ctest runs tests as parallel processes).
inline std::string scratch(const std::string& name) {
  const auto* info = testing::UnitTest::GetInstance()->current_test_info();
  return testing::TempDir() + "/rattle_replay_" + info->test_suite_name() + "_" + info->name() + "_" + name;
}

/// A small real replay: small.json, 4 units a team, the scripted opponent, `ticks` ticks, a keyframe
/// every 5 ticks. A few kilobytes: small enough to cut at every byte.
inline std::string smallReplay(uint32_t ticks = 40, uint32_t keyframeEvery = 5) {
  rts::replay::RecordRequest r;
  r.mapPath = sourcePath("assets/maps/small.json");
  r.seed = 3;
  r.ticks = ticks;
  r.unitsPerTeam = 4;
  r.keyframeEvery = keyframeEvery;
  r.output = scratch("small.replay");
  rts::replay::recordGame(r);
  return readFile(r.output);
}

inline rts::replay::Replay parsed(const std::string& bytes) {
  rts::replay::ReadResult r = rts::replay::readReplay(bytes);
  if (!r.ok()) ADD_FAILURE() << r.error.describe();
  return r.ok() ? std::move(*r.replay) : rts::replay::Replay{};
}

}  // namespace replay_test

namespace replay_test {

/// A replay file cut into its chunks, to change one and put the file back together with good CRCs:
/// hostile files that get past the checksums.
struct Chunk {
  std::string tag;
  std::string payload;
};

inline std::vector<Chunk> chunksOf(const std::string& file) {
  std::vector<Chunk> out;
  size_t pos = 10;
  while (pos + 12 <= file.size()) {
    uint32_t length = 0;
    for (int i = 0; i < 4; ++i) length |= uint32_t(uint8_t(file[pos + 4 + size_t(i)])) << (8 * i);
    out.push_back({file.substr(pos, 4), file.substr(pos + 8, length)});
    pos += 12 + length;
  }
  return out;
}

inline std::string assemble(const std::vector<Chunk>& chunks, uint16_t version = 1, const std::string& magic = "RATTLREP") {
  std::string out = magic;
  out += char(version & 0xFF);
  out += char(version >> 8);
  for (const Chunk& c : chunks) out += rts::replay::encodeChunk(c.tag.c_str(), c.payload);
  return out;
}

/// Index of the first chunk with this tag.
inline size_t firstChunk(const std::vector<Chunk>& chunks, const std::string& tag) {
  for (size_t i = 0; i < chunks.size(); ++i) {
    if (chunks[i].tag == tag) return i;
  }
  ADD_FAILURE() << "no chunk " << tag;
  return 0;
}

}  // namespace replay_test
