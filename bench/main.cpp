// rattle-bench: one run of one engine on one scene, timed step by step, with its errors measured outside
// the timed part and compared with an exact reference run in the same invocation. `--help` says what each
// column means; bench/README.md says how the standard matrix (make bench) uses it.
//
// Timing: each step() is timed twice, by the CPU time of this thread (clock_gettime(
// CLOCK_THREAD_CPUTIME_ID)) and by the wall clock (steady_clock). The speed columns use the CPU time, so
// that other work on a shared machine, which takes the core away, does not count as the engine's; the wall
// time is kept as a column of its own. Reading the thread's CPU clock is a system call (about 0.3 to 0.6 us
// here), so the cost of an empty measurement, taken before the run, is subtracted from every step.
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>
#include <string>
#include <vector>

#include "arena_run.h"
#include "engine.h"
#include "measure.h"
#include "options.h"
#include "reference.h"
#include "row.h"

namespace rattle_bench {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double threadCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// One timed interval, by both clocks.
struct Interval {
  double cpu = 0, wall = 0;
};

class StepTimer {
 public:
  StepTimer() {
    // The cost of an empty measurement: the median of many, by each clock.
    std::vector<double> cpu, wall;
    for (int i = 0; i < 501; ++i) {
      start();
      const Interval e = raw();
      cpu.push_back(e.cpu);
      wall.push_back(e.wall);
    }
    std::nth_element(cpu.begin(), cpu.begin() + 250, cpu.end());
    std::nth_element(wall.begin(), wall.begin() + 250, wall.end());
    overhead_ = {cpu[250], wall[250]};
  }
  void start() {
    wall0_ = Clock::now();
    cpu0_ = threadCpuSeconds();
  }
  Interval stop() {
    const Interval r = raw();
    return {std::max(0.0, r.cpu - overhead_.cpu), std::max(0.0, r.wall - overhead_.wall)};
  }

 private:
  Interval raw() {
    const double cpu = threadCpuSeconds();
    const double wall = std::chrono::duration<double>(Clock::now() - wall0_).count();
    return {cpu - cpu0_, wall};
  }
  Clock::time_point wall0_;
  double cpu0_ = 0;
  Interval overhead_;
};

int run(const Options& o) {
  const Clock::time_point setupStart = Clock::now();
  const Scene scene = buildScene(o.scene);
  std::unique_ptr<Engine> engine = makeEngine(o.engine, scene, o.settings);
  const double setupSeconds = secondsSince(setupStart);
  const long long steps = std::llround(o.seconds / o.dt);
  const size_t n = scene.disks.size();

  std::vector<Vec2> positions, velocities;
  engine->state(positions, velocities);
  const long double e0 = totalEnergy(scene, positions, velocities);
  OverlapMeter meter(scene);
  OverlapStats overlaps;
  std::vector<uint8_t> outside;
  int tunnelled = 0;

  Progress progress(!o.quiet, scene.name + "/" + o.engine + " n=" + std::to_string(n) + " dt=" + o.dtText);
  StepTimer timer;
  std::vector<double> stepSeconds, wallSeconds;
  stepSeconds.reserve(static_cast<size_t>(steps));
  wallSeconds.reserve(static_cast<size_t>(steps));
  // Timing: the steps of --warm-up, or the first tenth of them, are warm-up.
  size_t warm =
      o.warmUp >= 0 ? static_cast<size_t>(std::round(o.warmUp / o.dt)) : static_cast<size_t>(steps / 10);
  std::vector<long long> collisionsAfter;  // the engine's count after each step
  collisionsAfter.reserve(static_cast<size_t>(steps));
  // The crowd: steered before every step, and measured after every step (the steering reads the positions
  // anyway), so that a crossing of the dividing wall is seen step by step.
  const bool steered = scene.steering.enabled;
  std::vector<Vec2> steer, before;
  std::vector<uint8_t> reached(steered ? n : 0, 0), throughWall(steered ? n : 0, 0);
  const Clock::time_point runStart = Clock::now();
  bool stoppedAtLimit = false;
  long long ran = 0;
  for (long long k = 0; k < steps; ++k) {
    if (steered) {
      steerCrowd(scene, positions, steer);
      engine->setVelocities(steer);
      before = positions;
    }
    timer.start();
    engine->step(o.dt);
    const Interval took = timer.stop();
    stepSeconds.push_back(took.cpu);
    wallSeconds.push_back(took.wall);
    ran = k + 1;
    engine->collect();
    collisionsAfter.push_back(engine->collisions);
    const bool stop = o.timeLimit > 0 && k + 1 < steps && secondsSince(runStart) >= o.timeLimit;
    if (steered || stop || k % o.measureEvery == 0 || k == steps - 1) {
      engine->state(positions, velocities);
      meter.measure(positions, overlaps);
      tunnelled = markTunnelled(scene, positions, outside);
    }
    if (steered) {
      for (size_t i = 0; i < n; ++i) {
        if (inGoalRegion(scene, i, positions[i])) reached[i] = 1;
        if (crossedWallOutsideDoorways(scene, before[i], positions[i])) throughWall[i] = 1;
      }
    }
    progress.update("step", k + 1, steps);
    if (stop) {
      stoppedAtLimit = true;
      break;
    }
  }
  if (steered) {
    tunnelled = 0;
    for (size_t i = 0; i < n; ++i) tunnelled += (outside[i] || throughWall[i]) ? 1 : 0;
  }
  // A run stopped before its warm-up ended is timed after the first tenth of the steps it ran.
  if (warm >= static_cast<size_t>(ran)) warm = static_cast<size_t>(ran / 10);
  // The collisions of the warm-up steps, left out of collisions_per_s.
  const long long warmCollisions = warm > 0 ? collisionsAfter[warm - 1] : 0;
  const long double e1 = totalEnergy(scene, positions, velocities);

  Reference ref;
  // A steered scene has no exact reference (each engine's steering reacts to its own positions), and a run
  // stopped at the time limit none to compare with.
  if (o.reference && !steered && !stoppedAtLimit) {
    if (o.engine == "predictive" && scene.sensors.empty()) {
      ref.collisions = engine->collisions;  // this run is the reference
      ref.how = "this run";
    } else {
      progress.update("reference run", 0, 1);
      ref = exactReference(scene, o.dt, ran, o.settings.collapseTime);
    }
  }
  progress.finish();

  const std::vector<double> timed(stepSeconds.begin() + static_cast<long>(warm), stepSeconds.end());
  const std::vector<double> timedWall(wallSeconds.begin() + static_cast<long>(warm), wallSeconds.end());
  double sum = 0;
  for (double t : timed) sum += t;
  const double msPerStep = 1e3 * median(timed);
  const double msPerSimulatedSecond = 1e3 * (sum / static_cast<double>(timed.size())) / o.dt;
  const double nan = std::nan("");
  // Over the timed steps only, as the times: an event-driven engine's first step builds its grid and
  // predicts every body once, a cost of starting that a short run would otherwise spread over its collisions.
  const long long timedCollisions = engine->collisions >= 0 ? engine->collisions - warmCollisions : -1;
  const double collisionsPerSecond =
      timedCollisions >= 0 && sum > 0 ? static_cast<double>(timedCollisions) / sum : nan;
  const double energyDrift = steered ? nan : e0 != 0 ? static_cast<double>((e1 - e0) / std::fabs(e0)) : static_cast<double>(e1 - e0);
  double countError = nan;
  if (ref.collisions > 0 && engine->collisions >= 0)
    countError = static_cast<double>(engine->collisions - ref.collisions) / static_cast<double>(ref.collisions);
  else if (ref.collisions == 0 && engine->collisions >= 0)
    countError = engine->collisions == 0 ? 0.0 : std::numeric_limits<double>::infinity();
  const bool hasSensors = !scene.sensors.empty();
  long long sensorVisits = 0, referenceVisits = 0;
  for (long long c : engine->sensorBegins) sensorVisits += c;
  for (long long c : ref.sensorBegins) referenceVisits += c;
  const double sensorMissed =
      hasSensors && !ref.sensorBegins.empty() ? static_cast<double>(sensorMisses(ref.sensorBegins, engine->sensorBegins)) : nan;

  Row row;
  row.set("scene", scene.name);
  row.set("engine", o.engine);
  row.set("n", std::to_string(n));
  row.set("dt", num(o.dt, "%.10g"));
  row.set("seconds", num(static_cast<double>(ran) * o.dt, "%.10g"));
  row.set("ms_per_step", num(msPerStep));
  row.set("p99_ms_per_step", num(1e3 * percentile(timed, 0.99)));
  row.set("worst_ms_per_step", num(1e3 * percentile(timed, 1.0)));
  row.set("ms_per_simulated_second", num(msPerSimulatedSecond));
  row.set("collisions_per_s", num(collisionsPerSecond));
  row.set("energy_drift", num(energyDrift, "%.3e"));
  row.set("max_overlap", num(overlaps.max, "%.3e"));
  row.set("mean_overlap", num(overlaps.mean(), "%.3e"));
  row.set("tunnelled", std::to_string(tunnelled));
  row.set("sensor_missed", num(sensorMissed, "%.0f"));
  row.set("collision_count_error", num(countError, "%.4e"));
  row.set("seed", std::to_string(scene.seed));
  row.set("packing", num(scene.packing, "%.4g"));
  row.set("speed", num(scene.speed, "%.6g"));
  row.set("steps", std::to_string(ran));
  row.set("warm_up_s", num(static_cast<double>(warm) * o.dt, "%.10g"));
  row.set("collisions", engine->collisions >= 0 ? std::to_string(engine->collisions) : "");
  row.set("timed_collisions", timedCollisions >= 0 ? std::to_string(timedCollisions) : "");
  row.set("reference_collisions", ref.collisions >= 0 ? std::to_string(ref.collisions) : "");
  row.set("sensor_visits", hasSensors ? std::to_string(sensorVisits) : "");
  row.set("reference_sensor_visits", hasSensors && !ref.sensorBegins.empty() ? std::to_string(referenceVisits) : "");
  row.set("wall_ms_per_step", num(1e3 * median(timedWall)));
  row.set("setup_s", num(setupSeconds, "%.3g"));
  if (steered) {
    long long r = 0;
    for (uint8_t x : reached) r += x;
    row.set("reached_goal", std::to_string(r));
  }
  if (engine->asleep() >= 0) row.set("asleep", std::to_string(engine->asleep()));
  std::string notes = engine->notes;
  if (o.timeLimit > 0) {
    row.set("stopped_at_time_limit", stoppedAtLimit ? "yes" : "no");
    if (stoppedAtLimit)
      notes += std::string(notes.empty() ? "" : "; ") + "stopped at the wall-clock limit of " + num(o.timeLimit) +
               " s after " + std::to_string(ran) + " of " + std::to_string(steps) + " steps";
  }
  row.set("notes", notes);
  row.print(o.csv, ref.how);
  return 0;
}

}  // namespace

}  // namespace rattle_bench

int main(int argc, char** argv) {
  using namespace rattle_bench;
  Options o;
  try {
    o = parseOptions(std::vector<std::string>(argv + 1, argv + argc));
  } catch (const UsageError& e) {
    std::fprintf(stderr, "rattle-bench: %s\n(rattle-bench --help lists the options)\n", e.what());
    return 2;
  }
  if (o.help) {
    std::fputs(helpText().c_str(), stdout);
    return 0;
  }
  if (o.version) {
    std::printf("rattle-bench (rattle %s), compiler %s\n%s\n%s\n", RATTLE_BENCH_VERSION, __VERSION__,
                box2dVersion().c_str(), chipmunkVersion().c_str());
    return 0;
  }
  try {
    return o.scene.name == "arena" ? runArena(o) : run(o);
  } catch (const ArenaUnavailable& e) {
    std::fprintf(stderr, "rattle-bench: %s\n", e.what());
    return 4;
  } catch (const EngineCannotRun& e) {
    std::fprintf(stderr, "rattle-bench: %s\n", e.what());
    return 4;
  } catch (const EngineUnavailable& e) {
    std::fprintf(stderr, "rattle-bench: %s\n", e.what());
    return 3;
  } catch (const SceneError& e) {
    // Scene parameters the parser cannot judge alone (a cradle n that is not a multiple of 6, a packing the
    // lattice cannot hold): still the command line's fault.
    std::fprintf(stderr, "rattle-bench: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rattle-bench: the run failed: %s\n", e.what());
    return 1;
  }
}
