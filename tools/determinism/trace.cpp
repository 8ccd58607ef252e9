// rattle-trace: runs fixed scenes and prints one state hash per tick, so that two builds of the same
// source (other compilers, -O levels, sanitizers) can be compared line by line. The output depends only
// on the source and the options: no times, no paths, no build facts (those go to stderr).
//
// Every scene is run in every step mode:
//   game/<mode>       the demo game on the default arena, both teams played by the scripted opponent
//                     (Game::stateHash: bodies, hit points, orders, shots, doorways, gates)
//   <scene>/<mode>    an engine world (World::stateHash mixed with the step's contact and sensor events)
#include <rattle/rattle.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <functional>
#include <string>
#include <unistd.h>
#include <vector>

#include "engine_scenes.h"
#include "game_scene.h"
#include "map/map_loader.h"

namespace {

struct Options {
  std::string map = RATTLE_TRACE_DEFAULT_MAP;
  int gameTicks = 600;
  int engineSteps = 240;
  int disks = 200;
  int units = 100;
  uint64_t seed = 1;
  std::string only;  // a prefix of scene names; empty: all
};

const char* kHelp = R"(usage: rattle-trace [options]

Runs fixed scenes and prints one line per tick, "<scene>/<mode> <tick> <hash>", to stdout. Two builds of
the same source should print the same bytes; tools/determinism/run_builds.sh compares them (make
test-determinism). Progress goes to stderr.

Scenes, each in the discrete, hybrid and predictive step modes:
  game       the demo game on the default arena, both teams played by the scripted opponent
  gas        the benchmark's gas: equal disks, restitution 1, no gravity
  pile       the benchmark's pile: disks falling into a box, gravity (0, -10), restitution 0.5
  bullets    the benchmark's bullets: small disks at speeds 10 to 10000 between walls
  sensors    the benchmark's sensors: disks crossing six sensor strips
  crowd      the benchmark's crowd: disks steered naively through two doorways every step, dt 1/30
  kinematic  disks pushed by two kinematic bodies, one carrying a sensor ring
  .../loaded each of those but game, saved half way (World::save; a line "<name> save <FNV-1a 64 of
             the bytes> <size>") and loaded (World::load), the loaded world stepped to the end

options:
  --map FILE        the game's map (default: assets/maps/arena.json of the source tree)
  --game-ticks N    ticks of each game run, 0 to 1000000 (default 600, 20 seconds of game time: the teams
                    meet, fire, and lose units)
  --units N         units per team in the game, 0 to 100000 (default 100)
  --seed N          the scripted opponent's seed, 0 to 2^62 (default 1)
  --steps N         steps of each engine scene, at dt = 1/60 (the crowd: 1/30), 0 to 1000000 (default 240)
  --disks N         disks in the gas, pile, crowd and kinematic scenes, 2 to 100000; half as many in bullets
                    and sensors (default 200)
  --only PREFIX     only the scenes whose name starts with PREFIX (e.g. game, pile/hybrid); a PREFIX that
                    names no scene is an error
  --help            this text

Exit status: 0 every scene ran; 1 a scene could not be run (the map could not be read); 2 a bad command
line.
)";

bool parseInt(const char* text, long lo, long hi, long& out) {
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(text, &end, 10);
  if (errno != 0 || end == text || *end != '\0' || v < lo || v > hi) return false;
  out = v;
  return true;
}

// Returns -1 to run, otherwise the exit status.
int parseOptions(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::fputs(kHelp, stdout);
      return 0;
    }
    if (i + 1 >= argc) {
      const bool known = arg == "--map" || arg == "--only" || arg == "--game-ticks" || arg == "--units" ||
                         arg == "--seed" || arg == "--steps" || arg == "--disks";
      std::fprintf(stderr, known ? "rattle-trace: %s: a value is missing (see --help)\n"
                                 : "rattle-trace: %s: unknown option (see --help)\n",
                   arg.c_str());
      return 2;
    }
    const char* value = argv[++i];
    long v = 0;
    auto number = [&](long lo, long hi) {
      if (parseInt(value, lo, hi, v)) return true;
      std::fprintf(stderr, "rattle-trace: %s %s: expected a whole number from %ld to %ld\n", arg.c_str(), value,
                   lo, hi);
      return false;
    };
    if (arg == "--map") {
      o.map = value;
    } else if (arg == "--only") {
      o.only = value;
    } else if (arg == "--game-ticks") {
      if (!number(0, 1'000'000)) return 2;
      o.gameTicks = int(v);
    } else if (arg == "--units") {
      if (!number(0, 100'000)) return 2;
      o.units = int(v);
    } else if (arg == "--seed") {
      if (!number(0, 1L << 62)) return 2;
      o.seed = uint64_t(v);
    } else if (arg == "--steps") {
      if (!number(0, 1'000'000)) return 2;
      o.engineSteps = int(v);
    } else if (arg == "--disks") {
      if (!number(2, 100'000)) return 2;
      o.disks = int(v);
    } else {
      std::fprintf(stderr, "rattle-trace: %s: unknown option (see --help)\n", arg.c_str());
      return 2;
    }
  }
  return -1;
}

const char* modeName(rattle::StepMode m) {
  switch (m) {
    case rattle::StepMode::Discrete: return "discrete";
    case rattle::StepMode::Hybrid: return "hybrid";
    case rattle::StepMode::Predictive: return "predictive";
  }
  return "?";
}

// One scene: prints its lines and a progress line on stderr (rewritten in place on a terminal).
void runScene(const std::string& name, int ticks, const std::function<uint64_t()>& tick) {
  const bool tty = isatty(STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  for (int t = 1; t <= ticks; ++t) {
    const uint64_t h = tick();
    std::printf("%s %d %016" PRIx64 "\n", name.c_str(), t, h);
    if (tty && (t % 20 == 0 || t == ticks)) std::fprintf(stderr, "\rrattle-trace: %s %d/%d ", name.c_str(), t, ticks);
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::fprintf(stderr, "%srattle-trace: %s: %d ticks in %.2f s\n", tty ? "\r" : "", name.c_str(), ticks, s);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (int status = parseOptions(argc, argv, o); status >= 0) return status;
  const rattle::StepMode modes[] = {rattle::StepMode::Discrete, rattle::StepMode::Hybrid, rattle::StepMode::Predictive};
  auto wanted = [&](const std::string& scene) { return scene.compare(0, o.only.size(), o.only) == 0; };
  // A family of scenes is needed when --only names one of them or all of them ("game/hybrid", "game").
  auto family = [&](const std::string& prefix) {
    const size_t n = std::min(prefix.size(), o.only.size());
    return prefix.compare(0, n, o.only, 0, n) == 0;
  };
  // Two builds traced with a mistyped --only would print nothing alike, and "match".
  bool anyWanted = false;
  for (rattle::StepMode mode : modes) {
    anyWanted = anyWanted || wanted(std::string("game/") + modeName(mode));
    for (const std::string& scene : rattle_trace::engineSceneNames()) {
      const std::string name = scene + "/" + modeName(mode);
      anyWanted = anyWanted || wanted(name) || wanted(name + "/loaded");
    }
  }
  if (!anyWanted) {
    std::fprintf(stderr, "rattle-trace: --only %s: no scene's name starts with it (see --help)\n", o.only.c_str());
    return 2;
  }
  try {
    if (family("game/")) {
      const rts::Map map = rts::loadMap(o.map);
      for (rattle::StepMode mode : modes) {
        const std::string name = std::string("game/") + modeName(mode);
        if (!wanted(name)) continue;
        rattle_trace::GameScene game(map, mode, o.units, o.seed);
        runScene(name, o.gameTicks, [&] { return game.tick(); });
      }
    }
    for (const std::string& scene : rattle_trace::engineSceneNames()) {
      for (rattle::StepMode mode : modes) {
        const std::string name = scene + "/" + modeName(mode);
        if (!wanted(name)) continue;
        rattle_trace::EngineScene s = rattle_trace::buildEngineScene(scene, mode, o.disks);
        int step = 0;
        runScene(name, o.engineSteps, [&] {
          if (s.beforeStep) s.beforeStep(s, step);
          ++step;
          s.world.step(s.dt);
          return rattle_trace::stepHash(s.world);
        });
      }
    }
    // Saved half way and loaded (World::save, World::load): the save's bytes, and the loaded world's
    // steps, are the same on every build and processor.
    for (const std::string& scene : rattle_trace::engineSceneNames()) {
      for (rattle::StepMode mode : modes) {
        const std::string name = scene + "/" + modeName(mode) + "/loaded";
        if (!wanted(name)) continue;
        rattle_trace::EngineScene s = rattle_trace::buildEngineScene(scene, mode, o.disks);
        const int half = o.engineSteps / 2;
        int step = 0;
        for (; step < half; ++step) {
          if (s.beforeStep) s.beforeStep(s, step);
          s.world.step(s.dt);
        }
        const std::vector<uint8_t> bytes = s.world.save();
        uint64_t digest = 0xcbf29ce484222325ull;  // FNV-1a 64 of the save
        for (uint8_t b : bytes) digest = (digest ^ b) * 0x100000001b3ull;
        std::printf("%s save %016" PRIx64 " %zu\n", name.c_str(), digest, bytes.size());
        s.world = rattle::World::load(bytes);
        runScene(name, o.engineSteps - half, [&] {
          if (s.beforeStep) s.beforeStep(s, step);
          ++step;
          s.world.step(s.dt);
          return rattle_trace::stepHash(s.world);
        });
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rattle-trace: %s\n", e.what());
    return 1;
  }
  return 0;
}
