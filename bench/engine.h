// rattle-bench: what every engine adapter offers, and the list of engines.
//
// The harness (main.cpp) times step() alone. Building the world, reading the state and collecting the
// step's counts run outside the timed part. Each adapter builds its own world from the scene's plain data
// (scenes.h), set up as fairly as the engine allows; its file says how.
#pragma once

#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "scenes.h"

namespace rattle_bench {

class Engine {
 public:
  virtual ~Engine() = default;

  /// Advances the world by dt seconds. The only timed call.
  virtual void step(double dt) = 0;
  /// Called after every step, outside the timing: adds the step's collisions and sensor begins to the
  /// counters below.
  virtual void collect() {}
  /// Positions and velocities of the scene's disks, in the scene's order.
  virtual void state(std::vector<Vec2>& positions, std::vector<Vec2>& velocities) const = 0;
  /// Sets every disk's velocity, in the scene's order (the crowd's steering, before each step, outside the
  /// timing). Only the engines steeredEngine() names implement it; the others throw std::logic_error.
  virtual void setVelocities(const std::vector<Vec2>& velocities);
  /// How many of the scene's disks the engine holds asleep; -1 when it does not say (or never sleeps).
  virtual long long asleep() const { return -1; }

  /// Collisions since the start, disk-disk and disk-wall (each engine's own notion: a resolved impact,
  /// or a contact that began touching); -1 when the engine does not count them.
  long long collisions = 0;
  /// Sensor begin events since the start, per (sensor, disk): index sensor * disks + disk.
  std::vector<long long> sensorBegins;
  /// Anything the row's reader should know (an event budget reached, a speed cap met), or empty.
  std::string notes;
};

/// An engine name as the CLI takes it, whether it was compiled in, and a one-line description.
struct EngineInfo {
  std::string name;
  bool available = true;
  std::string description;
};

/// Every engine name, in the order the help lists them; Box2D and Chipmunk marked unavailable when they
/// were not found at configure time.
const std::vector<EngineInfo>& engineList();

/// The older detector's two depths (seeds/collision-detector-manual.txt): `movementCheck` levels of
/// breadth-first sampling of the step, then `searchDepth` bisections of the bracket found.
struct BisectDepths {
  int movementCheck = 4;
  int searchDepth = 10;
};

/// Settings some engines take beyond the scene.
struct EngineSettings {
  /// rattle's WorldDef::collapseTime (the TC model against inelastic collapse), seconds; 0: off (rattle's
  /// default). Only the rattle modes read it.
  double collapseTime = 0;
  BisectDepths bisect;
};

/// Whether the named engine takes a velocity for every disk before each step (Engine::setVelocities), as
/// scenes with steering need: rattle's three modes, Box2D and Chipmunk.
bool steeredEngine(const std::string& name);

/// Builds the named engine's world from the scene. Throws std::invalid_argument for an unknown name,
/// EngineUnavailable for one that was not compiled in and EngineCannotRun for a scene it cannot run.
std::unique_ptr<Engine> makeEngine(const std::string& name, const Scene& scene, const EngineSettings& settings = {});

struct EngineUnavailable : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// The engine cannot run this scene (edmd outside a closed elastic box, a steered scene with an engine
/// that takes no velocities).
struct EngineCannotRun : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Versions of the libraries compiled in ("Box2D 2.4.1", "Chipmunk 7.0.3"), or "Box2D: absent".
std::string box2dVersion();
std::string chipmunkVersion();

// The adapters, one file each.
enum class RattleMode { Discrete, Hybrid, Predictive };
std::unique_ptr<Engine> makeRattleEngine(const Scene& scene, RattleMode mode, double collapseTime = 0);
std::unique_ptr<Engine> makeBisectEngine(const Scene& scene, BisectDepths depths);
std::unique_ptr<Engine> makeBox2dEngine(const Scene& scene, bool bullets);
std::unique_ptr<Engine> makeChipmunkEngine(const Scene& scene);
std::unique_ptr<Engine> makeEdmdEngine(const Scene& scene);
std::unique_ptr<Engine> makeEdmdLeanEngine(const Scene& scene);
/// Whether the scene is what the event-driven baselines run: elastic disks that meet, in a box of four
/// walls on the sides of its bounds, without gravity or sensors (engine_edmd.cpp).
bool isElasticBox(const Scene& scene);

}  // namespace rattle_bench
