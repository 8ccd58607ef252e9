// Recording and verifying: recording changes nothing; a recorded game verifies; a changed command, a
// changed keyframe or another build are reported as they should be, to the tick, body and field.
#include <gtest/gtest.h>

#include <cmath>

#include "format/checksum.h"
#include "game/opponent.h"
#include "game/tick_loop.h"
#include "map/map_loader.h"
#include "replay_test_support.h"
#include "tool/build_facts.h"
#include "tool/divergence.h"
#include "tool/recorder.h"
#include "tool/verify.h"

namespace {

using namespace rts::replay;
using namespace replay_test;

TEST(ReplayVerify, RecordingDoesNotChangeTheGame) {
  const std::string mapPath = sourcePath("assets/maps/arena.json");
  rts::GameConfig config;
  config.unitsPerTeam = 20;
  rts::Game plain(rts::loadMap(mapPath), config), recorded(rts::loadMap(mapPath), config);
  rts::ScriptedOpponent a(9), b(9);
  RecordingInfo info;
  info.mapJson = rts::readMapFile(mapPath);
  info.keyframeEvery = 7;
  Recorder recorder(scratch("r.replay"), info, recorded);
  rts::TickLoop playing(plain), recording(recorded);
  playing.add(a);
  recording.add(b);
  for (int t = 0; t < 150; ++t) {
    playing.tick();
    recorder.afterTick(recorded, recording.tick());
    ASSERT_EQ(plain.stateHash(), recorded.stateHash()) << "tick " << plain.tickCount();
  }
  recorder.finish(recorded);
  const Replay r = parsed(readFile(scratch("r.replay")));
  EXPECT_EQ(r.ticks.back().stateHash, plain.stateHash());
  EXPECT_TRUE(verifyReplay(r).ok());
  EXPECT_FALSE(std::filesystem::exists(scratch("r.replay.part")));
}

TEST(ReplayVerify, AnUnfinishedRecordingLeavesNoFile) {
  const std::string mapPath = sourcePath("assets/maps/small.json");
  rts::GameConfig config;
  config.unitsPerTeam = 2;
  rts::Game game(rts::loadMap(mapPath), config);
  RecordingInfo info;
  info.mapJson = rts::readMapFile(mapPath);
  {
    Recorder recorder(scratch("u.replay"), info, game);
    game.tick();
    recorder.afterTick(game, {});
  }
  EXPECT_FALSE(std::filesystem::exists(scratch("u.replay")));
  EXPECT_FALSE(std::filesystem::exists(scratch("u.replay.part")));
}

TEST(ReplayVerify, ARecordedGameVerifies) {
  const Replay r = parsed(smallReplay(60, 10));
  const VerifyReport report = verifyReplay(r);
  EXPECT_TRUE(report.ok()) << report.text("small");
  EXPECT_TRUE(report.buildDifferences.empty());
  EXPECT_EQ(report.ticksMatched, 60u);
  EXPECT_NE(report.text("small").find("all 60 ticks match"), std::string::npos);
}

// Finds a move command at least `minTick` into the replay; returns its record index.
size_t firstMoveAfter(const Replay& r, uint32_t minTick, size_t& command) {
  for (size_t t = minTick; t < r.ticks.size(); ++t) {
    for (size_t c = 0; c < r.ticks[t].commands.size(); ++c) {
      if (r.ticks[t].commands[c].type == rts::CommandType::Move) {
        command = c;
        return t;
      }
    }
  }
  ADD_FAILURE() << "no move command";
  return 0;
}

TEST(ReplayVerify, ATamperedCommandFailsAtItsTickNamingTheBodies) {
  Replay r = parsed(readFile(sourcePath("assets/replays/arena.replay")));
  size_t c = 0;
  const size_t t = firstMoveAfter(r, 50, c);
  rts::Command& command = r.ticks[t].commands[c];
  command.target.x += 7;  // somewhere else on the map
  const uint32_t tick = r.ticks[t].tick;
  // Through the bytes, as a user's tampered file would come.
  const Replay tampered = parsed(encodeReplay(r));
  const VerifyReport report = verifyReplay(tampered);
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.divergence->tick, tick) << report.text("arena");
  EXPECT_EQ(report.ticksMatched, tick - 1);
  // The units ordered differ at once: they hold a different target (their digests cover it).
  const std::string first = unitName(*buildGame(tampered), command.units[0]);
  EXPECT_NE(std::find(report.divergence->bodies.begin(), report.divergence->bodies.end(), first), report.divergence->bodies.end())
      << report.text("arena");
  // The fields, at the next keyframe: the target, by 7.
  const TickCheck& fields = report.divergence->keyframe ? *report.divergence : *report.keyframeAfter;
  bool targetNamed = false;
  for (const FieldDiff& f : fields.fields) targetNamed |= f.body == first && f.field == "order.target.x";
  EXPECT_TRUE(targetNamed) << report.text("arena");
  const std::string text = report.text("arena");
  EXPECT_NE(text.find("diverges at tick " + std::to_string(tick)), std::string::npos) << text;
}

TEST(ReplayVerify, ATamperedKeyframeNamesTheBodyTheFieldAndTheAmount) {
  Replay r = parsed(smallReplay(30, 10));
  ASSERT_GE(r.keyframes.size(), 3u);
  UnitState& u = r.keyframes[2].state.units[3];  // tick 20
  ASSERT_TRUE(u.alive);
  u.motion.px = std::nextafter(u.motion.px, 1e9);
  const VerifyReport report = verifyReplay(parsed(encodeReplay(r)));
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.divergence->tick, 20u);
  ASSERT_EQ(report.divergence->fields.size(), 1u) << report.text("small");
  const FieldDiff& f = report.divergence->fields[0];
  EXPECT_EQ(f.body, "unit 3 (red)");
  EXPECT_EQ(f.field, "position.x");
  EXPECT_NE(f.delta.find(", 1 ulp"), std::string::npos) << f.delta;
  EXPECT_NE(report.text("small").find("unit 3 (red) position.x: recorded"), std::string::npos) << report.text("small");
}

TEST(ReplayVerify, ATamperedHashIsCaughtAtItsTick) {
  Replay r = parsed(smallReplay(30, 10));
  r.ticks[16].stateHash ^= 1;  // tick 17
  const VerifyReport report = verifyReplay(parsed(encodeReplay(r)));
  ASSERT_FALSE(report.ok());
  EXPECT_EQ(report.divergence->tick, 17u);
  ASSERT_TRUE(report.keyframeAfter);
  EXPECT_EQ(report.keyframeAfter->tick, 20u);
  EXPECT_TRUE(report.keyframeAfter->fields.empty());
}

TEST(ReplayVerify, ADifferentBuildIsReportedFirstThenTheHashes) {
  Replay r = parsed(smallReplay(20, 10));
  for (BuildFact& f : r.build) {
    if (f.key == "compiler") f.value = "Clang 99.0.0";
  }
  r.build.push_back({"flags seen only there", "-O3"});
  const VerifyReport report = verifyReplay(parsed(encodeReplay(r)));
  EXPECT_TRUE(report.ok());
  ASSERT_EQ(report.buildDifferences.size(), 2u);
  const std::string text = report.text("small");
  EXPECT_EQ(text.find("small: recorded by a different build:"), 0u) << text;
  EXPECT_NE(text.find("compiler: recorded \"Clang 99.0.0\", this build \""), std::string::npos) << text;
  EXPECT_NE(text.find("all 20 ticks match"), std::string::npos) << text;
  EXPECT_LT(text.find("compiler"), text.find("all 20 ticks match"));
}

TEST(ReplayVerify, ABadEmbeddedMapIsASetupError) {
  Replay r = parsed(smallReplay(5, 5));
  r.mapJson = "{\"type\": \"map\"}";
  r.mapHash = fnv1a64(r.mapJson);
  const ReadResult read = readReplay(encodeReplay(r));
  ASSERT_TRUE(read.ok()) << "the reader does not parse the map";
  try {
    verifyReplay(*read.replay);
    FAIL() << "no error";
  } catch (const ReplaySetupError& e) {
    EXPECT_NE(std::string(e.what()).find("bad embedded map"), std::string::npos) << e.what();
  }
}

TEST(ReplayVerify, UlpDistance) {
  EXPECT_EQ(ulpDistance(1.0, 1.0), 0);
  EXPECT_EQ(ulpDistance(1.0, std::nextafter(1.0, 2.0)), 1);
  EXPECT_EQ(ulpDistance(0.0, -0.0), 0);
  EXPECT_EQ(ulpDistance(-std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::denorm_min()), 2);
  EXPECT_EQ(ulpDistance(1.0, std::nan("")), std::numeric_limits<int64_t>::max());
}

}  // namespace
