// How the game steers its units (GameConfig::steering; rattle-demo --steering).
#pragma once

namespace rts {

enum class Steering {
  /// The default: units keep apart, queue and wait for gaps (units.cpp, Game::keepApart; demo/README.md,
  /// "Crowds"), so the engine seldom resolves a collision between units.
  KeepApart,
  /// Every unit with an order is sent at its full speed down its flow field toward its target, whatever
  /// stands in the way: no keeping apart, no queueing, no stepping aside, no slowing near the target. A
  /// crowd is pushed into itself and the engine keeps it apart: the case issue 24 measures.
  Naive,
};

}  // namespace rts
