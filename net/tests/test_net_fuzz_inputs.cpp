// The net_packet fuzzer's seeds and kept findings (fuzz/corpus/net_packet/, fuzz/regressions/net_packet/)
// under the property the fuzzer checks (fuzz/net_packet.cpp).
//
// The seeds are the encodings of net_test::sampleMessages(), one file each. This test is also their
// generator: after a change to the protocol, write them again with
//   RATTLE_WRITE_NET_SEEDS=1 build/bin/rattle_net_protocol_tests --gtest_filter='NetPacketFuzzInputs.*'
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "net_test_support.h"

namespace {

using namespace net_test;
namespace fs = std::filesystem;

const fs::path kSeeds = fs::path(RATTLE_SOURCE_DIR) / "fuzz/corpus/net_packet";
const fs::path kRegressions = fs::path(RATTLE_SOURCE_DIR) / "fuzz/regressions/net_packet";

std::vector<uint8_t> readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::vector<fs::path> inputsIn(const fs::path& dir) {
  std::vector<fs::path> files;
  if (!fs::exists(dir)) return files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && name != "README.md" && name != "seeds.txt") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(NetPacketFuzzInputs, TheSeedsAreTheSampleMessagesEncoded) {
  const char* write = std::getenv("RATTLE_WRITE_NET_SEEDS");
  if (write != nullptr && std::string(write) == "1") {
    fs::create_directories(kSeeds);
    for (const auto& [name, message] : sampleMessages()) {
      const std::vector<uint8_t> bytes = encode(message);
      std::ofstream out(kSeeds / name, std::ios::binary | std::ios::trunc);
      out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
      ASSERT_TRUE(out.good()) << (kSeeds / name);
    }
  }
  for (const auto& [name, message] : sampleMessages()) {
    ASSERT_TRUE(fs::exists(kSeeds / name))
        << (kSeeds / name) << " is missing; write the seeds again (see the top of this file)";
    EXPECT_EQ(readFile(kSeeds / name), encode(message))
        << name << ": the seed is out of date; write the seeds again (see the top of this file)";
    const Decoded d = decodeBytes(readFile(kSeeds / name), contextFor(message));
    ASSERT_TRUE(d.ok()) << name << ": " << d.error;
    expectSame(message, *d.message, name);
  }
}

// The kept findings (none yet: a finding is kept by copying it into fuzz/regressions/net_packet/), the
// seeds, and every seed cut short or with a byte more, under the three contexts the fuzzer uses.
TEST(NetPacketFuzzInputs, EveryInputIsRefusedCleanlyOrRoundTrips) {
  std::vector<std::pair<std::string, std::vector<uint8_t>>> inputs;
  for (const auto& file : inputsIn(kRegressions)) inputs.push_back({file.filename().string(), readFile(file)});
  const auto seeds = inputsIn(kSeeds);
  ASSERT_GE(seeds.size(), 5u) << kSeeds << " holds too few seeds";
  for (const auto& file : seeds) {
    const std::vector<uint8_t> bytes = readFile(file);
    inputs.push_back({file.filename().string(), bytes});
    for (size_t n = 0; n < bytes.size(); ++n) {
      inputs.push_back({file.filename().string() + " cut at " + std::to_string(n),
                        {bytes.begin(), bytes.begin() + std::ptrdiff_t(n)}});
    }
    std::vector<uint8_t> longer = bytes;
    longer.push_back(0x20);
    inputs.push_back({file.filename().string() + " and a byte", longer});
  }
  int decoded = 0, refused = 0;
  for (const auto& [name, bytes] : inputs) {
    for (const DecodeContext& context : {noGame(), largestGame(), snapshotGame()}) {
      (expectRefusedCleanlyOrRoundTrips(bytes, context, name) ? decoded : refused)++;
    }
  }
  // Every seed decodes under the largest game or its own (the test above checks their values); no cut
  // one does.
  EXPECT_GE(decoded, int(seeds.size()));
  EXPECT_GT(refused, 500);
}

}  // namespace
