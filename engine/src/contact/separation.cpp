// Separation of pairs made overlapping.
//
// Two dynamic bodies made overlapping (units spawned at one point, a body set onto another) have no
// time of impact to meet at: exact events would bounce each off all the others in turn, each bounce
// predicting it against all of them again (a wave of 400 units spawned at one point cost seconds a
// step), and a pair that passes through each other (squeeze.cpp) stays on one another until the game
// drives them apart. Such a pair is exempt from collisions while it overlaps; here it is parted, as a
// position correction outside the islands: a step moves the two apart by a share of their overlap,
// and a few steps leave them apart, when the pair collides again.
//
// The move changes no velocity, and keeps the pair's centre of mass (each body moves in inverse
// proportion to its mass), so under gravity it changes no potential energy either: energy is what it
// was. A move that would touch a static fixture is cut short there, so a body is never moved into a
// wall; under gravity the other's move is cut short alike, so that the centre of mass stays, and
// without gravity the other takes on what the wall took.
#include "contact/separation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "collision/closest_point.h"
#include "contact/squeeze.h"
#include "rattle/time_of_impact.h"

namespace rattle {

namespace {

// At most this fraction of the pair's larger radius a step: a unit of radius 0.5 made on another is
// parted in about eight steps, no faster than a unit walks at 30 ticks a second.
constexpr double kSeparationShare = 0.25;

// Directions for a pair whose centres coincide (no line between them): picked by the pair's fixtures,
// so that a crowd made at one point spreads in several directions, and the same on every run.
constexpr double kHalfRoot2 = 0.70710678118654752440;
constexpr Vec2 kCoincidentDirections[8] = {{1, 0},  {kHalfRoot2, kHalfRoot2},   {0, 1},  {-kHalfRoot2, kHalfRoot2},
                                           {-1, 0}, {-kHalfRoot2, -kHalfRoot2}, {0, -1}, {kHalfRoot2, -kHalfRoot2}};

bool isCircleLike(const Geometry& g) { return std::holds_alternative<Circle>(g) || std::holds_alternative<Point>(g); }

// A body this pass may move: awake, not sliding on a face (a slide is motion along where the face
// was), holding up no sleeper (it would have to wake them), and each of its physical fixtures a circle
// or a point.
bool movable(const detail::WorldState& w, uint32_t body) {
  const detail::BodySlot& b = w.bodies[body];
  if (b.type != BodyType::Dynamic || b.asleep || b.sliding || !w.dependents[body].empty()) return false;
  return std::all_of(b.fixtures.begin(), b.fixtures.end(),
                     [&](uint32_t f) { return w.fixtures[f].sensor || isCircleLike(w.fixtures[f].geometry); });
}

// Fixtures by the lower x edge of their boxes where they are now: the broad phase's bands are those of
// its last sweep (none yet in the predictive mode, and without fixtures added or moved since), so the
// pass reads its own.
struct SortedBoxes {
  std::vector<std::pair<Box, uint32_t>> byLowerX;
  double widest = 0;  // the widest box: a query starts that far before its own lower edge

  // The live fixtures, not sensors, of bodies of type `type`.
  SortedBoxes(const detail::WorldState& w, BodyType type) {
    for (uint32_t f = 0; f < w.fixtures.size(); ++f) {
      const detail::FixtureSlot& s = w.fixtures[f];
      if (!s.alive || s.sensor || w.bodies[s.body].type != type) continue;
      const Box box = w.worldBox(f);
      byLowerX.push_back({box, f});
      widest = std::max(widest, box.max.x - box.min.x);
    }
    std::sort(byLowerX.begin(), byLowerX.end(), [](const auto& a, const auto& b) {
      return a.first.min.x < b.first.min.x || (a.first.min.x == b.first.min.x && a.second < b.second);
    });
  }
  template <class Found>
  void query(const Box& q, Found&& found) const {
    auto it = std::lower_bound(byLowerX.begin(), byLowerX.end(), q.min.x - widest,
                               [](const auto& e, double x) { return e.first.min.x < x; });
    for (; it != byLowerX.end() && it->first.min.x <= q.max.x; ++it) {
      if (it->first.overlaps(q)) found(it->second);
    }
  }
};

// The fraction in [0, 1] of the move `delta` the body can take before one of its fixtures touches a
// static fixture it collides with (the time of impact of the move taken as a motion over unit time).
double freeFraction(const detail::WorldState& w, const SortedBoxes& statics, uint32_t body, Vec2 delta) {
  double fraction = 1;
  const detail::BodySlot& b = w.bodies[body];
  for (uint32_t f : b.fixtures) {
    if (w.fixtures[f].sensor) continue;
    const Box from = w.worldBox(f);
    statics.query(unionOf(from, from.translated(delta)), [&](uint32_t o) {
      if (!detail::canCollide(w, f, o)) return;
      const auto hit = timeOfImpact(w.fixtures[f].geometry, b.position, w.fixtures[o].geometry, w.bodyOf(o).position,
                                    Motion(delta), fraction);
      if (hit) fraction = std::min(fraction, hit->time);
    });
  }
  return fraction;
}

struct Overlap {
  uint32_t fa, fb;
  Vec2 ca, cb;  // the fixtures' centres
  double depth;
};

Overlap overlapOf(const detail::WorldState& w, uint32_t fa, uint32_t fb) {
  const detail::CircleOverlap o = detail::circleOverlap(w.fixtures[fa].geometry, w.bodyOf(fa).position,
                                                        w.fixtures[fb].geometry, w.bodyOf(fb).position);
  return {fa, fb, o.ca, o.cb, o.depth};
}

}  // namespace

void detail::separateExemptPairs(WorldState& w) {
  if (w.squeezes.empty()) return;
  // The pairs to part, and how many each body is in: a body in k of them takes 1/k of each share, so
  // that a crowd made at one point spreads rather than flies apart.
  std::vector<Overlap> pairs;
  std::vector<uint32_t> partners;  // each pair's two bodies
  for (const WorldState::Squeeze& s : w.squeezes) {
    const uint32_t fa = static_cast<uint32_t>(s.key >> 32), fb = static_cast<uint32_t>(s.key);
    const FixtureSlot& a = w.fixtures[fa];
    const FixtureSlot& b = w.fixtures[fb];
    if (!a.alive || !b.alive || !isCircleLike(a.geometry) || !isCircleLike(b.geometry)) continue;
    if (!movable(w, a.body) || !movable(w, b.body)) continue;
    const Overlap o = overlapOf(w, fa, fb);
    if (!(o.depth > 0)) continue;
    pairs.push_back(o);
    partners.push_back(a.body);
    partners.push_back(b.body);
  }
  if (pairs.empty()) return;
  std::sort(partners.begin(), partners.end());
  std::vector<std::pair<uint32_t, uint32_t>> counts;  // (body, how many pairs), sorted by body
  for (uint32_t body : partners) {
    if (counts.empty() || counts.back().first != body) counts.push_back({body, 0});
    ++counts.back().second;
  }
  auto countOf = [&](uint32_t body) {
    return std::lower_bound(counts.begin(), counts.end(), std::pair<uint32_t, uint32_t>{body, 0})->second;
  };
  const SortedBoxes statics(w, BodyType::Static);
  w.changes.roomToTouch(2 * pairs.size());
  // Nothing below allocates but keep(), which the step's undo needs and which fails cleanly.
  for (const Overlap& start : pairs) {
    const Overlap o = overlapOf(w, start.fa, start.fb);  // an earlier pair may have moved one of them
    if (!(o.depth > 0)) continue;
    const uint32_t ia = w.fixtures[o.fa].body, ib = w.fixtures[o.fb].body;
    BodySlot& a = w.bodies[ia];
    BodySlot& b = w.bodies[ib];
    const double gap = length(o.cb - o.ca);
    const Vec2 n = gap > 0 ? (o.cb - o.ca) * (1 / gap) : kCoincidentDirections[(o.fb - o.fa) % 8];
    const double larger = std::max(circleRadius(w.fixtures[o.fa].geometry), circleRadius(w.fixtures[o.fb].geometry));
    // The last move leaves them apart by their coordinates' round-off, not touching: refreshSqueezes then
    // ends the exemption at once, and a pair still driven together collides in this very step (left
    // touching, it stayed exempt, and the drive took it back in by a step's travel every step).
    const double apart = 4 * std::numeric_limits<double>::epsilon() *
                         std::max({std::fabs(o.ca.x), std::fabs(o.ca.y), std::fabs(o.cb.x), std::fabs(o.cb.y), larger});
    const double share = std::min(o.depth + apart, kSeparationShare * larger) / std::max(countOf(ia), countOf(ib));
    const double total = a.mass + b.mass;
    if (!(share > 0) || !(total > 0) || !std::isfinite(total)) continue;
    Vec2 moveA = n * (-share * (b.mass / total)), moveB = n * (share * (a.mass / total));
    const double fractionA = freeFraction(w, statics, ia, moveA), fractionB = freeFraction(w, statics, ib, moveB);
    if (w.def.gravity == Vec2{}) {
      // Positions hold no energy here: what a wall takes from one body's move the other takes on (a unit
      // made on one that stands against a wall).
      const Vec2 restA = moveA * (1 - fractionA), restB = moveB * (1 - fractionB);
      moveA = moveA * fractionA;
      moveB = moveB * fractionB;
      if (fractionA < 1) moveB += restA * -1.0;
      if (fractionB < 1) moveA += restB * -1.0;
      if (fractionA < 1 || fractionB < 1) {
        moveA = moveA * (fractionB < 1 ? freeFraction(w, statics, ia, moveA) : 1.0);
        moveB = moveB * (fractionA < 1 ? freeFraction(w, statics, ib, moveB) : 1.0);
      }
    } else {
      // Both cut short alike, so that their centre of mass, and with it their potential energy, stays.
      const double fraction = std::min(fractionA, fractionB);
      moveA = moveA * fraction;
      moveB = moveB * fraction;
    }
    if (moveA == Vec2{} && moveB == Vec2{}) continue;
    w.keep(a);
    w.keep(b);
    a.position += moveA;
    b.position += moveB;
    w.touched(ia);
    w.touched(ib);
  }
  for (const auto& count : counts) {
    const uint32_t body = count.first;
    for (uint32_t f : w.bodies[body].fixtures) w.broadPhase.setBox(f, w.worldBox(f));
  }
  if (w.def.gravity == Vec2{}) {
    // A move may take a body deep into a third that nothing brings toward it (the next in a queue, which
    // the game holds still): no impact would ever exempt that pair, and it stayed on one another. It is
    // exempt now, and parted from the next step on, as a pair made overlapping.
    const SortedBoxes dynamics(w, BodyType::Dynamic);
    for (const auto& count : counts) {
      for (uint32_t f : w.bodies[count.first].fixtures) {
        if (w.fixtures[f].sensor || !isCircleLike(w.fixtures[f].geometry)) continue;
        dynamics.query(w.worldBox(f), [&](uint32_t g) {
          if (isCircleLike(w.fixtures[g].geometry) && detail::canCollide(w, f, g)) {
            exemptIfMadeOverlapping(w, std::min(f, g), std::max(f, g), 0.0);
          }
        });
      }
    }
  }
  refreshSqueezes(w);  // the pairs parted are exempt no longer
}

}  // namespace rattle
