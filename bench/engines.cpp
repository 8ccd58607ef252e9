// rattle-bench: the engine names the CLI takes, and which of them were compiled in. Box2D and Chipmunk
// are found at configure time (bench/CMakeLists.txt); when one is absent its name is still listed, and
// asking for it throws EngineUnavailable (main.cpp turns that into its own exit code).
#include <stdexcept>

#include "engine.h"

namespace rattle_bench {

#ifdef RATTLE_BENCH_HAVE_BOX2D
constexpr bool kHaveBox2d = true;
#else
constexpr bool kHaveBox2d = false;
std::unique_ptr<Engine> makeBox2dEngine(const Scene&, bool) { return nullptr; }
std::string box2dVersion() { return "Box2D: absent"; }
#endif
#ifdef RATTLE_BENCH_HAVE_CHIPMUNK
constexpr bool kHaveChipmunk = true;
#else
constexpr bool kHaveChipmunk = false;
std::unique_ptr<Engine> makeChipmunkEngine(const Scene&) { return nullptr; }
std::string chipmunkVersion() { return "Chipmunk: absent"; }
#endif

const std::vector<EngineInfo>& engineList() {
  static const std::vector<EngineInfo> list = {
      {"discrete", true, "rattle, StepMode::Discrete: move a step, push overlapping pairs apart and reflect them"},
      {"hybrid", true, "rattle, StepMode::Hybrid (default): swept boxes, exact times of impact inside the step"},
      {"predictive", true, "rattle, StepMode::Predictive: event-driven, a step is only a time to look"},
      {"bisect", true, "the older detector: path-line check between frames, then bisection of the step"},
      {"box2d", kHaveBox2d, "Box2D 2.4, default settings (8 velocity, 3 position iterations)"},
      {"box2d-bullet", kHaveBox2d, "Box2D 2.4 with every disk a bullet (continuous collision between disks)"},
      {"chipmunk", kHaveChipmunk, "Chipmunk 7, default settings (10 iterations)"},
      {"edmd", true, "a baseline for predictive: the textbook event-driven gas (one event per disk, cell "
                     "crossings, a 4-ary heap; engine_edmd.cpp); gas, cradle, bullets only"},
      {"edmd-lean", true, "a second baseline for predictive: the same method written for speed alone (one cache "
                          "line per disk, a calendar queue, records asked for ahead; no contacts reported; "
                          "engine_edmd_lean.cpp); gas, cradle, bullets only"},
  };
  return list;
}

void Engine::setVelocities(const std::vector<Vec2>&) {
  throw std::logic_error("rattle-bench: this engine takes no velocities (steeredEngine)");
}

bool steeredEngine(const std::string& name) {
  return name == "discrete" || name == "hybrid" || name == "predictive" || name == "box2d" ||
         name == "box2d-bullet" || name == "chipmunk";
}

std::unique_ptr<Engine> makeEngine(const std::string& name, const Scene& scene, const EngineSettings& settings) {
  for (const EngineInfo& e : engineList())
    if (e.name == name && !e.available)
      throw EngineUnavailable("--engine " + name + ": not compiled in (" +
                              (name == "chipmunk" ? std::string("Chipmunk 7, libchipmunk-dev")
                                                  : std::string("Box2D 2.4, libbox2d-dev")) +
                              ", was not found when rattle-bench was configured; install it with `bash "
                              "scripts/install-deps.sh scripts/packages-bench.txt` and configure again)");
  if (scene.steering.enabled && !steeredEngine(name))
    throw EngineCannotRun("--engine " + name + ": not available for " + scene.name +
                          " (its disks are steered each step: discrete, hybrid, predictive, box2d, box2d-bullet, "
                          "chipmunk)");
  if (name == "discrete") return makeRattleEngine(scene, RattleMode::Discrete, settings.collapseTime);
  if (name == "hybrid") return makeRattleEngine(scene, RattleMode::Hybrid, settings.collapseTime);
  if (name == "predictive") return makeRattleEngine(scene, RattleMode::Predictive, settings.collapseTime);
  if (name == "bisect") return makeBisectEngine(scene, settings.bisect);
  if (name == "box2d") return makeBox2dEngine(scene, false);
  if (name == "box2d-bullet") return makeBox2dEngine(scene, true);
  if (name == "chipmunk") return makeChipmunkEngine(scene);
  if (name == "edmd") return makeEdmdEngine(scene);
  if (name == "edmd-lean") return makeEdmdLeanEngine(scene);
  throw std::invalid_argument("--engine " + name +
                              ": unknown (discrete, hybrid, predictive, bisect, box2d, box2d-bullet, chipmunk, "
                              "edmd, edmd-lean)");
}

}  // namespace rattle_bench
