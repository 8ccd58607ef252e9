// rattle-bench: the error measures, all taken outside the timed part of a step.
#pragma once

#include <cstdint>
#include <vector>

#include "scenes.h"

namespace rattle_bench {

/// Overlap depths relative to a radius, accumulated over every check of a run: a pair of disks that
/// should not meet counts (r_i + r_j - |c_i - c_j|) / min(r_i, r_j) when positive; a disk closer to a
/// wall than its radius counts (r - distance) / r.
struct OverlapStats {
  double max = 0;       ///< the deepest overlap seen (0 when none)
  double sum = 0;       ///< over every overlapping pair or disk-wall contact at every check
  long long count = 0;  ///< how many overlaps were summed
  double mean() const { return count > 0 ? sum / static_cast<double>(count) : 0.0; }
};

/// Finds overlaps in O(n) with a uniform grid of cells two radii wide (the largest radius). Keeps its
/// buffers between calls.
class OverlapMeter {
 public:
  explicit OverlapMeter(const Scene& scene);
  void measure(const std::vector<Vec2>& positions, OverlapStats& stats);

 private:
  const Scene& scene_;
  double cell_ = 1;
  int nx_ = 1, ny_ = 1;
  std::vector<int> cellOf_, start_, order_;
};

/// Kinetic plus potential energy (potential -m g.p, zero at the origin), summed in long double.
long double totalEnergy(const Scene& scene, const std::vector<Vec2>& positions, const std::vector<Vec2>& velocities);

/// Marks the disks whose centres are outside the scene's container (ever, over every call); returns how
/// many are marked.
int markTunnelled(const Scene& scene, const std::vector<Vec2>& positions, std::vector<uint8_t>& outside);

/// Visits the exact list has and the engine does not: the sum over (sensor, disk) of
/// max(0, reference begins - engine begins).
long long sensorMisses(const std::vector<long long>& reference, const std::vector<long long>& engine);

}  // namespace rattle_bench
