#include "tool/command_script.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "game/game.h"
#include "map/errno_reason.h"

namespace rts::replay {
namespace {

constexpr size_t kMaxScriptBytes = 4u << 20;

bool parseUnsigned(const std::string& s, uint64_t hi, uint64_t& out) {
  if (s.empty() || s.size() > 12 || !std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; })) return false;
  out = std::stoull(s);
  return out <= hi;
}

}  // namespace

CommandScript CommandScript::parse(const std::string& text, const std::string& name) {
  CommandScript script;
  std::istringstream in(text);
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    auto fail = [&](const std::string& why) -> std::runtime_error {
      return std::runtime_error(name + ":" + std::to_string(number) + ": " + why);
    };
    // A comment runs from '#' to the end of the line, after a command too (replay/README.md's example).
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream words(line);
    std::string tickWord, kind, teamWord;
    if (!(words >> tickWord)) continue;
    ScriptLine s;
    s.line = number;
    uint64_t v = 0;
    if (!parseUnsigned(tickWord, 100'000'000, v)) throw fail("'" + tickWord + "': expected a tick number");
    s.tick = uint32_t(v);
    s.command.tick = s.tick;
    if (!(words >> kind)) throw fail("expected move, stop, gate or reload after the tick");
    if (!(words >> teamWord)) throw fail("expected a team (blue, red, 0 or 1)");
    if (teamWord == "blue" || teamWord == "0") {
      s.command.team = 0;
    } else if (teamWord == "red" || teamWord == "1") {
      s.command.team = 1;
    } else {
      throw fail("'" + teamWord + "': expected a team (blue, red, 0 or 1)");
    }
    std::string unitsWord = "all";
    if (kind == "move") {
      s.command.type = CommandType::Move;
      std::string x, y;
      if (!(words >> x >> y)) throw fail("move: expected X Y");
      try {
        size_t ex = 0, ey = 0;
        s.command.target = {std::stod(x, &ex), std::stod(y, &ey)};
        if (ex != x.size() || ey != y.size() || !std::isfinite(s.command.target.x) || !std::isfinite(s.command.target.y)) throw std::invalid_argument("");
      } catch (const std::exception&) {
        throw fail("move: '" + x + " " + y + "': expected two numbers");
      }
      words >> unitsWord;
    } else if (kind == "stop") {
      s.command.type = CommandType::Stop;
      words >> unitsWord;
    } else if (kind == "gate") {
      s.command.type = CommandType::ToggleGate;
      std::string g;
      if (!(words >> g) || !parseUnsigned(g, 31, v)) throw fail("gate: expected a gate number (0 to 31)");
      s.command.gate = uint32_t(v);
    } else if (kind == "reload") {
      s.command.type = CommandType::ReloadWorld;
    } else {
      throw fail("'" + kind + "': expected move, stop, gate or reload");
    }
    if (s.command.type == CommandType::Move || s.command.type == CommandType::Stop) {
      if (unitsWord == "all") {
        s.allUnits = true;
      } else {
        std::istringstream parts(unitsWord);
        std::string part;
        while (std::getline(parts, part, ',')) {
          const size_t dash = part.find('-');
          uint64_t lo = 0, hi = 0;
          if (dash == std::string::npos ? !parseUnsigned(part, UINT32_MAX, lo)
                                        : !parseUnsigned(part.substr(0, dash), UINT32_MAX, lo) || !parseUnsigned(part.substr(dash + 1), UINT32_MAX, hi)) {
            throw fail("'" + unitsWord + "': expected all, or unit ids and ranges like 0-39,45");
          }
          if (dash == std::string::npos) hi = lo;
          if (hi < lo) throw fail("'" + part + "': an empty range");
          s.ranges.push_back({uint32_t(lo), uint32_t(hi)});
        }
      }
    }
    std::string extra;
    if (words >> extra) throw fail("'" + extra + "': unexpected text at the end of the line");
    script.lines_.push_back(std::move(s));
  }
  std::stable_sort(script.lines_.begin(), script.lines_.end(), [](const ScriptLine& a, const ScriptLine& b) { return a.tick < b.tick; });
  script.name_ = name;
  return script;
}

void CommandScript::checkAgainst(const Game& game) const {
  // A replay's reader refuses a gate the map does not have; a recording must never hold one.
  const size_t gates = game.gates().size();
  for (const ScriptLine& s : lines_) {
    if (s.command.type != CommandType::ToggleGate || s.command.gate < gates) continue;
    throw std::runtime_error(name_ + ":" + std::to_string(s.line) + ": gate " + std::to_string(s.command.gate) +
                             (gates == 0 ? std::string(": the map has no gates")
                                         : ": the map's gates are 0 to " + std::to_string(gates - 1)));
  }
}

CommandScript CommandScript::load(const std::string& path) {
  // A directory opens and reads as empty: it would pass for a script with no commands.
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) throw std::runtime_error(path + ": is a directory, not a command script");
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot open the command script" + errnoReason());
  std::string text;
  char buf[65536];
  while (in.read(buf, sizeof buf) || in.gcount() > 0) {
    text.append(buf, size_t(in.gcount()));
    if (text.size() > kMaxScriptBytes) throw std::runtime_error(path + ": a command script may be at most 4 MiB");
  }
  return parse(text, path);
}

void CommandScript::commandsFor(uint32_t tick, const Game& game, std::vector<Command>& out) {
  while (next_ < lines_.size() && lines_[next_].tick < tick) ++next_;  // lines for ticks already past
  for (; next_ < lines_.size() && lines_[next_].tick == tick; ++next_) {
    const ScriptLine& s = lines_[next_];
    Command c = s.command;
    c.tick = tick;
    if (c.type == CommandType::Move || c.type == CommandType::Stop) {
      for (const Unit& u : game.units()) {
        if (!u.alive || u.team != c.team) continue;
        const bool chosen = s.allUnits || std::any_of(s.ranges.begin(), s.ranges.end(), [&](auto r) { return u.id >= r.first && u.id <= r.second; });
        if (chosen) c.units.push_back(u.id);
      }
      if (c.units.empty()) continue;  // nobody left to order
    }
    out.push_back(std::move(c));
  }
}

}  // namespace rts::replay
