// What the hybrid step keeps for itself between and within steps: its event queue, its stepped islands
// and jams (contact/islands.h), and the scratch of its passes. Its stepper owns it (and the predictive
// stepper one for the steps it hands over); the squeezes, which the predictive mode meets in its own
// events too, stay in the world's state, with the contact response.
#pragma once

#include <cstdint>
#include <vector>

#include "common/large_array.h"
#include "contact/islands.h"
#include "world/world_impl.h"

namespace rattle::detail {

struct HybridState {
  explicit HybridState(WorldState& world) : islands(world) {}

  std::vector<PredictedContact> queue;  // binary heap ordered by detail::later
  LargeArray<uint32_t> stamp;           // by fixture index, for de-duplication
  uint32_t stampCounter = 0;
  std::vector<uint32_t> slidingAtStart;   // the bodies that start the step sliding
  std::vector<CandidatePair> deferred;    // pairs predicted after the islands
  std::vector<uint32_t> islandFreed;      // stepped bodies the start's solve set free
  Islands islands;

  /// A step ran out of memory and the world was taken back to its start (Stepper::forget): events it
  /// may have left queued go, and the islands take back their part (Islands::undoStep).
  void forget() {
    queue.clear();
    islands.undoStep();
  }
};

}  // namespace rattle::detail
