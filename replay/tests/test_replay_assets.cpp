// The recorded replays in assets/replays/: each verifies (every hash, digest and keyframe), and the
// frames listed in assets/golden/frames.txt match their golden PNGs.
//
// Tolerance: a pixel matches when each of its R, G and B channels is within kTolerance (of 255) of the
// golden's; every pixel must match. The same build with the same Mesa gives identical bytes; the margin
// absorbs rounding differences between Mesa builds, not a moved unit (a unit is a disk of some 4 pixels
// across in these 480x270 frames, drawn in full team colours, far more than 4 levels from its
// surroundings).
//
// A failed comparison writes <name>_actual.png and <name>_diff.png (differing pixels in red over the
// golden dimmed to grey) to build/golden-diffs/, and says so. Nothing here writes assets/golden/: that
// is `make update-goldens`.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "render/offscreen.h"
#include "render/png.h"
#include "replay_test_support.h"
#include "tool/frames.h"
#include "tool/image_compare.h"
#include "tool/replay_run.h"
#include "tool/verify.h"

namespace {

using namespace rts::replay;
using namespace replay_test;

constexpr int kTolerance = 4;

std::vector<std::string> assetReplays() {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(sourcePath("assets/replays"))) {
    if (e.path().extension() == ".replay") out.push_back(e.path().filename().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

struct Golden {
  std::string replay;
  uint32_t tick = 0;
  int width = 0, height = 0;
  int fog = 0;
  std::string png() const {
    char t[16];
    std::snprintf(t, sizeof t, "%06u", tick);
    return replay.substr(0, replay.size() - 7) + "_" + t + ".png";
  }
};

void PrintTo(const Golden& g, std::ostream* os) { *os << g.png(); }

std::vector<Golden> goldens() {
  std::vector<Golden> out;
  std::ifstream in(sourcePath("assets/golden/frames.txt"));
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    Golden g;
    std::string size, fog;
    if (!(words >> g.replay) || g.replay[0] == '#') continue;
    words >> g.tick >> size >> fog;
    std::sscanf(size.c_str(), "%dx%d", &g.width, &g.height);
    g.fog = fog == "none" ? -1 : std::atoi(fog.c_str());
    out.push_back(g);
  }
  return out;
}

TEST(ReplayAssets, ThereAreAtLeastThreeSmallReplays) {
  const std::vector<std::string> replays = assetReplays();
  EXPECT_GE(replays.size(), 3u);
  for (const char* name : {"arena.replay", "doorway-rush.replay", "projectile-storm.replay"}) {
    EXPECT_NE(std::find(replays.begin(), replays.end(), name), replays.end()) << name;
  }
  for (const std::string& name : replays) EXPECT_LT(std::filesystem::file_size(sourcePath("assets/replays/" + name)), 1u << 20) << name;
}

class AssetReplay : public testing::TestWithParam<std::string> {};

TEST_P(AssetReplay, VerifiesEveryTick) {
  const Replay r = parsed(readFile(sourcePath("assets/replays/" + GetParam())));
  EXPECT_GE(r.tickCount(), 100u);
  const VerifyReport report = verifyReplay(r);
  EXPECT_TRUE(report.ok()) << report.text(GetParam());
  EXPECT_EQ(report.ticksMatched, r.tickCount());
  // Build differences are fine (the replay was recorded by some build); a different arithmetic is not.
  if (!report.buildDifferences.empty()) std::printf("%s", report.text(GetParam()).c_str());
}

INSTANTIATE_TEST_SUITE_P(All, AssetReplay, testing::ValuesIn(assetReplays()), [](const auto& info) {
  std::string name = info.param.substr(0, info.param.size() - 7);
  for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return name;
});

TEST(ReplayAssets, EveryReplayHasGoldenFramesAndEveryGoldenIsListed) {
  const std::vector<Golden> list = goldens();
  for (const std::string& r : assetReplays()) {
    EXPECT_TRUE(std::any_of(list.begin(), list.end(), [&](const Golden& g) { return g.replay == r; })) << r << " has no golden frame";
  }
  for (const auto& e : std::filesystem::directory_iterator(sourcePath("assets/golden"))) {
    if (e.path().extension() != ".png") continue;
    const std::string name = e.path().filename().string();
    EXPECT_TRUE(std::any_of(list.begin(), list.end(), [&](const Golden& g) { return g.png() == name; })) << name << " is not in frames.txt";
  }
}

class GoldenFrame : public testing::TestWithParam<Golden> {};

TEST_P(GoldenFrame, MatchesWithinTolerance) {
  const Golden& g = GetParam();
  const Replay r = parsed(readFile(sourcePath("assets/replays/" + g.replay)));
  ASSERT_LE(g.tick, r.tickCount());
  ReplayRun run(r);
  while (run.tick() < g.tick) ASSERT_TRUE(run.step().ok()) << g.replay << " diverges at tick " << run.tick();
  FrameOptions options;
  options.width = g.width;
  options.height = g.height;
  options.fogTeam = g.fog;
  rts::OffscreenRenderer renderer(g.width, g.height, options.supersample);
  const std::vector<uint8_t> actual = drawFrame(renderer, run.game(), options);

  int w = 0, h = 0;
  std::vector<uint8_t> golden;
  const std::string goldenPath = sourcePath("assets/golden/" + g.png());
  ASSERT_EQ(rts::readPng(goldenPath, w, h, golden), "") << "run `make update-goldens` to make it";
  const ImageComparison c = compareImages(golden, w, h, actual, g.width, g.height, kTolerance);
  if (c.sameSize && c.differing == 0) return;

  const std::string dir = RATTLE_GOLDEN_DIFF_DIR;
  std::filesystem::create_directories(dir);
  const std::string stem = dir + "/" + g.png().substr(0, g.png().size() - 4);
  EXPECT_EQ(rts::writePng(stem + "_actual.png", g.width, g.height, actual), "");
  if (c.sameSize) {
    EXPECT_EQ(rts::writePng(stem + "_diff.png", w, h, c.diff), "");
  }
  ADD_FAILURE() << goldenPath << ": " << (c.sameSize ? std::to_string(c.differing) + " of " + std::to_string(c.pixels) + " pixels differ by more than " +
                                                           std::to_string(kTolerance) + " (largest difference " + std::to_string(c.largestDifference) + ")"
                                                     : "the golden is " + std::to_string(w) + "x" + std::to_string(h))
                << ". Wrote " << stem << "_actual.png" << (c.sameSize ? " and " + stem + "_diff.png" : std::string())
                << ". If the change is intended: make update-goldens.";
}

INSTANTIATE_TEST_SUITE_P(Listed, GoldenFrame, testing::ValuesIn(goldens()), [](const auto& info) {
  std::string name = info.param.png();
  name = name.substr(0, name.size() - 4);
  for (char& c : name) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return name;
});

}  // namespace
