// rattle-bench: the exact answers a run's errors are measured against.
#pragma once

#include <string>
#include <vector>

#include "scenes.h"

namespace rattle_bench {

struct Reference {
  long long collisions = -1;             ///< the exact collision count over the run; -1: not computed
  std::vector<long long> sensorBegins;  ///< exact sensor begins per (sensor, disk), like Engine's; empty: none
  std::string how;                      ///< which engine and step gave each part
};

/// The exact reference for `steps` steps of `dt` of the scene, run inside the same invocation (outside
/// any timing): the collision count from rattle's predictive mode (exact times of impact, every event in
/// time order, whatever dt) at the same frames, and, when the scene has sensors, the sensor begins from
/// rattle's hybrid mode (exact sensor times inside a step) at a step of at most 1/240 s covering the same
/// time (a second exact run, made by other collision code than the predictive one; reference.cpp says how
/// to take the sensor events from the predictive run instead).
/// `collapseTime` is rattle's WorldDef::collapseTime, as the run being measured used it.
Reference exactReference(const Scene& scene, double dt, long long steps, double collapseTime);

}  // namespace rattle_bench
