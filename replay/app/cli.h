// rattle-replay's subcommands and what they share: argument helpers, exit statuses, the progress line.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace rts::replay::cli {

/// Exit statuses: 0 done (verify: every tick matches), 1 verify found a divergence or the work failed
/// (a file could not be written), 2 bad usage or a malformed replay.
enum Exit { kOk = 0, kFailed = 1, kBadInput = 2 };

int runInfo(const std::vector<std::string>& args);
int runVerify(const std::vector<std::string>& args);
int runRender(const std::vector<std::string>& args);
int runRecord(const std::vector<std::string>& args);

/// Prints "rattle-replay SUB: message" and the hint to use --help; returns kBadInput.
int usageError(const std::string& sub, const std::string& message);
/// A whole number in [lo, hi].
bool parseNumber(const std::string& text, uint64_t lo, uint64_t hi, uint64_t& out);
/// The argument after args[i], advancing i to it; nullptr when args[i] is the last.
const std::string* nextValue(const std::vector<std::string>& args, size_t& i);
/// The argument after the option args[i] (advancing i) as a whole number in [lo, hi]: -1 when it is one,
/// otherwise the status of the usage error it printed, naming the option and the value.
int nextNumber(const std::string& sub, const std::vector<std::string>& args, size_t& i, uint64_t lo, uint64_t hi,
               uint64_t& out);
/// WIDTHxHEIGHT, each 16 to 8192.
bool parseSize(const std::string& text, int& width, int& height);

/// A progress line on stderr: shown only once a run has taken half a second, refreshed a few times a
/// second on a terminal (every 5 s otherwise), ended by done().
class Progress {
 public:
  Progress(std::string what, bool enabled);
  void update(uint32_t tick, uint32_t total);
  void done();

 private:
  using Clock = std::chrono::steady_clock;
  std::string what_;
  bool enabled_, tty_, shown_ = false;
  Clock::time_point start_, last_;
  uint32_t tick_ = 0, total_ = 0;
};

}  // namespace rts::replay::cli

#include <optional>

#include "format/replay.h"

namespace rts::replay::cli {

/// Reads a replay; on failure prints "rattle-replay SUB: FILE: not a valid replay: byte N: field: why"
/// and returns nothing (the caller exits with kBadInput).
std::optional<Replay> loadReplay(const std::string& sub, const std::string& path);

}  // namespace rts::replay::cli
