// Sensor events after the fact, from the paths bodies took through the step (hybrid and predictive).
//
// A body may sit in many sensors at once (a unit's sight circle over its neighbours). Re-predicting each
// of its sensor pairs at every collision, with the contacts, made sensors most of the cost of a crowd;
// instead both modes record each body's path through the step as pieces (a line or a parabola from each
// instant its motion changed: PathLog) and find the sensor events once the step's collisions are done:
//  1. Every fixture of a moving body gets the box of its whole piecewise path; sort-and-sweep (the
//     world's broad phase, as in the hybrid step) gives the pairs of a sensor and a physical fixture whose
//     boxes meet.
//  2. For each pair, the step is cut at every instant either path changes; within a piece both move
//     along one polynomial path each, and timeOfOverlapChange gives each begin or end exactly, as the
//     hybrid step would find it from the same instant.
//  3. Overlaps the sweep did not see end at time 0 unless the two still overlap (as in the hybrid step),
//     and the events are ordered as the hybrid step orders them: by time, then by fixture ids.
#include <algorithm>
#include <cmath>

#include "collision/path_box.h"
#include "rattle/time_of_impact.h"
#include "world/path_log.h"
#include "sensors/sensors.h"
#include "world/world_impl.h"

namespace rattle {

using detail::PathLog;
using detail::PathPiece;

namespace {

// A body's pieces in time order: its motion at the step's start, then each change.
struct Path {
  const PathPiece* first;
  const PathPiece* const* rest;
  size_t restCount;
  size_t size() const { return restCount + 1; }
  const PathPiece& operator[](size_t k) const { return k == 0 ? *first : *rest[k - 1]; }
};

Vec2 positionOn(const PathPiece& p, double t) {
  const double h = t - p.start;
  return p.position + p.velocity * h + p.acceleration * (0.5 * h * h);
}
Vec2 velocityOn(const PathPiece& p, double t) { return p.velocity + p.acceleration * (t - p.start); }

// More begins and ends than this for one pair in one step is round-off chatter, not motion: the rest of
// the step is skipped for that pair (what it overlaps at the end is still what is recorded).
constexpr int kMaxChangesPerPair = 1024;

}  // namespace

void detail::startPaths(WorldState& w) {
  PathLog& log = w.pathLog;
  log.active = w.liveSensors > 0;
  if (!log.active) return;
  const size_t nb = w.bodies.size();
  log.first.resize(nb);
  log.asleepAtStart.resize(nb);
  log.lastPiece.assign(nb, PathLog::kNoPiece);
  log.changes.clear();
  for (size_t i = 0; i < nb; ++i) {
    const detail::BodySlot& b = w.bodies[i];
    log.first[i] = {b.localTime, b.position, b.velocity, b.acceleration};
    log.asleepAtStart[i] = b.asleep;
  }
}

void detail::sensePaths(WorldState& w, PathLog& log, double end) {
  ++w.stepStamp;
  // Each body's changes, grouped by body in the order they happened (a counting sort).
  const size_t nb = w.bodies.size();
  std::vector<uint32_t> begin(nb + 1, 0);
  for (const auto& c : log.changes) ++begin[c.body + 1];
  for (size_t i = 0; i < nb; ++i) begin[i + 1] += begin[i];
  std::vector<const PathPiece*> sorted(log.changes.size());
  {
    std::vector<uint32_t> fill(begin.begin(), begin.end() - 1);
    for (const auto& c : log.changes) sorted[fill[c.body]++] = &c.piece;
  }
  auto pathOf = [&](uint32_t body) {
    return Path{&log.first[body], sorted.data() + begin[body], size_t{begin[body + 1] - begin[body]}};
  };

  // 1. Boxes of the whole paths. A body asleep all step is at rest, as in the hybrid step.
  for (uint32_t i = 0; i < nb; ++i) {
    const detail::BodySlot& b = w.bodies[i];
    if (!b.alive || b.type == BodyType::Static) continue;
    const Path path = pathOf(i);
    const bool moving = !log.asleepAtStart[i] || path.restCount > 0;
    Box box{b.position, b.position};
    if (moving) {
      box = Box{path[0].position, path[0].position};
      for (size_t k = 0; k < path.size(); ++k) {
        const double until = k + 1 < path.size() ? path[k + 1].start : end;
        box = unionOf(box, detail::pathBox(path[k].position, path[k].velocity, path[k].acceleration,
                                           std::max(until - path[k].start, 0.0)));
      }
    }
    for (uint32_t f : b.fixtures) {
      w.broadPhase.setMoving(f, moving);
      w.broadPhase.setBox(f, Box{box.min + w.fixtures[f].localBox.min, box.max + w.fixtures[f].localBox.max});
    }
  }

  // 2. Each pair along the pieces of both paths.
  std::vector<SensorEvent> found;
  auto sense = [&](uint32_t sensor, uint32_t visitor) {
    const Path a = pathOf(w.fixtures[sensor].body), b = pathOf(w.fixtures[visitor].body);
    bool overlapping = isOverlapping(w, sensor, visitor);
    double t = 0;
    size_t ka = 0, kb = 0;
    for (int changes = 0; changes < kMaxChangesPerPair;) {
      while (ka + 1 < a.size() && a[ka + 1].start <= t) ++ka;
      while (kb + 1 < b.size() && b[kb + 1].start <= t) ++kb;
      double next = end;
      if (ka + 1 < a.size()) next = std::min(next, a[ka + 1].start);
      if (kb + 1 < b.size()) next = std::min(next, b[kb + 1].start);
      ++w.stats.timeOfImpactTests;
      const Motion relative{velocityOn(a[ka], t) - velocityOn(b[kb], t), a[ka].acceleration - b[kb].acceleration};
      const auto h =
          timeOfOverlapChange(w.fixtures[sensor].geometry, positionOn(a[ka], t), w.fixtures[visitor].geometry,
                              positionOn(b[kb], t), relative, std::max(next - t, 0.0), overlapping);
      if (h) {
        t = std::min(t + *h, next);
        overlapping = !overlapping;
        recordSensorChange(w, sensor, visitor, t, overlapping, found);
        ++changes;
        continue;
      }
      if (!(next < end)) break;
      t = next;
    }
  };
  w.broadPhase.findSensorPairs([&](uint32_t fa, uint32_t fb) {
    if (!canSense(w, fa, fb)) return;
    sensorOverlapsSeen(w, fa, fb);
    if (w.fixtures[fa].sensor) {
      sense(fa, fb);
    } else {
      sense(fb, fa);
    }
  });

  // 3. Overlaps whose pair the sweep did not see: the body was moved away between steps (so they are
  // judged where the bodies were at the step's start).
  endUnseenOverlaps(w, [&](uint32_t body) { return positionOn(pathOf(body)[0], 0.0); });
  // One pair's events are in time order already; the sort is stable, so they stay so at equal times.
  sortSensorEvents(found);
  w.sensorEvents.insert(w.sensorEvents.end(), found.begin(), found.end());
}

}  // namespace rattle
