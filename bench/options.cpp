// rattle-bench: the command line (see helpText for what it takes).
#include "options.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "engine.h"

namespace rattle_bench {

namespace {

// A whole decimal number, nothing after it.
bool parseDouble(const std::string& s, double& out) {
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  out = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && errno == 0;
}

// A number, or a fraction a/b ("1/60").
bool parseNumberOrFraction(const std::string& s, double& out) {
  const size_t slash = s.find('/');
  if (slash == std::string::npos) return parseDouble(s, out);
  double a, b;
  if (!parseDouble(s.substr(0, slash), a) || !parseDouble(s.substr(slash + 1), b) || b == 0) return false;
  out = a / b;
  return true;
}

// Digits, or a whole number written with an exponent ("1e5") when it is below 2^53.
bool parseUnsigned(const std::string& s, unsigned long long max, unsigned long long& out) {
  if (s.empty()) return false;
  if (s.find_first_not_of("0123456789") == std::string::npos) {
    errno = 0;
    out = std::strtoull(s.c_str(), nullptr, 10);
    return errno == 0 && out <= max;
  }
  double d;
  if (!parseDouble(s, d) || !(d >= 0 && d <= 0x1p53) || d != std::floor(d)) return false;
  out = static_cast<unsigned long long>(d);
  return out <= max;
}

}  // namespace

Options parseOptions(const std::vector<std::string>& args) {
  Options o;
  bool nGiven = false, dtGiven = false;
  std::vector<std::string> diskOnly;  // options given that only the disk scenes take
  for (size_t i = 0; i < args.size(); ++i) {
    std::string name = args[i], value;
    bool hasValue = false;
    if (const size_t eq = name.find('='); name.rfind("--", 0) == 0 && eq != std::string::npos) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
      hasValue = true;
    }
    auto take = [&]() -> const std::string& {
      if (!hasValue) {
        if (i + 1 >= args.size()) throw UsageError(name + ": needs a value");
        value = args[++i];
        hasValue = true;
      }
      return value;
    };
    auto bad = [&](const std::string& why) { return UsageError(name + " " + value + ": " + why); };
    auto noValue = [&]() {
      if (hasValue) throw UsageError(name + "=" + value + ": " + name + " takes no value");
    };
    if (name == "--help" || name == "-h") {
      noValue();
      o.help = true;
    } else if (name == "--version") {
      noValue();
      o.version = true;
    } else if (name == "--csv") {
      noValue();
      o.csv = true;
    } else if (name == "--no-reference") {
      noValue();
      o.reference = false;
    } else if (name == "--quiet") {
      noValue();
      o.quiet = true;
    } else if (name == "--scene") {
      o.scene.name = take();
      bool known = value == "arena";
      for (const std::string& s : sceneNames()) known = known || s == value;
      if (!known) throw bad("unknown scene (gas, pile, bullets, cradle, sensors, crowd, arena)");
    } else if (name == "--engine") {
      o.engine = take();
      bool known = false;
      for (const EngineInfo& e : engineList()) known = known || e.name == value;
      if (!known) throw bad("unknown engine (discrete, hybrid, predictive, bisect, box2d, box2d-bullet, chipmunk, edmd, edmd-lean)");
    } else if (name == "--n") {
      unsigned long long n;
      if (!parseUnsigned(take(), 100'000'000ull, n) || n < 1) throw bad("must be a whole number from 1 to 10^8");
      o.scene.n = static_cast<int>(n);
      nGiven = true;
    } else if (name == "--dt") {
      double dt;
      if (!parseNumberOrFraction(take(), dt) || !std::isfinite(dt) || !(dt > 0))
        throw bad("must be a positive number of seconds, or a fraction like 1/60");
      o.dt = dt;
      o.dtText = value;
      dtGiven = true;
    } else if (name == "--seconds") {
      double t;
      if (!parseNumberOrFraction(take(), t) || !std::isfinite(t) || !(t > 0))
        throw bad("must be a positive number of simulated seconds");
      o.seconds = t;
      o.secondsText = value;
    } else if (name == "--seed") {
      unsigned long long k;
      if (!parseUnsigned(take(), ~0ull, k)) throw bad("must be a whole number from 0 to 2^64 - 1");
      o.scene.seed = k;
    } else if (name == "--packing") {
      double p;
      if (!parseDouble(take(), p) || !(p > 0 && p < 0.9)) throw bad("must be a packing fraction in (0, 0.9)");
      o.scene.packing = p;
      diskOnly.push_back(name + " " + value);
    } else if (name == "--speed") {
      double v;
      if (!parseDouble(take(), v) || !std::isfinite(v) || !(v >= 0)) throw bad("must be a speed >= 0");
      o.scene.speed = v;
      diskOnly.push_back(name + " " + value);
    } else if (name == "--collapse-time") {
      double t;
      if (!parseDouble(take(), t) || !std::isfinite(t) || !(t >= 0)) throw bad("must be a time in seconds >= 0");
      o.settings.collapseTime = t;
      diskOnly.push_back(name + " " + value);
    } else if (name == "--bisect-depths") {
      const std::string& v = take();
      const size_t comma = v.find(',');
      unsigned long long m, s;
      if (comma == std::string::npos || !parseUnsigned(v.substr(0, comma), 20, m) || m < 1 ||
          !parseUnsigned(v.substr(comma + 1), 60, s))
        throw bad("must be M,S: 1 <= M <= 20 sampling levels, 0 <= S <= 60 bisections");
      o.settings.bisect = {static_cast<int>(m), static_cast<int>(s)};
      diskOnly.push_back(name + " " + value);
    } else if (name == "--warm-up") {
      double t;
      if (!parseNumberOrFraction(take(), t) || !std::isfinite(t) || !(t >= 0))
        throw bad("must be a number of simulated seconds >= 0");
      o.warmUp = t;
      o.warmUpText = value;
    } else if (name == "--time-limit") {
      double t;
      if (!parseDouble(take(), t) || !std::isfinite(t) || !(t >= 0))
        throw bad("must be a number of wall-clock seconds >= 0 (0: no limit)");
      o.timeLimit = t;
      diskOnly.push_back(name + " " + value);
    } else if (name == "--measure-every") {
      unsigned long long k;
      if (!parseUnsigned(take(), 1'000'000'000ull, k) || k < 1) throw bad("must be a whole number >= 1");
      o.measureEvery = static_cast<int>(k);
    } else {
      throw UsageError(name + ": unknown option");
    }
  }
  if (o.scene.name == "arena") {
    // The demo's game ticks at a fixed rate, so the arena runs at that step or not at all; a --dt that
    // differs only by the rounding of its decimal digits is taken as the tick.
    if (dtGiven && std::fabs(o.dt - kArenaTickSeconds) > 1e-9 * kArenaTickSeconds)
      throw UsageError("--dt " + o.dtText + ": the arena scene plays the demo's game, whose tick is fixed at 1/30 s "
                       "(rts::Game::kTickSeconds); give --dt 1/30 or leave --dt out");
    o.dt = kArenaTickSeconds;
    o.dtText = "1/30";
    if (!diskOnly.empty())
      throw UsageError(diskOnly.front() + ": the arena scene does not take it (the demo's map, units and game "
                       "settings make the scene)");
    if (!nGiven) o.scene.n = 100;
  } else if (!nGiven) {
    o.scene.n = defaultDiskCount(o.scene.name);
  }
  const double steps = std::round(o.seconds / o.dt);
  const std::string both = "--seconds " + o.secondsText + " with --dt " + o.dtText;
  if (!(steps >= 1)) throw UsageError(both + ": less than one step");
  if (steps > 1e9) throw UsageError(both + ": more than 10^9 steps");
  if (o.warmUp >= 0 && !(std::round(o.warmUp / o.dt) < steps))
    throw UsageError("--warm-up " + o.warmUpText + " with " + both + ": no step left to time");
  return o;
}

std::string helpText() {
  std::string engines;
  for (const EngineInfo& e : engineList())
    engines += "  " + e.name + std::string(14 - e.name.size(), ' ') + e.description +
               (e.available ? "" : "  [not compiled in]") + "\n";
  return R"(rattle-bench: one run of one engine on one scene; prints its speed and its errors.

usage: rattle-bench [--scene S] [--engine E] [--n N] [--dt DT] [--seconds T] [--seed K] [--csv]
                    [--packing P] [--speed V] [--collapse-time TC] [--bisect-depths M,S]
                    [--no-reference] [--measure-every K] [--warm-up T] [--time-limit S] [--quiet]
       rattle-bench --help | --version

  --scene S          gas (default), pile, bullets, cradle, sensors, crowd (scenes/scenes.h says what
                     each is), arena (the demo's game on assets/maps/arena.json; bench/arena.h)
  --engine E         one of the engines below (default hybrid); arena: discrete, hybrid, predictive;
                     crowd: discrete, hybrid, predictive, box2d, box2d-bullet, chipmunk
  --n N              number of disks (defaults: gas, pile and crowd 1000, bullets 100, cradle 60 (a
                     multiple of 6), sensors 200); arena: units per team (default 100)
  --dt DT            step in seconds, a number or a fraction (default 1/60); arena: the game's fixed
                     tick, 1/30, is the default and the only step it takes
  --seconds T        simulated seconds (default 2); steps = round(T / DT)
  --seed K           the seed of the random start (default 1); arena: the scripted opponent's seed
  --csv              print a header line and one CSV row instead of named values
  --packing P        gas only: packing fraction (default 0.3)
  --speed V          speed of every disk (defaults: gas 1, pile up to 1, bullets 10..10^4 in turn,
                     cradle 1..3 per lane, sensors 10..40); crowd: the steering's full speed (default 3)
  --collapse-time TC WorldDef::collapseTime (the TC model against inelastic collapse) for the rattle
                     modes and for the exact reference run, whatever the engine (default 0: off,
                     rattle's default)
  --bisect-depths M,S  bisect: M levels of sampling the step, then S bisections (default 4,10)
  --no-reference     skip the exact reference run (collision_count_error and sensor_missed left empty)
  --measure-every K  measure overlaps and tunnelling after every K-th step and the last (default 1);
                     arena: overlaps only (its other measures need every tick)
  --warm-up T        the steps of the first T simulated seconds are not timed (default: the first
                     tenth of the steps); a gas started from a lattice takes about 0.5 s to settle
                     into its steady collision rate
  --time-limit S     stop after the step under way once S wall-clock seconds have passed since the
                     first step (default 0: no limit); the row covers the steps run, and
                     stopped_at_time_limit says yes (a step is never cut short)
  --quiet            no progress line on stderr

engines:
)" + engines +
         R"(
The row: times are the CPU time of the thread running step() (other work on the machine does not count;
wall_ms_per_step gives the wall-clock median too). ms_per_step is the median time of one step() after a
warm-up (--warm-up; the first tenth of the steps), p99_ms_per_step the 99th percentile (nearest rank) and
worst_ms_per_step the longest of the same steps; ms_per_simulated_second the mean step time after warm-up divided
by DT; collisions_per_s the collisions of the timed steps (after warm-up) per second of their step time
(timed_collisions; collisions counts every step); energy_drift (E_end - E_0) / |E_0| with E
kinetic plus potential; max_overlap and mean_overlap the depths of disk-disk and disk-wall overlaps
relative to the smaller radius, measured after the steps outside the timing; tunnelled the disks ever
found outside the container; sensor_missed the exact sensor visits the engine did not report;
collision_count_error (count - exact) / exact. The exact reference is run in the same invocation:
rattle's predictive mode for the collision count, rattle's hybrid mode at DT <= 1/240 for sensor events
(the predictive mode reports none yet). asleep: the disks the engine holds asleep at the end (rattle
and Box2D; empty for engines that do not say or never sleep).

The crowd row: before every step (outside the timing) each disk's velocity is set by the naive steering
(scenes/scenes.h); reached_goal counts the disks whose centre was ever in the goal region (the second
room); tunnelled counts the disks ever found outside the container or that crossed the dividing wall
anywhere but through a doorway (through a wall); max_overlap and mean_overlap as above (disks against
disks and walls). There is no exact reference (the steering makes each engine's run its own), and
energy_drift is empty (the steering sets the energy).

The arena row: the step times are the game's own measure of World::step (rattle-demo prints its
median); n is units per team; tunnelled counts projectiles whose centre crossed a wall, a building or
a standing gate inside a tick; max_overlap and mean_overlap are those of units (against units, walls
and gates); sensor_missed counts the sight and doorway begins seen from the positions at the end of each
tick that the engine did not report; collision_count_error compares the contact events with those of
the predictive mode's game from the same seed, a game of its own (bench/README.md says how to read it).
energy_drift, packing and speed are empty; shots, shots_out_of_range and crossings are the game's counts,
and reference_shots, reference_shots_out_of_range and reference_crossings the predictive game's.

exit codes: 0 done; 1 the run failed; 2 bad command line (or a scene that cannot be built from it);
3 the engine or scene asked for is not compiled in; 4 the engine cannot run the scene asked for
(arena runs only with discrete, hybrid and predictive; crowd not with bisect, edmd or edmd-lean).
)";
}

}  // namespace rattle_bench
