// Inputs the fuzzer (or a person) found to break the map reader, kept in fuzz/regressions/map_reader/:
// each must now give a MapError that names the file, within the same heap bound as the hostile maps.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "heap_meter.h"
#include "map/map_loader.h"

namespace {

std::vector<std::filesystem::path> regressionInputs() {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(std::string(RATTLE_SOURCE_DIR) + "/fuzz/regressions/map_reader")) {
    if (entry.is_regular_file() && entry.path().filename() != "README.md") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

TEST(MapRegressions, EveryKeptInputGivesACleanError) {
  const std::vector<std::filesystem::path> files = regressionInputs();
  ASSERT_FALSE(files.empty()) << "fuzz/regressions/map_reader/ holds no inputs";
  for (const std::filesystem::path& file : files) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream buffer;
    buffer << in.rdbuf();
    const std::string text = buffer.str();
    const std::string name = file.filename().string();
    rattle_test::HeapMeter meter;
    try {
      rts::parseMap(text, name);
      ADD_FAILURE() << name << ": accepted; a kept input must be refused with a MapError";
    } catch (const rts::MapError& e) {
      const std::string message = e.what();
      EXPECT_EQ(message.rfind(name + ": ", 0), 0u) << message;
      // The fuzzer's bound (fuzz/map_reader.cpp): one readable line, not a copy of the input.
      EXPECT_LE(message.size(), 2048u) << name << ": " << message.size() << " bytes";
    }
    EXPECT_LE(meter.peak(), 32 * text.size() + (64 << 10)) << name;
  }
}
