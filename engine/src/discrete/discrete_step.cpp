// The discrete mode: step and check (the seeds' first approach, and the baseline the others are
// measured against). Every body moves the whole step; sort-and-sweep over the boxes where the bodies end
// finds overlapping pairs; each such pair is pushed apart along its normal (in inverse proportion to the
// masses) and, when approaching, gets the same restitution impulse as in the other modes. One response
// per pair per step, all reported at the end of the step. A body fast enough to pass a wall within one
// step passes it, and a body between two close walls meets at most one of them per step: the tests
// document both.
#include <algorithm>
#include <cmath>
#include <optional>
#include <span>

#include "collision/closest_point.h"
#include "collision/path_box.h"
#include "contact/impulse.h"
#include "contact/response.h"
#include "contact/tolerances.h"
#include "sensors/sensors.h"
#include "world/stepper.h"
#include "world/world_impl.h"

namespace rattle {

using detail::BodySlot;

namespace {

// How far a circle overlaps another geometry, and along which normal (from the other toward the circle).
struct Penetration {
  Vec2 normal;
  double depth;
};

// The step in named phases over the world's state. It owns only the step's scratch, which each phase
// refills before it reads it: the discrete mode keeps nothing between steps. In this file's anonymous
// namespace, so that each phase, called once, is inlined into step() as when they were one function.
class DiscreteStepper final : public detail::Stepper {
 public:
  explicit DiscreteStepper(detail::WorldState& world);
  void step(double dt) override;
  void forget() override {
    std::fill(pushedSlot_.begin(), pushedSlot_.end(), -1);
    pushed_.clear();
  }

 private:
  struct Pair {
    uint32_t a, b;
    uint32_t rank = 0;  // 0: two dynamic bodies; 1: with a kinematic body; 2: with a static body
  };
  // A body pushed by another dynamic or a kinematic body, and where its own motion had taken it.
  struct Moved {
    uint32_t body;
    Vec2 position;
    bool pushedByKinematic;
  };
  static bool byIds(const Pair& x, const Pair& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; }

  void moveBodies(double dt);
  void findOverlappingPairs();
  void pushApartAndReflect(double dt);
  void reflect(uint32_t own, uint32_t other, const Penetration& pen, double inverseA, double inverseB, double dt);
  std::optional<Vec2> crossedSurface(uint32_t body, Vec2 centre, double radius, uint32_t wall, Penetration& pen);
  void putBackAcrossStatics();
  void putBack(const Moved& m);
  void senseOverlaps(double dt);
  void pushOutOf(detail::BodySlot& b, Vec2 centre, double radius, std::span<const uint32_t> statics,
                 std::optional<uint32_t> neverAcrossFor = std::nullopt);
  bool crossesStatic(uint32_t own, Vec2 from, Vec2 travel);
  bool movedSlowly(uint32_t body, Vec2 ownMotionEnd, double radius) const;
  static double onSurfaceMargin(Vec2 a, Vec2 b);
  void keepCentreOut(detail::BodySlot& b, uint32_t own, Vec2 centre, Vec2 from);
  void stayOnItsSide(detail::BodySlot& b, uint32_t own, Vec2 centre, Vec2 origin);
  void notePush(uint32_t body, Vec2 before, bool byKinematic);

  detail::WorldState& w_;
  std::vector<Pair> pairs_;
  std::vector<Moved> pushed_;  // in the order first pushed
  std::vector<int> pushedSlot_;  // body -> index into pushed_; -1 outside it (all -1 between passes)
  std::vector<uint32_t> nearStatic_;  // bodies in a pair with a static body, sorted
  std::vector<uint32_t> walls_;       // scratch of putBack
  std::vector<SensorEvent> sensed_;   // scratch of senseOverlaps: the step's sensor events, then sorted
};

// How far a circle (centre c, radius r) overlaps a placed geometry, if it does.
std::optional<Penetration> penetration(Vec2 c, double r, const Geometry& g, Vec2 position) {
  if (const auto* other = std::get_if<Circle>(&g)) {
    const Vec2 d = c - (other->center + position);
    const double len = length(d);
    const double depth = r + other->radius - len;
    if (!(depth > 0)) return std::nullopt;
    const Vec2 n = len > 0 ? d * (1.0 / len) : Vec2{1, 0};
    return Penetration{n, depth};
  }
  if (const auto closest = detail::closestPoint(g, position, c)) {
    if (!closest->collidable) return std::nullopt;  // a segment's end is not a corner
    const Vec2 d = c - closest->point;
    const double len = length(d);
    if (!(len < r) || !(len > 0)) return std::nullopt;
    return Penetration{d * (1.0 / len), r - len};
  }
  // The centre is inside a polygon (or a circle, handled above): out through the nearest edge.
  const auto& polygon = std::get<Polygon>(g);
  const size_t n = polygon.points.size();
  Penetration best{{}, -1};
  for (size_t i = 0; i < n; ++i) {
    const Vec2 a = polygon.points[i] + position, b = polygon.points[(i + 1) % n] + position;
    const Vec2 u = (b - a) * (1.0 / length(b - a));
    const Vec2 normal{u.y, -u.x};
    const double s = dot(normal, c - a);  // negative inside
    const double depth = r - s;
    if (best.depth < 0 || depth < best.depth) best = {normal, depth};
  }
  return best;
}

// Whether a circle overlaps a bare Segment only at an end, which does not collide. A slow disk there
// may have crossed the segment's inside this step and gone on past its end: out of a box of four
// Segments at its corner (fuzz/regressions/world_api/escape-discrete-disk-through-a-bare-segment-corner).
bool atSegmentEnd(Vec2 c, double r, const Geometry& g, Vec2 position) {
  if (!std::holds_alternative<Segment>(g)) return false;
  const auto closest = detail::closestPoint(g, position, c);
  return closest && !closest->collidable && length(c - closest->point) < r;
}

DiscreteStepper::DiscreteStepper(detail::WorldState& world) : w_(world) {}

void DiscreteStepper::step(double dt) {
  detail::WorldState& w = w_;
  w.contactEvents.clear();
  w.sensorEvents.swap(w.pendingSensorEvents);
  w.pendingSensorEvents.clear();
  w.stats = StepStats{};
  ++w.stepStamp;
  moveBodies(dt);
  findOverlappingPairs();
  pushApartAndReflect(dt);
  putBackAcrossStatics();
  senseOverlaps(dt);
  w.time += dt;
}

// 1. Move everything a whole step (where it was kept first: step_undo.cpp).
void DiscreteStepper::moveBodies(double dt) {
  detail::WorldState& w = w_;
  for (uint32_t i = 0; i < w.bodies.size(); ++i) {
    BodySlot& b = w.bodies[i];
    if (!b.alive || b.type == BodyType::Static || b.asleep) continue;
    w.stepStart.motion[i] = {b.position, b.velocity};
    b.localTime = 0;
    if (b.type == BodyType::Dynamic) {
      b.acceleration = w.def.gravity;
      b.position = b.position + b.velocity * dt + b.acceleration * (0.5 * dt * dt);
      b.velocity += b.acceleration * dt;
    } else {
      b.position += b.velocity * dt;
    }
    for (uint32_t f : b.fixtures) {
      w.broadPhase.setMoving(f, true);
      w.broadPhase.setBox(f, w.worldBox(f));
    }
  }
}

// 2. Overlapping pairs where the bodies ended.
void DiscreteStepper::findOverlappingPairs() {
  detail::WorldState& w = w_;
  // A local vector while the sweep fills it: a member, reached through `this` from the lambda, is
  // loaded again at every pair the sweep reports.
  std::vector<Pair> pairs;
  w.broadPhase.setPairCache(false);  // its responses follow the sweep's order
  w.broadPhase.setPairTestBudget(w.pairTestBudget());
  // Memory for the pairs, too, is bounded: overlapping boxes come a few to a body unless bodies pile up.
  const size_t pairLimit = 16 * w.fixtures.size() + static_cast<size_t>(w.def.maxEventsPerStep);
  bool tooMany = false;
  w.broadPhase.findPairs([&](uint32_t fa, uint32_t fb) {
    if (!canCollide(w, fa, fb)) return;
    if (pairs.size() == pairLimit) {
      tooMany = true;
      return;
    }
    const BodyType ta = w.bodyOf(fa).type, tb = w.bodyOf(fb).type;
    const uint32_t rank = (ta == BodyType::Static || tb == BodyType::Static)        ? 2
                          : (ta == BodyType::Kinematic || tb == BodyType::Kinematic) ? 1
                                                                                     : 0;
    pairs.push_back({std::min(fa, fb), std::max(fa, fb), rank});
  });
  if (w.broadPhase.overflowed() || tooMany) {
    // A degenerate world (bodies piled on one point): the pairs are incomplete, and pushing millions of
    // them apart one by one would cost as much as testing them all. None is, and the step says so.
    w.stats.eventBudgetReached = true;
    pairs.clear();
  }
  // Pairs of two dynamic bodies first, then those with a kinematic body, those with a static body last:
  // a push between two dynamic bodies may move one into a wall, and the wall's push, coming after it,
  // has the last word (a body is never left pushed into a static body by another's push). Within each,
  // fixture order.
  std::sort(pairs.begin(), pairs.end(),
            [&](const Pair& x, const Pair& y) { return x.rank != y.rank ? x.rank < y.rank : byIds(x, y); });
  w.stats.candidatePairs = static_cast<int>(pairs.size());
  pairs_ = std::move(pairs);
}

// Moves body `b`'s circle (centre offset `centre`, radius `radius`) out of the static fixtures `statics`,
// position only, a few rounds at most: a box's corner overlaps a circle at two features, and leaving
// one may touch the other. With neverAcrossFor (the circle's fixture), a push that would carry the centre
// across a static surface that fixture collides with is not made: a disk wedged between a floor and a
// static circle nearer than its diameter was pushed out of the circle through the floor
// (fuzz/regressions/world_api/escape-discrete-disk-wedged-under-a-static-circle). It overlaps then, as a
// disk wider than its slot does (keepCentreOut).
void DiscreteStepper::pushOutOf(BodySlot& b, Vec2 centre, double radius, std::span<const uint32_t> statics,
                                std::optional<uint32_t> neverAcrossFor) {
  detail::WorldState& w = w_;
  for (int k = 0; k < 3; ++k) {
    bool moved = false;
    for (uint32_t g : statics) {
      const auto pen = penetration(b.position + centre, radius, w.fixtures[g].geometry, w.bodyOf(g).position);
      if (!pen) continue;
      if (neverAcrossFor && crossesStatic(*neverAcrossFor, b.position + centre, pen->normal * pen->depth)) continue;
      b.position += pen->normal * pen->depth;
      moved = true;
    }
    if (!moved) break;
  }
}

// Whether the centre moving from `from` by `travel` crosses the surface of a static fixture it collides
// with (starting on or inside one is not a crossing).
bool DiscreteStepper::crossesStatic(uint32_t own, Vec2 from, Vec2 travel) {
  detail::WorldState& w = w_;
  const Box path = detail::pathBox(from, travel, Vec2{}, 1.0);
  bool crosses = false;
  w.broadPhase.query(path, [&](uint32_t g) {
    if (crosses || w.bodyOf(g).type != BodyType::Static || !canCollide(w, own, g)) return;
    const auto hit = rayCast(w.fixtures[g].geometry, w.bodyOf(g).position, from, travel);
    crosses = hit && hit->fraction > 0;
  });
  return crosses;
}

// Where each dynamic body's own motion took it, before any push: a push that carries its centre across a
// static fixture's surface from there is taken back (step 3b).
void DiscreteStepper::notePush(uint32_t body, Vec2 before, bool byKinematic) {
  std::vector<int>& pushedSlot = pushedSlot_;
  if (pushedSlot[body] < 0) {
    pushedSlot[body] = static_cast<int>(pushed_.size());
    pushed_.push_back({body, before, false});
  }
  pushed_[pushedSlot[body]].pushedByKinematic |= byKinematic;
}

// 3. Push apart and reflect, in that order.
void DiscreteStepper::pushApartAndReflect(double dt) {
  detail::WorldState& w = w_;
  std::vector<int>& pushedSlot = pushedSlot_;  // bodies pushed by another dynamic or a kinematic body
  if (pushedSlot.size() < w.bodies.size()) pushedSlot.resize(w.bodies.size(), -1);
  pushed_.clear();
  for (const Pair& p : pairs_) {
    // The dynamic circle is `own`; `other` may be anything.
    const bool aDynamic = w.bodyOf(p.a).type == BodyType::Dynamic;
    const uint32_t own = aDynamic ? p.a : p.b, other = aDynamic ? p.b : p.a;
    BodySlot& body = w.bodyOf(own);
    BodySlot& partner = w.bodyOf(other);
    ++w.stats.timeOfImpactTests;
    const Vec2 centre = detail::circleCentre(w.fixtures[own].geometry);
    const double radius = detail::circleRadius(w.fixtures[own].geometry);
    auto pen = penetration(body.position + centre, radius, w.fixtures[other].geometry, partner.position);
    const uint32_t ownBody = w.fixtures[own].body;
    std::optional<Vec2> crossedFrom;
    // A body pushed already this step (by a body or a wall) is looked at from where it began the step
    // in 3b (putBack).
    const bool pushedAlready = pushedSlot_[ownBody] >= 0;
    if (partner.type == BodyType::Static && !body.asleep &&
        (pen || (!pushedAlready && atSegmentEnd(body.position + centre, radius, w.fixtures[other].geometry,
                                                partner.position)))) {
      Penetration crossing = pen ? *pen : Penetration{};
      crossedFrom = crossedSurface(ownBody, centre, radius, other, crossing);
      if (crossedFrom) pen = crossing;
    }
    if (!pen) continue;
    if (w.stats.eventsProcessed >= w.def.maxEventsPerStep) {
      w.stats.eventBudgetReached = true;
      break;
    }
    const double inverseA = body.asleep ? 0.0 : body.inverseMass;
    const double inverseB = (partner.type == BodyType::Dynamic && !partner.asleep) ? partner.inverseMass : 0.0;
    const double inverseSum = inverseA + inverseB;
    if (!(inverseSum > 0)) continue;
    if (partner.type != BodyType::Static) {
      notePush(ownBody, body.position, partner.type == BodyType::Kinematic);
      if (inverseB > 0) notePush(w.fixtures[other].body, partner.position, false);
    } else if (pushedSlot[ownBody] >= 0 && pushed_[pushedSlot[ownBody]].pushedByKinematic) {
      // Pushed by a kinematic body into a static one: a squeeze. The wall holds; the kinematic body
      // overlaps it (README, "Squeezes").
      ++w.stats.squeezes;
      pushed_[pushedSlot[ownBody]].pushedByKinematic = false;
    } else {
      // Out of one static fixture it may be pushed across another (a slot narrower than the disk).
      notePush(ownBody, body.position, false);
    }
    // Put back on the side it came from, the push-back check (3b) looks from there: from where its
    // own motion took it, it would see the push back across the surface as a crossing.
    if (crossedFrom) pushed_[pushedSlot[ownBody]].position = *crossedFrom;
    body.position += pen->normal * (pen->depth * inverseA / inverseSum);
    partner.position -= pen->normal * (pen->depth * inverseB / inverseSum);
    if (partner.type == BodyType::Static) {
      // A polyline or polygon can overlap the circle at more than one feature (a corner of a box): out of
      // each in turn (the impulse below is the pair's one).
      pushOutOf(body, centre, radius, std::span<const uint32_t>(&other, 1));
    }
    reflect(own, other, *pen, inverseA, inverseB, dt);
  }
}

// How near a static surface a centre counts as on it: well above the round-off of coordinates this
// large, which a fixture's own frame (the body's position subtracted) adds to a distance.
double DiscreteStepper::onSurfaceMargin(Vec2 a, Vec2 b) {
  return 1e-12 * std::max({1.0, std::fabs(a.x), std::fabs(a.y), std::fabs(b.x), std::fabs(b.y)});
}

// A slow body: its own motion this step, which ended at ownMotionEnd before any push moved it (notePush
// kept that), is shorter than its radius. Only such a body's centre is kept on the side of a static
// surface where it began the step (README, the discrete mode's promise); one definition for both places
// that ask (crossedSurface, putBack).
bool DiscreteStepper::movedSlowly(uint32_t body, Vec2 ownMotionEnd, double radius) const {
  return length(ownMotionEnd - w_.stepStart.motion[body].first) < radius;
}

// A slow body (movedSlowly) that overlaps static fixture `wall`, or only a bare Segment's end
// (atSegmentEnd), may have carried its centre across the wall's surface this step: a disk pushed deep
// onto a wall in the step before needs only a little motion of its own to cross it
// (fuzz/regressions/world_api/escape-discrete-disk-pushed-onto-a-wall). The overlap measured from the far
// side would then push it on out of its container. If the path from where its centre began the step
// crosses the surface, `pen` becomes the push that puts the centre a radius out on the side it came
// from, and the result is where the body began the step. A faster body may pass a wall, as documented,
// and is pushed out wherever it ended.
std::optional<Vec2> DiscreteStepper::crossedSurface(uint32_t body, Vec2 centre, double radius, uint32_t wall,
                                                    Penetration& pen) {
  detail::WorldState& w = w_;
  const BodySlot& b = w.bodies[body];
  const int pushedSlot = pushedSlot_[body];  // pushed already in this pass: its own motion ended before that
  if (!movedSlowly(body, pushedSlot >= 0 ? pushed_[pushedSlot].position : b.position, radius)) return std::nullopt;
  const Vec2 start = w.stepStart.motion[body].first;
  const Vec2 travel = b.position - start;
  const auto hit = rayCast(w.fixtures[wall].geometry, w.bodyOf(wall).position, start + centre, travel);
  // None, or the centre began the step on the surface or inside the fixture: the overlap stands.
  if (!hit || !(hit->fraction > 0)) return std::nullopt;
  // The push along the surface's normal at the crossing that leaves the centre a radius out of it.
  pen = Penetration{hit->normal, radius - dot(hit->normal, b.position + centre - hit->point)};
  return start;
}

// The restitution impulse of a pair just pushed apart, and its ContactEvent.
void DiscreteStepper::reflect(uint32_t own, uint32_t other, const Penetration& pen, double inverseA, double inverseB,
                              double dt) {
  detail::WorldState& w = w_;
  BodySlot& body = w.bodyOf(own);
  BodySlot& partner = w.bodyOf(other);
  const double vn = dot(body.velocity - partner.velocity, pen.normal);
  // Only an approach is a collision; an overlap that is already separating, or approaching no faster
  // than round-off of the speeds involved, is just pushed apart.
  const double roundOff = detail::kApproachRoundOff * (length(body.velocity) + length(partner.velocity));
  if (!(vn < -roundOff)) return;
  const double e = std::max(w.fixtures[own].restitution, w.fixtures[other].restitution);
  const detail::PairImpulse impulse = detail::PairImpulse::alongNormal(pen.normal, inverseA, inverseB);
  double j = impulse.bounce(body.velocity, partner.velocity, vn, e);
  impulse.keepSeparating(body.velocity, partner.velocity, pen.normal, j);
  ++w.stats.eventsProcessed;
  // Where the two touch once pushed apart: on the circle, opposite its normal.
  const Vec2 point = body.position + detail::circleCentre(w.fixtures[own].geometry) -
                     pen.normal * detail::circleRadius(w.fixtures[own].geometry);
  w.contactEvents.push_back(contactEventOf(w, own, other, dt, point, pen.normal, j));
}

// 3b. A push may have carried a body's centre across a static fixture's surface (a thin wall, a
// polygon's edge), where the wall's own push would only drive it further out on the wrong side. Such a
// body goes back to where its centre first crossed, on the side it came from, and stops moving into
// the surface. A body whose box met no static fixture's after its own motion, pushed less than its
// radius, cannot have crossed one (its centre stayed inside that box): most of a gas is not looked at.
void DiscreteStepper::putBackAcrossStatics() {
  detail::WorldState& w = w_;
  nearStatic_.clear();
  for (const Pair& p : pairs_) {
    if (p.rank != 2) continue;
    const uint32_t ba = w.fixtures[p.a].body, bb = w.fixtures[p.b].body;
    nearStatic_.push_back(w.bodies[ba].type == BodyType::Static ? bb : ba);
  }
  std::sort(nearStatic_.begin(), nearStatic_.end());
  for (const Moved& m : pushed_) {
    pushedSlot_[m.body] = -1;
    putBack(m);
  }
  pushed_.clear();
}

void DiscreteStepper::putBack(const Moved& m) {
  detail::WorldState& w = w_;
  BodySlot& b = w.bodies[m.body];
  if (b.position == m.position) return;
  uint32_t own = 0;
  bool physical = false;
  for (uint32_t f : b.fixtures) {
    if (!w.fixtures[f].sensor) {
      own = f;
      physical = true;
      break;
    }
  }
  if (!physical) return;
  const double radius = detail::circleRadius(w.fixtures[own].geometry);
  // Pushed less than its radius (less the margin stayOnItsSide keeps), from a box that met no static
  // fixture's: its centre stayed that far inside the box.
  const double pushed = length(b.position - m.position);
  if (pushed < radius - onSurfaceMargin(m.position, b.position) &&
      !std::binary_search(nearStatic_.begin(), nearStatic_.end(), m.body)) {
    return;
  }
  // A slow body is looked at from where it began the step: its own motion may have carried its centre
  // across a surface it began the step deep against (crossedSurface) before a push carried it on. (Its
  // start and end both lie within its radius of m.position, so the test above still holds.)
  const Vec2 origin = movedSlowly(m.body, m.position, radius) ? w.stepStart.motion[m.body].first : m.position;
  const Vec2 travel = b.position - origin;
  const Vec2 centre = detail::circleCentre(w.fixtures[own].geometry);
  const Vec2 from = origin + centre;
  const Box path = detail::pathBox(from, travel, Vec2{}, 1.0);
  std::optional<RayCastHit> first;
  uint32_t firstFixture = 0;
  walls_.clear();
  w.broadPhase.query(path, [&](uint32_t g) {
    if (w.bodyOf(g).type != BodyType::Static || !canCollide(w, own, g)) return;
    walls_.push_back(g);
    const auto hit = rayCast(w.fixtures[g].geometry, w.bodyOf(g).position, from, travel);
    if (!hit || !(hit->fraction > 0)) return;  // none, or the centre started on it or inside it
    if (!first || hit->fraction < first->fraction || (hit->fraction == first->fraction && g < firstFixture)) {
      first = hit;
      firstFixture = g;
    }
  });
  if (first) {
    b.position = first->point + first->normal * radius - centre;
    const double vn = dot(b.velocity, first->normal);
    if (vn < 0) b.velocity -= first->normal * vn;
    // Put back on its side, it may overlap another wall there (a corner): out of those too.
    std::sort(walls_.begin(), walls_.end());
    pushOutOf(b, centre, radius, walls_, own);
  }
  keepCentreOut(b, own, centre, from);
  stayOnItsSide(b, own, centre, origin);
}

// The last word of 3b. Each correction above looks at one surface at a time, and one can carry the
// centre across another: a radius out of a static circle is below a floor that runs through it
// (fuzz/regressions/world_api/escape-discrete-pushed-out-of-a-corner), the second wall of a corner
// pushes across the first, which a segment, having no inside, cannot see afterwards
// (escape-discrete-row-pushes-a-disk-into-a-corner), and a centre on the seam of two wall polygons,
// pushed out of one through its nearest edge, goes into the other (inside-discrete-seam-of-two-walls).
// If the centre's straight path from `origin` still crosses a static surface, or ends inside a static
// fixture that `origin` was not inside, the body goes back to `origin`, which is on the container's
// side by the same rule one step earlier: a closed container's inside is the set of points a straight
// path leaves only across its surface. It stops moving into the surface it would have crossed.
// A path that ends on a surface, within its coordinates' round-off (onSurfaceMargin), goes back too:
// from a centre on a surface no path is seen to cross it (the ray starts on it), and the next step's push
// could carry the centre out unseen (fuzz/regressions/world_api/escape-discrete-pushed-onto-a-wall-line:
// a push of a radius less 3e-16 left a centre 4e-16 inside a wall, where the wall's own frame put it on
// the line). The path is followed that margin beyond its end.
void DiscreteStepper::stayOnItsSide(BodySlot& b, uint32_t own, Vec2 centre, Vec2 origin) {
  detail::WorldState& w = w_;
  const Vec2 from = origin + centre;
  const Vec2 moved = b.position - origin;
  if (moved == Vec2{}) return;
  const Vec2 travel = moved * (1 + onSurfaceMargin(origin, b.position) / length(moved));
  const Box path = detail::pathBox(from, travel, Vec2{}, 1.0);
  std::optional<Vec2> into;  // the normal of the surface it crossed or went into
  uint32_t intoFixture = 0;
  double intoFraction = 2;
  const Vec2 at = from + moved;
  w.broadPhase.query(path, [&](uint32_t g) {
    if (w.bodyOf(g).type != BodyType::Static || !canCollide(w, own, g)) return;
    const Geometry& wall = w.fixtures[g].geometry;
    const Vec2 wallAt = w.bodyOf(g).position;
    double fraction = 2;
    Vec2 normal;
    if (const auto hit = rayCast(wall, wallAt, from, travel); hit && hit->fraction > 0) {
      fraction = hit->fraction;
      normal = hit->normal;
    } else if (const auto inside = penetration(at, 0.0, wall, wallAt); inside && inside->depth > 0) {
      const auto before = penetration(from, 0.0, wall, wallAt);
      if (before && before->depth > 0) return;
      fraction = 1;
      normal = inside->normal;
    } else {
      return;
    }
    if (fraction < intoFraction || (fraction == intoFraction && g < intoFixture)) {
      into = normal;
      intoFraction = fraction;
      intoFixture = g;
    }
  });
  if (!into) return;
  b.position = origin;
  const double vn = dot(b.velocity, *into);
  if (vn < 0) b.velocity -= *into * vn;
}

// A disk wider than the gap between two walls cannot be clear of both: pushed out of one it went into
// the other (fuzz/regressions/world_api/inside-discrete-disk-wider-than-its-slot). It may overlap them,
// but its centre goes no further in than the surface, and stops moving into it. A centre inside a
// static fixture goes back out where its path from `from` (outside, where it was before this step's
// pushes) went in; the nearest surface of a wall thinner than the disk may be its far side.
void DiscreteStepper::keepCentreOut(BodySlot& b, uint32_t own, Vec2 centre, Vec2 from) {
  detail::WorldState& w = w_;
  const Vec2 at = b.position + centre;
  walls_.clear();
  w.broadPhase.query(Box{at, at}, [&](uint32_t g) {
    if (w.bodyOf(g).type == BodyType::Static && canCollide(w, own, g)) walls_.push_back(g);
  });
  std::sort(walls_.begin(), walls_.end());
  for (uint32_t g : walls_) {
    const Geometry& wall = w.fixtures[g].geometry;
    const Vec2 wallAt = w.bodyOf(g).position;
    auto pen = penetration(b.position + centre, 0.0, wall, wallAt);
    if (!pen || !(pen->depth > 0)) continue;
    const auto before = penetration(from, 0.0, wall, wallAt);
    if (!before || !(before->depth > 0)) {
      if (const auto entry = rayCast(wall, wallAt, from, b.position + centre - from)) {
        pen = Penetration{entry->normal, dot(entry->normal, entry->point - (b.position + centre))};
      }
    }
    // Never out across another surface (a static circle reaching through the floor: its way out
    // went through the floor).
    if (crossesStatic(own, b.position + centre, pen->normal * pen->depth)) continue;
    b.position += pen->normal * pen->depth;
    const double vn = dot(b.velocity, pen->normal);
    if (vn < 0) b.velocity -= pen->normal * vn;
  }
}

// 4. Sensors: what overlaps where the bodies ended, after the pushes (a push can move a body into a
// sensor or out of one), against what overlapped before. A change is reported at the step's end, but
// an overlap that held where the bodies began the step too (a body created inside a sensor, or a filter
// changed) begins at time 0, as the other modes and sensorEvents() have it. The events are ordered as
// theirs: by time, then by fixture ids.
void DiscreteStepper::senseOverlaps(double dt) {
  detail::WorldState& w = w_;
  std::vector<Pair> sensing;
  if (w.liveSensors > 0) {
    for (const BodySlot& b : w.bodies) {
      if (!b.alive || b.type == BodyType::Static || b.asleep) continue;
      for (uint32_t f : b.fixtures) w.broadPhase.setBox(f, w.worldBox(f));
    }
    w.broadPhase.findSensorPairs([&](uint32_t fa, uint32_t fb) {
      if (canSense(w, fa, fb)) sensing.push_back({std::min(fa, fb), std::max(fa, fb)});
    });
    std::sort(sensing.begin(), sensing.end(), byIds);
    w.stats.candidatePairs += static_cast<int>(sensing.size());
  }
  const auto& fixtures = w.fixtures;
  // Where a fixture's body began the step (moveBodies kept that of every body it moved).
  const auto startOf = [&](uint32_t f) {
    const uint32_t body = fixtures[f].body;
    const BodySlot& b = w.bodies[body];
    return b.type == BodyType::Static || b.asleep ? b.position : w.stepStart.motion[body].first;
  };
  std::vector<SensorEvent>& found = sensed_;
  found.clear();
  for (const Pair& p : sensing) {
    sensorOverlapsSeen(w, p.a, p.b);
    const bool now = overlaps(fixtures[p.a].geometry, w.bodyOf(p.a).position, fixtures[p.b].geometry,
                              w.bodyOf(p.b).position);
    if (now == isOverlapping(w, p.a, p.b)) continue;
    const bool atStart = now && overlaps(fixtures[p.a].geometry, startOf(p.a), fixtures[p.b].geometry, startOf(p.b));
    recordSensorChange(w, p.a, p.b, atStart ? 0.0 : dt, now, found);
  }
  std::vector<uint64_t> unseen;
  for (const auto& [key, seen] : w.sensorOverlaps) {
    if (seen != w.stepStamp) unseen.push_back(key);
  }
  std::sort(unseen.begin(), unseen.end());
  for (uint64_t key : unseen) {
    const uint32_t sensor = static_cast<uint32_t>(key >> 32), visitor = static_cast<uint32_t>(key);
    if (!overlaps(fixtures[sensor].geometry, w.bodyOf(sensor).position, fixtures[visitor].geometry,
                  w.bodyOf(visitor).position)) {
      recordSensorChange(w, sensor, visitor, dt, false, found);
    }
  }
  detail::sortSensorEvents(found);
  w.sensorEvents.insert(w.sensorEvents.end(), found.begin(), found.end());
}

}  // namespace

std::unique_ptr<detail::Stepper> detail::makeDiscreteStepper(detail::WorldState& world) {
  return std::make_unique<DiscreteStepper>(world);
}

}  // namespace rattle
