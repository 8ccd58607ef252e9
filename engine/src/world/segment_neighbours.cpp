// The Segments of one body that meet end to end. To a point, two Segments that share an end are joined
// there as two faces of a Polyline are: its time of impact reads the far end of the other, an acute
// joint being the apex of a wedge the point may be in (time_of_impact.cpp), and a slide along one ends
// beyond such a joint (resting.cpp). A Segment is another's neighbour only where it is the one other
// Segment of the body with an end there: where three meet, none is, and each face keeps its own
// round-off past that end, as every Segment did before.
#include <algorithm>
#include <vector>

#include "world/world_impl.h"

namespace rattle {

using detail::BodySlot;
using detail::SegmentNeighbours;

namespace {

const Segment* physicalSegment(const detail::WorldState& w, uint32_t f) {
  const detail::FixtureSlot& slot = w.fixtures[f];
  if (!slot.alive || slot.sensor) return nullptr;
  return std::get_if<Segment>(&slot.geometry);
}

bool hasEndAt(const Segment& s, Vec2 p) { return s.a == p || s.b == p; }

// The far end of the one Segment of `body` other than `self` with an end at `joint`, if there is one.
std::optional<Vec2> onlyNeighbourFarEnd(const detail::WorldState& w, const BodySlot& body, uint32_t self, Vec2 joint) {
  std::optional<Vec2> far;
  for (uint32_t g : body.fixtures) {
    const Segment* s = g == self ? nullptr : physicalSegment(w, g);
    if (s == nullptr || !hasEndAt(*s, joint)) continue;
    if (far) return std::nullopt;
    far = s->a == joint ? s->b : s->a;
  }
  return far;
}

void findNeighboursOf(detail::WorldState& w, const BodySlot& body, uint32_t f) {
  SegmentNeighbours& n = w.segmentNeighbours[f];
  n = {};
  const Segment* s = physicalSegment(w, f);
  if (s == nullptr) return;
  if (const auto far = onlyNeighbourFarEnd(w, body, f, s->a)) {
    n.beforeStart = *far;
    n.hasBefore = true;
  }
  if (const auto far = onlyNeighbourFarEnd(w, body, f, s->b)) {
    n.afterEnd = *far;
    n.hasAfter = true;
  }
}

}  // namespace

void detail::refreshSegmentNeighboursAround(WorldState& w, uint32_t body, uint32_t segment) {
  const Segment* s = std::get_if<Segment>(&w.fixtures[segment].geometry);
  w.segmentNeighbours[segment] = {};
  if (s == nullptr || w.fixtures[segment].sensor) return;
  const BodySlot& b = w.bodies[body];
  for (uint32_t g : b.fixtures) {
    const Segment* t = physicalSegment(w, g);
    if (t != nullptr && (g == segment || hasEndAt(*t, s->a) || hasEndAt(*t, s->b))) findNeighboursOf(w, b, g);
  }
}

void detail::findSegmentNeighbours(WorldState& w) {
  w.segmentNeighbours.assign(w.fixtures.size(), SegmentNeighbours{});
  // Per body, every Segment end sorted by position: the ends at one point are then side by side, and a
  // pair of two is a joint (onlyNeighbourFarEnd's rule, in n log n rather than n^2 for a wall of many).
  struct End {
    Vec2 at;
    uint32_t fixture;
    bool start;
  };
  std::vector<End> ends;
  for (const BodySlot& b : w.bodies) {
    if (!b.alive) continue;
    ends.clear();
    for (uint32_t f : b.fixtures) {
      if (const Segment* s = physicalSegment(w, f)) {
        ends.push_back({s->a, f, true});
        ends.push_back({s->b, f, false});
      }
    }
    std::sort(ends.begin(), ends.end(), [](const End& x, const End& y) {
      if (x.at.x != y.at.x) return x.at.x < y.at.x;
      if (x.at.y != y.at.y) return x.at.y < y.at.y;
      return x.fixture < y.fixture;
    });
    for (size_t i = 0; i < ends.size();) {
      size_t j = i + 1;
      while (j < ends.size() && ends[j].at == ends[i].at) ++j;
      if (j - i == 2) {
        for (const auto& [here, there] : {std::pair{ends[i], ends[i + 1]}, std::pair{ends[i + 1], ends[i]}}) {
          const Segment& other = std::get<Segment>(w.fixtures[there.fixture].geometry);
          SegmentNeighbours& n = w.segmentNeighbours[here.fixture];
          (here.start ? n.beforeStart : n.afterEnd) = there.start ? other.b : other.a;
          (here.start ? n.hasBefore : n.hasAfter) = true;
        }
      }
      i = j;
    }
  }
}

}  // namespace rattle
