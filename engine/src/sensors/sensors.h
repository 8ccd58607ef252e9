// Private: sensors. The overlaps that hold now (WorldState::sensorOverlaps) and their begin and end
// events (sensor_overlaps.cpp), and the events of a step found from the paths bodies took through it
// (sensor_paths.cpp), in the hybrid and predictive modes; the discrete mode compares overlaps at a step's
// end.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "rattle/geometry.h"
#include "world/world_impl.h"

namespace rattle::detail {

/// Whether the sensor pair of fixtures fa and fb (either one the sensor) overlaps now.
bool isOverlapping(const WorldState& w, uint32_t fa, uint32_t fb);
/// Stamps a sensor overlap found by this step's sweep as seen.
void sensorOverlapsSeen(WorldState& w, uint32_t fa, uint32_t fb);
/// Begins or ends the overlap of fa and fb (either one the sensor) and appends its event at `time` to
/// `out`; inside a step the change is logged so that a failed step can take it back.
void recordSensorChange(WorldState& w, uint32_t fa, uint32_t fb, double time, bool begin,
                        std::vector<SensorEvent>& out);
/// Orders a step's sensor events as contact events are ordered: by time, then by the fixture ids (the
/// lower, then the higher); a stable sort, so one pair's events at one instant keep their order.
void sortSensorEvents(std::vector<SensorEvent>& events);
/// Ends the overlaps (those still in the map), their events reported at time 0 of the next step.
/// Allocates nothing when pendingSensorEvents has room for them.
void endOverlaps(WorldState& w, const std::vector<uint64_t>& ended);

/// The overlaps of `fixture` to end, all but those with a fixture `keep` keeps: appended to `ended`,
/// sorted (the map's order must not reach the events). Changes nothing.
template <class Keep>
void overlapsToEnd(const WorldState& w, uint32_t fixture, Keep&& keep, std::vector<uint64_t>& ended) {
  const auto from = static_cast<std::ptrdiff_t>(ended.size());
  for (const auto& [key, stamp] : w.sensorOverlaps) {
    const uint32_t sensor = static_cast<uint32_t>(key >> 32), visitor = static_cast<uint32_t>(key);
    if ((sensor == fixture && !keep(visitor)) || (visitor == fixture && !keep(sensor))) ended.push_back(key);
  }
  std::sort(ended.begin() + from, ended.end());
}

/// Ends at time 0 (into sensorEvents) every overlap the step's sweep did not see (its stamp is not
/// stepStamp) whose two fixtures no longer overlap where their bodies start the step
/// (`startOf(body)`): a body moved away between steps. Unseen because neither body moves (a sleeping
/// body in a static sensor) is no end.
template <class StartOf>
void endUnseenOverlaps(WorldState& w, StartOf&& startOf) {
  std::vector<uint64_t> unseen;
  for (const auto& [key, seen] : w.sensorOverlaps) {
    if (seen == w.stepStamp) continue;
    const uint32_t sensor = static_cast<uint32_t>(key >> 32), visitor = static_cast<uint32_t>(key);
    if (!overlaps(w.fixtures[sensor].geometry, startOf(w.fixtures[sensor].body), w.fixtures[visitor].geometry,
                  startOf(w.fixtures[visitor].body))) {
      unseen.push_back(key);
    }
  }
  std::sort(unseen.begin(), unseen.end());  // the map's order must not reach the events
  for (uint64_t key : unseen) {
    recordSensorChange(w, static_cast<uint32_t>(key >> 32), static_cast<uint32_t>(key), 0.0, false, w.sensorEvents);
  }
}

/// Starts recording when the world has sensors: every body's motion at the step's start.
void startPaths(WorldState& w);
/// The sensor events of a step from the paths the bodies took (up to `end`).
void sensePaths(WorldState& w, PathLog& log, double end);

}  // namespace rattle::detail
