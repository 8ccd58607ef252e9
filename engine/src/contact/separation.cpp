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
// The move changes no velocity. Without gravity it is along the line of the centres, each body moving
// in inverse proportion to its mass so that the pair's centre of mass stays. Under gravity it is level
// (square to gravity), so that it changes no potential energy whichever body moves: a move along the
// line would lift one body onto the other. Energy is what it was. A move that would touch a static
// fixture is cut short there, so a body is never moved into a wall, and the other takes on what the
// wall took.
#include "contact/separation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <tuple>
#include <vector>

#include "collision/closest_point.h"
#include "contact/resting.h"
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

// A dynamic body each of whose physical fixtures is a circle or a point: a pair of two such bodies is
// parted here.
bool circleLike(const detail::WorldState& w, uint32_t body) {
  const detail::BodySlot& b = w.bodies[body];
  if (b.type != BodyType::Dynamic) return false;
  return std::all_of(b.fixtures.begin(), b.fixtures.end(),
                     [&](uint32_t f) { return w.fixtures[f].sensor || isCircleLike(w.fixtures[f].geometry); });
}

// Whether this pass may move such a body: awake, holding up no sleeper (it would have to wake them),
// and not sliding on a face (a slide is motion along where the face was) unless the face is level
// under gravity, which the pass's level move keeps it on (or takes it past its end, where the slide
// ends at once: slideEndTime).
bool movable(const detail::WorldState& w, uint32_t body) {
  const detail::BodySlot& b = w.bodies[body];
  if (b.asleep || !w.dependents[body].empty()) return false;
  return !b.sliding || (cross(b.support.normal, w.def.gravity) == 0 && dot(b.support.normal, w.def.gravity) < 0);
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

// The fraction in [0, 1] of the move `delta` the body can take and stay clear of every static fixture it
// collides with: the time of impact of the move taken as a motion over unit time, less what keeps the
// body 64 round-offs of the coordinates off the face (beyond the slack within which a point counts as on
// a face's line, Edge::pointSlack). A point left on the line has no side but its motion's: moving away
// from a wall it was parted onto, it read as arriving from beyond, and its first collision bounced it
// out of its container (fuzz/regressions/world_api/escape-predictive-point-parted-onto-a-wall).
double freeFraction(const detail::WorldState& w, const SortedBoxes& statics, uint32_t body, Vec2 delta) {
  double fraction = 1;
  const detail::BodySlot& b = w.bodies[body];
  for (uint32_t f : b.fixtures) {
    if (w.fixtures[f].sensor) continue;
    const Box from = w.worldBox(f);
    // Widened by the round-off: a point come to rest in a corner lies on the wall's line to round-off,
    // which may be an ulp beyond the wall's box, and a move out through the corner met no wall.
    const Box swept = unionOf(from, from.translated(delta));
    const double reach = 64 * std::numeric_limits<double>::epsilon() *
                         std::max({1.0, std::fabs(swept.min.x), std::fabs(swept.min.y), std::fabs(swept.max.x),
                                   std::fabs(swept.max.y)});
    statics.query({swept.min - Vec2{reach, reach}, swept.max + Vec2{reach, reach}}, [&](uint32_t o) {
      if (!detail::canCollide(w, f, o)) return;
      const auto hit = timeOfImpact(w.fixtures[f].geometry, b.position, w.fixtures[o].geometry, w.bodyOf(o).position,
                                    Motion(delta), fraction);
      if (!hit) return;
      const Box wall = w.worldBox(o);
      const double coordinates = length(b.position) + length(w.bodyOf(o).position) +
                                 std::max({std::fabs(wall.min.x), std::fabs(wall.min.y), std::fabs(wall.max.x),
                                           std::fabs(wall.max.y)});
      const double clearance = 64 * std::numeric_limits<double>::epsilon() * coordinates;
      // Along the face's normal: a move nearly along the face keeps only its normal part's clearance.
      const double closing = std::fabs(dot(delta, hit->normal));
      fraction = std::min(fraction, closing > 0 ? std::max(0.0, hit->time - clearance / closing) : 0.0);
    });
  }
  return fraction;
}

// The largest t in [0, 1] for which a body already displaced by d and moved on by t m stays within
// `bound` of where it started: the root of |d + t m|^2 = bound^2.
double withinBound(Vec2 d, Vec2 m, double bound) {
  const double mm = dot(m, m);
  if (!(mm > 0)) return 1;
  const double dm = dot(d, m), c = dot(d, d) - bound * bound;
  if (!(c < 0)) return dm < 0 ? 1 : 0;  // at the bound already: only a move back in
  const double t = (-dm + std::sqrt(dm * dm - mm * c)) / mm;
  return std::clamp(t, 0.0, 1.0);
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
  w.beingParted.clear();
  if (w.squeezes.empty()) return;
  // The pairs to part, and how many each body is in. Without gravity a body in k of them takes 1/k of
  // each share, so that a crowd made at one point spreads rather than flies apart; under gravity each
  // body's displacement is bounded instead (below). That bound without gravity let the predictive mode
  // spend a step's event budget on small disks wedged round a thin static block
  // (fuzz/regressions/world_api/budget-predictive-parting-four-small-disks-round-a-block).
  std::vector<Overlap> pairs;
  std::vector<uint32_t> partners;  // each pair's two bodies
  const bool underGravity = !(w.def.gravity == Vec2{});
  if (underGravity) {
    // A body asleep in a pair whose other body is awake wakes, with what it holds up, so that both can be
    // moved: a row of units made at one point, landed on a floor between two of them already asleep,
    // had no room, and its awake units were moved to and fro between the two for good.
    std::vector<uint32_t> woken;
    for (const WorldState::Squeeze& s : w.squeezes) {
      const uint32_t fa = static_cast<uint32_t>(s.key >> 32), fb = static_cast<uint32_t>(s.key);
      const FixtureSlot& a = w.fixtures[fa];
      const FixtureSlot& b = w.fixtures[fb];
      if (!a.alive || !b.alive || !isCircleLike(a.geometry) || !isCircleLike(b.geometry)) continue;
      if (circleRadius(a.geometry) == 0 || circleRadius(b.geometry) == 0) continue;
      if (!circleLike(w, a.body) || !circleLike(w, b.body)) continue;
      if (w.bodies[a.body].asleep == w.bodies[b.body].asleep) continue;
      if (!(overlapOf(w, fa, fb).depth > 0)) continue;
      wakeUp(w, w.bodies[a.body].asleep ? a.body : b.body, 0.0, woken);
    }
    for (uint32_t i : woken) w.touched(i);
  }
  for (const WorldState::Squeeze& s : w.squeezes) {
    const uint32_t fa = static_cast<uint32_t>(s.key >> 32), fb = static_cast<uint32_t>(s.key);
    const FixtureSlot& a = w.fixtures[fa];
    const FixtureSlot& b = w.fixtures[fb];
    if (!a.alive || !b.alive || !isCircleLike(a.geometry) || !isCircleLike(b.geometry)) continue;
    if (!circleLike(w, a.body) || !circleLike(w, b.body)) continue;
    // Under gravity the move is level (below), so one body alone may take it: a unit made on one that
    // rests on the floor.
    const bool movableA = movable(w, a.body), movableB = movable(w, b.body);
    if (underGravity ? !movableA && !movableB : !movableA || !movableB) continue;
    // Under gravity a point (no extent) made in a body falls through it, as the two pass through each
    // other, and parts from it so; a level move would only carry it to the body's edge or a wall.
    if (underGravity && (circleRadius(a.geometry) == 0 || circleRadius(b.geometry) == 0)) continue;
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
  auto indexOf = [&](uint32_t body) {
    return static_cast<size_t>(std::lower_bound(counts.begin(), counts.end(), std::pair<uint32_t, uint32_t>{body, 0}) -
                               counts.begin());
  };
  auto countOf = [&](uint32_t body) { return counts[indexOf(body)].second; };
  std::vector<Vec2> displaced(counts.size());  // by indexOf: how far this pass has moved each body
  const SortedBoxes statics(w, BodyType::Static);
  w.changes.roomToTouch(2 * pairs.size());
  w.beingParted.reserve(2 * pairs.size());
  // Nothing below allocates but keep(), which the step's undo needs and which fails cleanly.
  for (const Overlap& start : pairs) {
    const Overlap o = overlapOf(w, start.fa, start.fb);  // an earlier pair may have moved one of them
    if (!(o.depth > 0)) continue;
    const uint32_t ia = w.fixtures[o.fa].body, ib = w.fixtures[o.fb].body;
    const BodySlot& a = w.bodies[ia];
    const BodySlot& b = w.bodies[ib];
    const Vec2 d = o.cb - o.ca;
    const double larger = std::max(circleRadius(w.fixtures[o.fa].geometry), circleRadius(w.fixtures[o.fb].geometry));
    // The last move leaves them apart by their coordinates' round-off, not touching: refreshSqueezes then
    // ends the exemption at once, and a pair still driven together collides in this very step (left
    // touching, it stayed exempt, and the drive took it back in by a step's travel every step).
    const double apart = 4 * std::numeric_limits<double>::epsilon() *
                         std::max({std::fabs(o.ca.x), std::fabs(o.ca.y), std::fabs(o.cb.x), std::fabs(o.cb.y), larger});
    // Without gravity along the line of the centres, by the depth. Under gravity level, square to it: a
    // move along the line would lift one body onto the other, or, cut short by the floor under the lower
    // one, not part them at all (a wave of units made at one point stayed stacked). Level, the pair is
    // apart once its level distance reaches sqrt(R^2 - v^2), v the distance along gravity and R the sum of
    // the radii, and no potential energy changes whichever body moves.
    Vec2 n;
    double need = o.depth;
    if (!underGravity) {
      const double gap = length(d);
      n = gap > 0 ? d * (1 / gap) : kCoincidentDirections[(o.fb - o.fa) % 8];
    } else {
      const Vec2 down = w.def.gravity * (1 / length(w.def.gravity));
      const Vec2 level{-down.y, down.x};
      const double across = dot(d, level), along = dot(d, down);
      const double sum = o.depth + length(d);  // the radii's sum
      n = across > 0 || (across == 0 && (o.fb - o.fa) % 2 == 0) ? level : level * -1.0;
      need = std::sqrt(std::max(0.0, sum * sum - along * along)) - std::fabs(across);
    }
    const double share =
        std::min(need + apart, kSeparationShare * larger) / (underGravity ? 1 : std::max(countOf(ia), countOf(ib)));
    const bool movesA = movable(w, ia), movesB = movable(w, ib);
    const double total = a.mass + b.mass;
    if (!(share > 0) || !(total > 0) || !std::isfinite(total)) continue;
    // In inverse proportion to the masses, which keeps the centre of mass; the whole of it when the other
    // body may not move.
    Vec2 moveA = movesA ? n * (-share * (movesB ? b.mass / total : 1.0)) : Vec2{};
    Vec2 moveB = movesB ? n * (share * (movesA ? a.mass / total : 1.0)) : Vec2{};
    const double fractionA = movesA ? freeFraction(w, statics, ia, moveA) : 1.0;
    const double fractionB = movesB ? freeFraction(w, statics, ib, moveB) : 1.0;
    // Neither move changes potential energy (none without gravity, level under it): what a wall takes from
    // one body's move the other takes on (a unit made on one that stands against a wall).
    const Vec2 restA = moveA * (1 - fractionA), restB = moveB * (1 - fractionB);
    moveA = moveA * fractionA;
    moveB = moveB * fractionB;
    if (fractionA < 1 && movesB) moveB += restA * -1.0;
    if (fractionB < 1 && movesA) moveA += restB * -1.0;
    if (fractionA < 1 || fractionB < 1) {
      moveA = moveA * (fractionB < 1 && movesA ? freeFraction(w, statics, ia, moveA) : 1.0);
      moveB = moveB * (fractionA < 1 && movesB ? freeFraction(w, statics, ib, moveB) : 1.0);
    }
    if (underGravity) {
      // Each body's displacement in this pass stays within kSeparationShare of the larger radius of where
      // it started, the pairs parted one after another from where the others left them (Gauss-Seidel):
      // a level row of units made at one point keeps a third to a half of the deep pairs that 1/k of each
      // share kept after 8 s (bench/README.md).
      const double bound = kSeparationShare * larger;
      const double fraction = std::min(withinBound(displaced[indexOf(ia)], moveA, bound),
                                       withinBound(displaced[indexOf(ib)], moveB, bound));
      moveA = moveA * fraction;
      moveB = moveB * fraction;
      displaced[indexOf(ia)] += moveA;
      displaced[indexOf(ib)] += moveB;
    }
    if (moveA == Vec2{} && moveB == Vec2{}) continue;
    for (const auto& [body, move, moves] : {std::tuple{ia, moveA, movesA}, std::tuple{ib, moveB, movesB}}) {
      if (!moves) continue;
      w.keep(w.bodies[body]);
      w.bodies[body].position += move;
      w.touched(body);
      w.beingParted.push_back(body);
    }
  }
  std::sort(w.beingParted.begin(), w.beingParted.end());
  w.beingParted.erase(std::unique(w.beingParted.begin(), w.beingParted.end()), w.beingParted.end());
  for (const auto& count : counts) {
    const uint32_t body = count.first;
    for (uint32_t f : w.bodies[body].fixtures) w.broadPhase.setBox(f, w.worldBox(f));
  }
  {
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
