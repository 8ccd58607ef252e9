// rattle-bench: the exact reference (see reference.h).
#include "reference.h"

#include <algorithm>
#include <cmath>

#include "engine.h"

namespace rattle_bench {

namespace {

// The sensor reference is the hybrid mode at dt <= 1/240 s. The predictive mode finds the same events
// (both modes sense along the recorded paths, sensor_paths.cpp); true would take them from the
// predictive run instead, which is also the collision reference.
constexpr bool kPredictiveReportsSensors = false;

}  // namespace

Reference exactReference(const Scene& scene, double dt, long long steps, double collapseTime) {
  Reference ref;
  std::unique_ptr<Engine> predictive = makeRattleEngine(scene, RattleMode::Predictive, collapseTime);
  for (long long k = 0; k < steps; ++k) {
    predictive->step(dt);
    predictive->collect();
  }
  ref.collisions = predictive->collisions;
  ref.how = "collisions: rattle predictive at the same frames";
  if (scene.sensors.empty()) return ref;
  if (kPredictiveReportsSensors) {
    ref.sensorBegins = predictive->sensorBegins;
    ref.how += "; sensors: the same run";
    return ref;
  }
  // Hybrid, split each frame into `parts` steps of at most 1/240 s.
  const long long parts = std::max(1LL, static_cast<long long>(std::ceil(dt * 240.0 - 1e-9)));
  std::unique_ptr<Engine> hybrid = makeRattleEngine(scene, RattleMode::Hybrid, collapseTime);
  for (long long k = 0; k < steps; ++k)
    for (long long j = 0; j < parts; ++j) {
      hybrid->step(dt / static_cast<double>(parts));
      hybrid->collect();
    }
  ref.sensorBegins = hybrid->sensorBegins;
  ref.how += "; sensors: rattle hybrid at dt/" + std::to_string(parts);
  return ref;
}

}  // namespace rattle_bench
