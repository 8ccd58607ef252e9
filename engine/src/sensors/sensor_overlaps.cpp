// Sensor overlaps and their events: which sensor pairs overlap now (WorldState::sensorOverlaps, an
// unordered map probed by key and sorted before anything read out of it reaches an event), and the
// begin and end events as an overlap changes, inside a step or between steps (a destroy, a filter).
#include <algorithm>
#include <utility>

#include "common/out_of_memory.h"
#include "sensors/sensors.h"
#include "world/world_impl.h"

namespace rattle {

bool detail::isOverlapping(const WorldState& w, uint32_t fa, uint32_t fb) {
  const bool aIsSensor = w.fixtures[fa].sensor;
  return w.sensorOverlaps.count(detail::overlapKey(aIsSensor ? fa : fb, aIsSensor ? fb : fa)) != 0;
}

void detail::sensorOverlapsSeen(WorldState& w, uint32_t fa, uint32_t fb) {
  const uint32_t sensor = w.fixtures[fa].sensor ? fa : fb, visitor = w.fixtures[fa].sensor ? fb : fa;
  auto it = w.sensorOverlaps.find(detail::overlapKey(sensor, visitor));
  if (it != w.sensorOverlaps.end()) it->second = w.stepStamp;
}

void detail::recordSensorChange(WorldState& w, uint32_t fa, uint32_t fb, double time, bool begin,
                                std::vector<SensorEvent>& out) {
  const uint32_t sensor = w.fixtures[fa].sensor ? fa : fb, visitor = w.fixtures[fa].sensor ? fb : fa;
  const uint64_t key = detail::overlapKey(sensor, visitor);
  // Inside a step every change is logged (the room made first), so that undoStep can take it back.
  auto& log = w.stepStart.sensorOverlaps;
  if (w.stepStart.active) detail::roomForOneMore(log);
  if (begin) {
    const auto [it, inserted] = w.sensorOverlaps.try_emplace(key, w.stepStamp);
    it->second = w.stepStamp;
    if (inserted && w.stepStart.active) log.push_back({key, {}});
  } else if (w.stepStart.active) {
    auto ended = w.sensorOverlaps.extract(key);
    if (!ended.empty()) log.push_back({key, std::move(ended)});
  } else {
    w.sensorOverlaps.erase(key);
  }
  SensorEvent e;
  e.time = time;
  e.sensor = {sensor, w.fixtures[sensor].generation};
  e.sensorBody = {w.fixtures[sensor].body, w.bodies[w.fixtures[sensor].body].generation};
  e.visitor = {visitor, w.fixtures[visitor].generation};
  e.visitorBody = {w.fixtures[visitor].body, w.bodies[w.fixtures[visitor].body].generation};
  e.begin = begin;
  out.push_back(e);
}

void detail::sortSensorEvents(std::vector<SensorEvent>& events) {
  std::stable_sort(events.begin(), events.end(), [](const SensorEvent& x, const SensorEvent& y) {
    if (x.time != y.time) return x.time < y.time;
    const uint32_t xl = std::min(x.sensor.index, x.visitor.index), yl = std::min(y.sensor.index, y.visitor.index);
    if (xl != yl) return xl < yl;
    return std::max(x.sensor.index, x.visitor.index) < std::max(y.sensor.index, y.visitor.index);
  });
}

void detail::endOverlaps(WorldState& w, const std::vector<uint64_t>& ended) {
  for (uint64_t key : ended) {
    if (!w.sensorOverlaps.contains(key)) continue;  // both of an overlap's fixtures were ending
    recordSensorChange(w, static_cast<uint32_t>(key >> 32), static_cast<uint32_t>(key), 0.0, false,
                       w.pendingSensorEvents);
  }
}

}  // namespace rattle
