// Pinned hashes (as Box2D's and Jolt's determinism tests pin theirs): fixed scenes stepped a fixed
// number of ticks in each mode must end at the hash recorded here. A change that claims to keep
// behaviour (a refactor, a faster path) fails here at once when it does not. A change that means to
// alter behaviour updates the table and says so in its commit; `rattle-trace` prints the same
// hashes, tick by tick, to find the first tick that moved:
//   rattle-trace --steps 240 --disks 200 --game-ticks 300 --units 50 --only pile/hybrid
#include <gtest/gtest.h>

#include <rattle/rattle.h>

#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "engine_scenes.h"
#include "game_scene.h"
#include "map/map_loader.h"

namespace {

constexpr int kEngineSteps = 240;
constexpr int kDisks = 200;
constexpr int kGameTicks = 300;
constexpr int kUnitsPerTeam = 50;

struct Pinned {
  const char* scene;
  rattle::StepMode mode;
  uint64_t hash;  // the last line rattle-trace prints for the scene
};

using rattle::StepMode;
const Pinned kPinned[] = {
    {"gas", StepMode::Discrete, 0x86c8116bfbbf36e8},       {"gas", StepMode::Hybrid, 0xef8626af8f7350c0},
    {"gas", StepMode::Predictive, 0xc6fb1d9b81e9f0b8},     {"pile", StepMode::Discrete, 0x59db58347c70023b},
    {"pile", StepMode::Hybrid, 0x78b4934a912bce0b},        {"pile", StepMode::Predictive, 0xb0689ca28cb03c4a},
    {"bullets", StepMode::Discrete, 0xe0e44a1acacf69c4},   {"bullets", StepMode::Hybrid, 0x4967d9a4a82be735},
    {"bullets", StepMode::Predictive, 0x96540e0f02999b15}, {"sensors", StepMode::Discrete, 0xacda9670e7a43d36},
    {"sensors", StepMode::Hybrid, 0xb0079c3b59625bff},     {"sensors", StepMode::Predictive, 0xf966fb83ffdda990},
    {"crowd", StepMode::Discrete, 0xcf9c0c699a7ab4d5},     {"crowd", StepMode::Hybrid, 0x51f8587a3dc03c61},
    {"crowd", StepMode::Predictive, 0xec93c2e42913e1f9},
    {"kinematic", StepMode::Discrete, 0x9ed1833edbb1ba4e}, {"kinematic", StepMode::Hybrid, 0xa03e4cc8bff84ea0},
    {"kinematic", StepMode::Predictive, 0x494ee097476d774d},
    {"game", StepMode::Discrete, 0xf58e526bef8dd05f},      {"game", StepMode::Hybrid, 0x240b7c8aa35003f7},
    {"game", StepMode::Predictive, 0xa0390ba1e293e3d4},
};

const char* modeName(StepMode m) {
  switch (m) {
    case StepMode::Discrete: return "discrete";
    case StepMode::Hybrid: return "hybrid";
    case StepMode::Predictive: return "predictive";
  }
  return "?";
}

std::string hex(uint64_t h) {
  char text[20];
  std::snprintf(text, sizeof text, "%016" PRIx64, h);
  return text;
}

// The game loop of rattle-trace's game scene: both teams played by the scripted opponent (seed 1).
uint64_t gameHash(StepMode mode) {
  rattle_trace::GameScene game(rts::loadMap(RATTLE_PINNED_MAP), mode, kUnitsPerTeam, 1);
  uint64_t hash = 0;
  for (int t = 0; t < kGameTicks; ++t) hash = game.tick();
  return hash;
}

uint64_t engineSceneHash(const std::string& name, StepMode mode) {
  rattle_trace::EngineScene s = rattle_trace::buildEngineScene(name, mode, kDisks);
  for (int step = 0; step < kEngineSteps; ++step) {
    if (s.beforeStep) s.beforeStep(s, step);
    s.world.step(s.dt);
  }
  return rattle_trace::stepHash(s.world);
}

class PinnedHash : public ::testing::TestWithParam<Pinned> {};

TEST_P(PinnedHash, TheSceneEndsWhereItDidWhenPinned) {
  const Pinned& p = GetParam();
  const std::string scene = p.scene;
  const uint64_t hash = scene == "game" ? gameHash(p.mode) : engineSceneHash(scene, p.mode);
  EXPECT_EQ(hex(hash), hex(p.hash)) << scene << "/" << modeName(p.mode)
                                    << " moved: if the change means to alter behaviour, pin the new hash and "
                                       "say so in the commit (rattle-trace finds the first tick that differs)";
}

INSTANTIATE_TEST_SUITE_P(EveryScene, PinnedHash, ::testing::ValuesIn(kPinned),
                         [](const ::testing::TestParamInfo<Pinned>& info) {
                           return std::string(info.param.scene) + "_" + modeName(info.param.mode);
                         });

// Every scene rattle-trace runs is pinned in every mode.
TEST(PinnedHashes, CoverEverySceneOfTheTrace) {
  for (const std::string& scene : rattle_trace::engineSceneNames()) {
    for (StepMode mode : {StepMode::Discrete, StepMode::Hybrid, StepMode::Predictive}) {
      bool found = false;
      for (const Pinned& p : kPinned) found = found || (scene == p.scene && mode == p.mode);
      EXPECT_TRUE(found) << scene << "/" << modeName(mode) << " has no pinned hash";
    }
  }
}

}  // namespace
