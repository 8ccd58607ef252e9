// rattle-bench: one run of the arena scene. The game times its own engine step (Physics::step measures
// World::step alone, by this thread's CPU time and by the wall clock); everything else in a tick (the
// game's rules, the scripted opponent, the measures) is outside the numbers reported. No empty-measurement
// cost is subtracted here, unlike the other scenes: what the game's CPU measure adds to a step (one read
// of the CPU clock and two of the wall clock) is under a microsecond, against arena steps of a quarter of
// a millisecond and up.
#include "arena_run.h"

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "engine.h"
#include "row.h"

#ifdef RATTLE_BENCH_HAVE_ARENA
#include "arena.h"
#include "map/map_loader.h"
#endif

namespace rattle_bench {

#ifndef RATTLE_BENCH_HAVE_ARENA

int runArena(const Options&) {
  throw EngineUnavailable("--scene arena: not compiled in (rattle-bench was configured with RATTLE_BUILD_DEMO=OFF; "
                          "the arena scene plays the demo's game)");
}

#else

static_assert(kArenaTickSeconds == rts::Game::kTickSeconds, "options.h must know the game's tick");

namespace {

rattle::StepMode modeOf(const std::string& engine) {
  if (engine == "discrete") return rattle::StepMode::Discrete;
  if (engine == "hybrid") return rattle::StepMode::Hybrid;
  if (engine == "predictive") return rattle::StepMode::Predictive;
  throw ArenaUnavailable("--engine " + engine +
                         ": not available for arena (the arena scene is the demo's game, which steps a rattle "
                         "world: use discrete, hybrid or predictive)");
}

/// Plays `ticks` ticks, measuring overlaps every `measureEvery` ticks and at the last.
void play(ArenaGame& arena, long long ticks, int measureEvery, Progress& progress, const char* what) {
  for (long long k = 0; k < ticks; ++k) {
    arena.tick(k % measureEvery == 0 || k == ticks - 1);
    progress.update(what, k + 1, ticks);
  }
}

}  // namespace

int runArena(const Options& o) {
  ArenaParams params;
  params.unitsPerTeam = o.scene.n;
  params.seed = o.scene.seed;
  params.mode = modeOf(o.engine);
  const auto setupStart = std::chrono::steady_clock::now();
  std::unique_ptr<ArenaGame> arena;
  try {
    arena = std::make_unique<ArenaGame>(params);
  } catch (const rts::MapError& e) {
    throw SceneError(std::string("--scene arena: bad map: ") + e.what());
  } catch (const rts::GameError& e) {
    throw SceneError("--scene arena --n " + std::to_string(o.scene.n) + ": " + e.what());
  }
  const double setupSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - setupStart).count();
  const double tick = rts::Game::kTickSeconds;
  const long long ticks = std::llround(o.seconds / tick);

  Progress progress(!o.quiet, "arena/" + o.engine + " n=" + std::to_string(o.scene.n));
  play(*arena, ticks, o.measureEvery, progress, "tick");
  const ArenaTotals run = arena->totals();

  ArenaTotals ref;
  std::string how;
  bool haveRef = false;
  if (o.reference) {
    haveRef = true;
    if (params.mode == rattle::StepMode::Predictive) {
      ref = run;
      how = "this run (predictive)";
    } else {
      ArenaParams exact = params;
      exact.mode = rattle::StepMode::Predictive;
      ArenaGame game(exact);
      play(game, ticks, 1'000'000'000, progress, "reference run");
      ref = game.totals();
      how = "the predictive mode's game from the same seed (a game of its own: see bench/README.md)";
    }
  }
  progress.finish();

  // Timing: the ticks of --warm-up, or the first tenth of them, are warm-up.
  const rts::GameStats& stats = arena->game().stats();
  const size_t warm = o.warmUp >= 0 ? static_cast<size_t>(std::min<long long>(ticks - 1, std::llround(o.warmUp / tick)))
                                    : static_cast<size_t>(ticks / 10);
  const std::vector<double> timed(stats.stepCpuSeconds.begin() + static_cast<long>(warm), stats.stepCpuSeconds.end());
  const std::vector<double> timedWall(stats.stepSeconds.begin() + static_cast<long>(warm), stats.stepSeconds.end());
  double sum = 0, total = 0;
  for (double t : timed) sum += t;
  for (double t : stats.stepCpuSeconds) total += t;
  const double nan = std::nan("");
  double countError = nan;
  if (haveRef && ref.contacts > 0) countError = double(run.contacts - ref.contacts) / double(ref.contacts);

  Row row;
  row.set("scene", "arena");
  row.set("engine", o.engine);
  row.set("n", std::to_string(o.scene.n));
  row.set("dt", num(tick, "%.10g"));
  row.set("seconds", num(double(ticks) * tick, "%.10g"));
  row.set("ms_per_step", num(1e3 * median(timed)));
  row.set("p99_ms_per_step", num(1e3 * percentile(timed, 0.99)));
  row.set("worst_ms_per_step", num(1e3 * percentile(timed, 1.0)));
  row.set("ms_per_simulated_second", num(1e3 * (sum / double(timed.size())) / tick));
  row.set("collisions_per_s", num(total > 0 ? double(run.contacts) / total : nan));
  row.set("max_overlap", num(run.overlaps.max, "%.3e"));
  row.set("mean_overlap", num(run.overlaps.mean(), "%.3e"));
  row.set("tunnelled", std::to_string(run.tunnelledShots));
  row.set("sensor_missed", std::to_string(run.sensorMissed));
  row.set("collision_count_error", num(countError, "%.4e"));
  row.set("seed", std::to_string(o.scene.seed));
  row.set("steps", std::to_string(ticks));
  row.set("collisions", std::to_string(run.contacts));
  row.set("reference_collisions", haveRef ? std::to_string(ref.contacts) : "");
  row.set("sensor_visits", std::to_string(run.sensorBeginsReported));
  row.set("reference_sensor_visits", std::to_string(run.sensorBeginsSeen));
  row.set("wall_ms_per_step", num(1e3 * median(timedWall)));
  row.set("setup_s", num(setupSeconds, "%.3g"));
  row.set("shots", std::to_string(run.shotsFired));
  row.set("shots_out_of_range", std::to_string(run.outOfRange));
  row.set("reference_shots", haveRef ? std::to_string(ref.shotsFired) : "");
  row.set("reference_shots_out_of_range", haveRef ? std::to_string(ref.outOfRange) : "");
  row.set("crossings", std::to_string(run.crossings));
  row.set("reference_crossings", haveRef ? std::to_string(ref.crossings) : "");
  std::string notes = "units left " + std::to_string(run.alive[0]) + " + " + std::to_string(run.alive[1]);
  if (stats.eventBudgetSteps > 0) notes += "; " + std::to_string(stats.eventBudgetSteps) + " steps hit the event budget";
  row.set("notes", notes);
  row.print(o.csv, how);
  return 0;
}

#endif

}  // namespace rattle_bench
