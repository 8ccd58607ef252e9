// Command scripts: a game's orders written by hand, for recording scenarios (the doorway rush, the
// projectile storm) without a person at the window. One command a line:
//
//   # a comment (from '#' to the end of the line, after a command too)
//   TICK move TEAM X Y [UNITS]   send units to (X, Y), world units
//   TICK stop TEAM [UNITS]       drop their orders
//   TICK gate TEAM GATE          open or close gate number GATE
//
// TICK is the tick the command applies before (0 = before the first tick). TEAM is blue, red, 0 or 1.
// UNITS is `all` (the default: the team's live units at that tick) or ids and ranges, `0-39,45`, of
// which the team's live units are taken.
#pragma once

#include <string>
#include <vector>

#include "game/commands.h"

namespace rts::replay {

struct ScriptLine {
  int line = 0;  ///< in the file, for messages
  uint32_t tick = 0;
  Command command;            ///< units empty and `all` set: the whole team
  bool allUnits = false;
  std::vector<std::pair<uint32_t, uint32_t>> ranges;  ///< inclusive id ranges when not `all`
};

class CommandScript : public CommandSource {
 public:
  /// Parses a script; throws std::runtime_error "FILE:LINE: why".
  static CommandScript parse(const std::string& text, const std::string& name);
  static CommandScript load(const std::string& path);
  /// Throws std::runtime_error "FILE:LINE: why" for a command the game cannot take: a gate its map
  /// does not have.
  void checkAgainst(const Game& game) const;

  void commandsFor(uint32_t tick, const Game& game, std::vector<Command>& out) override;
  size_t size() const { return lines_.size(); }

 private:
  std::vector<ScriptLine> lines_;  // by tick, then file order
  std::string name_;
  size_t next_ = 0;
};

}  // namespace rts::replay
