// The engine scenes rattle-trace steps: small worlds that between them touch every solver a game or a
// gas uses (straight paths, parabolas, sensors, kinematic pushers), built from fixed numbers so that
// every build of the program steps exactly the same world.
#pragma once

#include <rattle/world.h>
#include <scenes.h>

#include <cstdint>
#include <string>
#include <vector>

namespace rattle_trace {

struct EngineScene {
  std::string name;   ///< gas, pile, bullets, sensors, crowd, kinematic
  rattle::World world;
  double dt = 1.0 / 60.0;  ///< the crowd's: 1/30, a game's tick
  /// Called before each step (kinematic bodies turn around, the crowd is steered); may be empty.
  void (*beforeStep)(EngineScene&, int step) = nullptr;
  std::vector<rattle::BodyId> movers;  ///< bodies a beforeStep steers
  rattle_bench::Scene scene;           ///< the benchmark scene it was built from (the crowd's steering)
};

/// The scene names, in trace order.
const std::vector<std::string>& engineSceneNames();

/// Builds the named scene for a step mode. `disks` scales it (the default trace uses 200).
EngineScene buildEngineScene(const std::string& name, rattle::StepMode mode, int disks);

/// The world's stateHash mixed with every event of the last step (times, fixtures, points, normals,
/// impulses, sensor begins and ends), so a sensor event that differs shows even when positions agree.
uint64_t stepHash(const rattle::World& world);

}  // namespace rattle_trace
