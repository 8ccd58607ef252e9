// What the hybrid step keeps for itself between and within steps: its event queue, its stepped islands
// and jams (contact/islands.h), and the scratch of its passes. Its stepper owns it (and the predictive
// stepper one for the steps it hands over); the squeezes, which the predictive mode meets in its own
// events too, stay in the world's state, with the contact response.
#pragma once

#include <cstdint>
#include <vector>

#include "common/body_marks.h"
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
  // Round-off approaches absorbed in the current step, by body (the hybrid step's dismissContact): a
  // disk wedged between two others can absorb against each in turn at one instant, without end, where
  // coordinates are large. Past collapseCollisions() such an approach is left as it is. Only the
  // bodies that absorbed have a count; each hybrid step starts with none.
  BodyMarks<uint16_t> absorbs;
  /// Counts one; saturates.
  void countAbsorb(uint32_t body) {
    const uint16_t count = absorbs.get(body);
    if (count < UINT16_MAX) absorbs.set(body, static_cast<uint16_t>(count + 1));
  }

  /// A step ran out of memory and the world was taken back to its start (Stepper::forget): events it
  /// may have left queued go, and the islands take back their part (Islands::undoStep).
  void forget() {
    queue.clear();
    islands.undoStep();
    absorbs.clear();
  }
};

}  // namespace rattle::detail
