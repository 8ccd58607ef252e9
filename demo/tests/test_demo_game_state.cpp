// A game's state as bytes (Game::saveState, Game::restoreState) and the ReloadWorld command: a game built
// from the same map and config and given another's state at tick T plays on exactly as that one does
// after a ReloadWorld at T, with the same commands; bad bytes are refused with the field named and leave
// the game as it was.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "game/game.h"
#include "game/opponent.h"
#include "game/tick_loop.h"
#include "map/map_loader.h"

namespace {

using rts::Command;
using rts::CommandType;
using rts::Game;
using rts::GameConfig;

std::string assetPath(const std::string& name) { return std::string(RATTLE_SOURCE_DIR) + "/assets/maps/" + name; }

GameConfig config(int units, rattle::StepMode mode = rattle::StepMode::Hybrid) {
  GameConfig c;
  c.unitsPerTeam = units;
  c.stepMode = mode;
  return c;
}

Command reloadWorld(uint32_t tick) {
  Command c;
  c.tick = tick;
  c.type = CommandType::ReloadWorld;
  return c;
}

// Plays `ticks` ticks of the scripted opponent for both teams, with a ReloadWorld at `reloadAt`; returns
// the commands applied before each tick.
std::vector<std::vector<Command>> play(Game& g, uint32_t ticks, uint32_t reloadAt, std::string* stateAtReload) {
  rts::ScriptedOpponent opponent(7);
  rts::TickLoop loop(g);
  loop.add(opponent);
  std::vector<std::vector<Command>> log;
  for (uint32_t t = 0; t < ticks; ++t) {
    if (g.tickCount() == reloadAt && stateAtReload) *stateAtReload = g.saveState();
    std::vector<Command> commands = loop.applyCommands();
    if (g.tickCount() == reloadAt) {
      EXPECT_TRUE(g.apply(reloadWorld(reloadAt)));
      commands.push_back(reloadWorld(reloadAt));
    }
    g.tick();
    log.push_back(std::move(commands));
  }
  return log;
}

TEST(DemoGameState, ARestoredGameSavesTheSameBytesAndHashesTheSame) {
  for (rattle::StepMode mode : {rattle::StepMode::Hybrid, rattle::StepMode::Predictive, rattle::StepMode::Discrete}) {
    Game g(rts::loadMap(assetPath("arena.json")), config(40, mode));
    play(g, 150, 1000, nullptr);
    const std::string state = g.saveState();
    Game other(rts::loadMap(assetPath("arena.json")), config(40, mode));
    other.restoreState(state);
    EXPECT_EQ(other.saveState(), state);
    EXPECT_EQ(other.stateHash(), g.stateHash());
    EXPECT_EQ(other.tickCount(), 150u);
    EXPECT_EQ(other.alive(0), g.alive(0));
    EXPECT_EQ(other.alive(1), g.alive(1));
  }
}

// The players' game takes a ReloadWorld at tick T; a spectator's game is built from the map and config,
// takes the players' state at T and the same commands from T on: every hash after it is the same.
TEST(DemoGameState, AGameStartedFromTheStateAtAReloadPlaysAsThePlayersGame) {
  for (rattle::StepMode mode : {rattle::StepMode::Hybrid, rattle::StepMode::Predictive, rattle::StepMode::Discrete}) {
    SCOPED_TRACE(int(mode));
    const uint32_t T = 120, ticks = 420;
    Game players(rts::loadMap(assetPath("arena.json")), config(60, mode));
    std::string state;
    std::vector<uint64_t> hashes;
    std::vector<std::vector<Command>> log;
    {
      rts::ScriptedOpponent opponent(7);
      rts::TickLoop loop(players);
      loop.add(opponent);
      for (uint32_t t = 0; t < ticks; ++t) {
        if (t == T) state = players.saveState();
        std::vector<Command> commands = loop.applyCommands();
        if (t == T) {
          ASSERT_TRUE(players.apply(reloadWorld(T)));
          commands.push_back(reloadWorld(T));
        }
        players.tick();
        log.push_back(std::move(commands));
        hashes.push_back(players.stateHash());
      }
    }
    ASSERT_GT(players.stats().shotsFired, 0) << "the game should be under way";
    Game spectator(rts::loadMap(assetPath("arena.json")), config(60, mode));
    spectator.restoreState(state);
    ASSERT_EQ(spectator.tickCount(), T);
    for (uint32_t t = T; t < ticks; ++t) {
      for (const Command& c : log[t]) spectator.apply(c);
      spectator.tick();
      ASSERT_EQ(spectator.stateHash(), hashes[t]) << "tick " << t;
    }
  }
}

// The bytes of a small game's state, each changed in turn (by 0x01 and by 0xFF): refused with a
// GameError that names the byte, leaving the game unchanged, or taken into a game that then ticks. In
// the discrete mode a 0x01 in a zero makeWay made it subnormal, its length 0 and the unit's velocity NaN
// (the game_state fuzzer's fuzz/regressions/game_state/nan-velocity-from-a-subnormal-make-way).
TEST(DemoGameState, EveryByteChangedIsRefusedAndLeavesTheGameOrTicks) {
  int refused = 0, taken = 0;
  for (rattle::StepMode mode : {rattle::StepMode::Hybrid, rattle::StepMode::Discrete}) {
    Game g(rts::loadMap(assetPath("small.json")), config(3, mode));
    {
      rts::ScriptedOpponent opponent(5);
      rts::TickLoop loop(g);
      loop.add(opponent);
      for (int t = 0; t < 40; ++t) loop.tick();
    }
    const std::string state = g.saveState();
    Game target(rts::loadMap(assetPath("small.json")), config(3, mode));
    const std::string before = target.saveState();
    // The world's bytes are checked by World::load (tests/test_world_save.cpp): here every byte of the
    // game's own part, and every 29th of the world's, whose checksum World::load then refuses.
    const size_t worldAt = state.find("RTLW");
    ASSERT_NE(worldAt, std::string::npos);
    for (size_t at = 0; at < state.size(); at += at < worldAt + 8 ? 1 : 29) {
      for (uint8_t change : {uint8_t{0x01}, uint8_t{0xFF}}) {
        std::string bad = state;
        bad[at] = char(uint8_t(bad[at]) ^ change);
        Game t(rts::loadMap(assetPath("small.json")), config(3, mode));
        try {
          t.restoreState(bad);
          for (int k = 0; k < 3; ++k) t.tick();
          ++taken;
        } catch (const rts::GameError& e) {
          ++refused;
          EXPECT_EQ(std::string(e.what()).rfind("game state: ", 0), 0u) << e.what();
          EXPECT_EQ(t.saveState(), before) << "a refused state changed the game (byte " << at << ")";
        }
      }
    }
  }
  const std::string state = [] {
    Game g(rts::loadMap(assetPath("small.json")), config(2));
    play(g, 40, 1000, nullptr);
    return g.saveState();
  }();
  Game target(rts::loadMap(assetPath("small.json")), config(2));
  const std::string before = target.saveState();
  EXPECT_GT(refused, 0);
  EXPECT_GT(taken, 0);
  for (size_t n = 0; n < state.size(); n += 7) {
    EXPECT_THROW(target.restoreState(std::string_view(state).substr(0, n)), rts::GameError) << n;
  }
  EXPECT_EQ(target.saveState(), before);
  try {
    std::string other = state;
    other[0] = 'X';
    target.restoreState(other);
    ADD_FAILURE() << "a state without its magic was taken";
  } catch (const rts::GameError& e) {
    EXPECT_EQ(std::string(e.what()), "game state: byte 0: magic: not a game's state (it does not start with \"RTSG\")");
  }
  // Another game's state: more units than this one has.
  Game bigger(rts::loadMap(assetPath("small.json")), config(3));
  try {
    target.restoreState(bigger.saveState());
    ADD_FAILURE() << "a state of another size was taken";
  } catch (const rts::GameError& e) {
    EXPECT_NE(std::string(e.what()).find("byte 13: unit count: 6 is out of range (at most 4)"), std::string::npos)
        << e.what();
  }
}

}  // namespace
