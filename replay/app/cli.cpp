#include "app/cli.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cerrno>
#include <cstdlib>
#include <cstring>

namespace rts::replay::cli {

int usageError(const std::string& sub, const std::string& message) {
  std::fprintf(stderr, "rattle-replay %s: %s\nTry 'rattle-replay %s --help'.\n", sub.c_str(), message.c_str(), sub.c_str());
  return kBadInput;
}

const std::string* nextValue(const std::vector<std::string>& args, size_t& i) {
  return i + 1 < args.size() ? &args[++i] : nullptr;
}

int nextNumber(const std::string& sub, const std::vector<std::string>& args, size_t& i, uint64_t lo, uint64_t hi,
               uint64_t& out) {
  const std::string& option = args[i];
  const std::string* v = nextValue(args, i);
  if (v && parseNumber(*v, lo, hi, out)) return -1;
  return usageError(sub, option + " " + (v ? *v : "(missing)") + ": expected a whole number from " + std::to_string(lo) +
                             " to " + std::to_string(hi));
}

bool parseNumber(const std::string& text, uint64_t lo, uint64_t hi, uint64_t& out) {
  if (text.empty() || text.size() > 20 || !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; })) return false;
  errno = 0;
  const unsigned long long v = std::strtoull(text.c_str(), nullptr, 10);
  if (errno || v < lo || v > hi) return false;
  out = v;
  return true;
}

bool parseSize(const std::string& text, int& width, int& height) {
  const size_t x = text.find('x');
  uint64_t w = 0, h = 0;
  if (x == std::string::npos || !parseNumber(text.substr(0, x), 16, 8192, w) || !parseNumber(text.substr(x + 1), 16, 8192, h)) return false;
  width = int(w);
  height = int(h);
  return true;
}

Progress::Progress(std::string what, bool enabled)
    : what_(std::move(what)), enabled_(enabled), tty_(isatty(2)), start_(Clock::now()), last_(start_) {}

void Progress::update(uint32_t tick, uint32_t total) {
  tick_ = tick;
  total_ = total;
  if (!enabled_) return;
  const auto now = Clock::now();
  if (now - start_ < std::chrono::milliseconds(500)) return;
  if (shown_ && now - last_ < std::chrono::milliseconds(tty_ ? 250 : 5000)) return;
  last_ = now;
  shown_ = true;
  const double seconds = std::chrono::duration<double>(now - start_).count();
  std::fprintf(stderr, "%s%s: tick %u/%u (%.0f%%, %.1f s)%s", tty_ ? "\r" : "", what_.c_str(), tick, total,
               total ? 100.0 * tick / total : 100.0, seconds, tty_ ? "   " : "\n");
  std::fflush(stderr);
}

void Progress::done() {
  if (!enabled_ || !shown_) return;
  const double seconds = std::chrono::duration<double>(Clock::now() - start_).count();
  std::fprintf(stderr, "%s%s: tick %u/%u done in %.1f s\n", tty_ ? "\r" : "", what_.c_str(), tick_, total_, seconds);
  shown_ = false;
}

}  // namespace rts::replay::cli

#include "format/replay_reader.h"

namespace rts::replay::cli {

std::optional<Replay> loadReplay(const std::string& sub, const std::string& path) {
  ReadResult r = readReplayFile(path);
  if (!r.ok()) {
    if (r.error.field == "file") {
      std::fprintf(stderr, "rattle-replay %s: %s\n", sub.c_str(), r.error.message.c_str());
    } else {
      std::fprintf(stderr, "rattle-replay %s: %s: not a valid replay: %s\n", sub.c_str(), path.c_str(), r.error.describe().c_str());
    }
    return std::nullopt;
  }
  return std::move(r.replay);
}

}  // namespace rts::replay::cli
