// The replay fuzzer's seeds and kept findings (fuzz/corpus/replay_reader/, fuzz/regressions/replay_reader/),
// under the promises the fuzzer checks (fuzz/replay_reader.cpp): every file is either refused with an
// error inside it, or read, written again byte for byte the same as the recording, and read back.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "format/replay_reader.h"
#include "format/replay_writer.h"

namespace {

std::vector<std::filesystem::path> inputsIn(const std::string& folder) {
  std::vector<std::filesystem::path> files;
  const std::filesystem::path dir = std::string(RATTLE_SOURCE_DIR) + "/" + folder;
  if (!std::filesystem::exists(dir)) return files;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && name != "README.md" && name != "seeds.txt") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::string contents(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

}  // namespace

TEST(ReplayFuzzInputs, TheSeedRecordingReadsAndWritesBackByteForByte) {
  const auto seeds = inputsIn("fuzz/corpus/replay_reader");
  ASSERT_FALSE(seeds.empty()) << "fuzz/corpus/replay_reader/ holds no seed";
  for (const auto& file : seeds) {
    const std::string bytes = contents(file);
    const auto r = rts::replay::readReplay(bytes);
    ASSERT_TRUE(r.ok()) << file.filename() << ": " << r.error.describe();
    EXPECT_TRUE(rts::replay::encodeReplay(*r.replay) == bytes) << file.filename() << ": written again, other bytes";
  }
}

// The fuzzer's property on the kept findings (none yet: a finding is kept by copying it into
// fuzz/regressions/replay_reader/, fuzz/README.md), on the seeds, and on the seeds cut short.
TEST(ReplayFuzzInputs, EveryInputIsRefusedCleanlyOrRoundTrips) {
  std::vector<std::pair<std::string, std::string>> inputs;
  for (const auto& file : inputsIn("fuzz/regressions/replay_reader")) inputs.push_back({file.filename().string(), contents(file)});
  for (const auto& file : inputsIn("fuzz/corpus/replay_reader")) {
    const std::string bytes = contents(file);
    inputs.push_back({file.filename().string(), bytes});
    for (size_t cut : {size_t{9}, size_t{100}, bytes.size() / 2, bytes.size() - 1})
      inputs.push_back({file.filename().string() + " cut at " + std::to_string(cut), bytes.substr(0, cut)});
  }
  int refused = 0, read = 0;
  for (const auto& [name, bytes] : inputs) {
    const auto r = rts::replay::readReplay(bytes);
    if (!r.ok()) {
      ++refused;
      EXPECT_LE(r.error.offset, bytes.size()) << name;
      EXPECT_FALSE(r.error.message.empty()) << name;
      EXPECT_LE(r.error.describe().size(), 2048u) << name;
      continue;
    }
    ++read;
    const std::string once = rts::replay::encodeReplay(*r.replay);
    const auto again = rts::replay::readReplay(once);
    ASSERT_TRUE(again.ok()) << name << ": " << again.error.describe();
    EXPECT_TRUE(rts::replay::encodeReplay(*again.replay) == once) << name;
  }
  EXPECT_GT(read, 0);
  EXPECT_GT(refused, 0);
}
