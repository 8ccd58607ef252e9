#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>

#include "app/run.h"
#include "map/printable.h"

namespace rts {
namespace {

template <class T>
T percentile(std::vector<T> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[size_t(p * double(v.size() - 1) + 0.5)];
}

const char* modeName(rattle::StepMode m) {
  switch (m) {
    case rattle::StepMode::Hybrid: return "hybrid";
    case rattle::StepMode::Discrete: return "discrete";
    case rattle::StepMode::Predictive: return "predictive";
  }
  return "?";
}

}  // namespace

void progress(const Game& game, long totalTicks, bool done) {
  using Clock = std::chrono::steady_clock;
  static Clock::time_point last{};
  static bool shown = false;
  const bool tty = isatty(2);
  const auto now = Clock::now();
  if (!done && now - last < std::chrono::milliseconds(tty ? 250 : 5000)) return;
  if (done && !shown) return;
  last = now;
  shown = true;
  const std::vector<double>& steps = game.stats().stepSeconds;
  const double recent = steps.empty() ? 0 : steps.back() * 1e3;
  std::fprintf(stderr, "%stick %u/%ld  blue %d  red %d  shots %ld  engine step %.2f ms (median so far %.2f ms)%s",
               tty ? "\r" : "", game.tickCount(), totalTicks, game.alive(0), game.alive(1), game.stats().shotsFired, recent,
               percentile(steps, 0.5) * 1e3, tty && !done ? "   " : "\n");
  std::fflush(stderr);
}

void printSummary(const Game& game, const Options& o, int framesWritten, double medianFrameSeconds,
                  double medianDrawSeconds) {
  const GameStats& s = game.stats();
  const double median = percentile(s.stepSeconds, 0.5) * 1e3;
  const double p95 = percentile(s.stepSeconds, 0.95) * 1e3;
  const double p99 = percentile(s.stepSeconds, 0.99) * 1e3;
  const double worst = s.stepSeconds.empty() ? 0 : *std::max_element(s.stepSeconds.begin(), s.stepSeconds.end()) * 1e3;
  const long outOfRange = s.shotsFired - s.unitHits - s.wallHits - long(game.shots().size());
  std::string rooms;
  for (size_t r = 0; r < game.rooms().size(); ++r) {
    const int h = game.rooms()[r].holder;
    rooms += (r ? ", " : "") + printable(game.map().rooms[r].name) + " " + (h < 0 ? "empty" : h == 2 ? "contested" : h == 0 ? "blue" : "red");
  }
  std::printf(
      "Ran %u ticks (%.1f s of game time) on %s (%g x %g) with %d units per team, seed %llu, %s mode%s. "
      "Units left: blue %d, red %d. Shots fired: %ld (%ld hit units, %ld hit walls, %ld ran out of range). "
      "Doorway crossings: %ld. Rooms: %s. Engine step: median %.3f ms, 95th percentile %.3f ms, 99th percentile "
      "%.3f ms, worst %.3f ms over %zu steps%s.",
      game.tickCount(), game.tickCount() * Game::kTickSeconds, game.map().name.empty() ? "the map" : printable(game.map().name).c_str(),
      game.map().width, game.map().height, o.units, static_cast<unsigned long long>(o.seed), modeName(o.mode),
      o.steering == Steering::Naive ? ", naive steering" : "",
      game.alive(0), game.alive(1), s.shotsFired, s.unitHits, s.wallHits, std::max(0l, outOfRange), s.crossings,
      rooms.empty() ? "none" : rooms.c_str(), median, p95, p99, worst, s.stepSeconds.size(),
      s.eventBudgetSteps ? (", " + std::to_string(s.eventBudgetSteps) + " of them hit the event budget").c_str() : "");
  // The engine's work, which unlike the times does not depend on what else the machine is doing.
  std::printf(" Engine work a step: median %d collisions and %d time-of-impact tests (95th percentile %d and %d).",
              percentile(s.stepCollisions, 0.5), percentile(s.stepImpactTests, 0.5), percentile(s.stepCollisions, 0.95),
              percentile(s.stepImpactTests, 0.95));
  if (framesWritten > 0) {
    std::printf(" Frames: %d PNG files in %s/ (median %.0f ms each: %.0f ms to draw at %dx%d with %dx%d supersampling, the rest to write).",
                framesWritten, o.framesDir.c_str(), medianFrameSeconds * 1e3, medianDrawSeconds * 1e3, o.width, o.height,
                o.supersample, o.supersample);
  }
  std::printf(" Final state hash %016llx.\n", static_cast<unsigned long long>(game.stateHash()));
}

}  // namespace rts
