// The discrete mode: step and check (the seeds' first approach, and the baseline the others are
// measured against). Every body moves the whole step; sort-and-sweep over the boxes where the bodies end
// finds overlapping pairs; each such pair is pushed apart along its normal (in inverse proportion to the
// masses) and, when approaching, gets the same restitution impulse as in the other modes. One response
// per pair per step, all reported at the end of the step. A body fast enough to pass a wall within one
// step passes it, and a body between two close walls meets at most one of them per step: the tests
// document both.
#include <algorithm>
#include <cmath>
#include <span>

#include "collision/closest_point.h"
#include "world/world_impl.h"

namespace rattle {

using detail::BodySlot;

namespace {

struct Penetration {
  Vec2 normal;  // from the other fixture toward the circle
  double depth;
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

}  // namespace

void detail::WorldState::stepDiscrete(double dt) {
  contactEvents.clear();
  sensorEvents.swap(pendingSensorEvents);
  pendingSensorEvents.clear();
  stats = StepStats{};
  ++stepStamp;

  // 1. Move everything a whole step (where it was kept first: step_undo.cpp).
  for (uint32_t i = 0; i < bodies.size(); ++i) {
    BodySlot& b = bodies[i];
    if (!b.alive || b.type == BodyType::Static || b.asleep) continue;
    stepStart.motion[i] = {b.position, b.velocity};
    b.localTime = 0;
    if (b.type == BodyType::Dynamic) {
      b.acceleration = def.gravity;
      b.position = b.position + b.velocity * dt + b.acceleration * (0.5 * dt * dt);
      b.velocity += b.acceleration * dt;
    } else {
      b.position += b.velocity * dt;
    }
    for (uint32_t f : b.fixtures) {
      broadPhase.setMoving(f, true);
      broadPhase.setBox(f, worldBox(f));
    }
  }

  // 2. Overlapping pairs where the bodies ended.
  struct Pair {
    uint32_t a, b;
    uint32_t rank = 0;  // 0: two dynamic bodies; 1: with a kinematic body; 2: with a static body (step 3)
  };
  auto byIds = [](const Pair& x, const Pair& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; };
  std::vector<Pair> pairs;
  broadPhase.setPairCache(false);  // its responses follow the sweep's order
  broadPhase.setPairTestBudget(pairTestBudget());
  // Memory for the pairs, too, is bounded: overlapping boxes come a few to a body unless bodies pile up.
  const size_t pairLimit = 16 * fixtures.size() + static_cast<size_t>(def.maxEventsPerStep);
  bool tooMany = false;
  broadPhase.findPairs([&](uint32_t fa, uint32_t fb) {
    if (!canCollide(fa, fb)) return;
    if (pairs.size() == pairLimit) {
      tooMany = true;
      return;
    }
    const BodyType ta = bodyOf(fa).type, tb = bodyOf(fb).type;
    const uint32_t rank = (ta == BodyType::Static || tb == BodyType::Static)        ? 2
                          : (ta == BodyType::Kinematic || tb == BodyType::Kinematic) ? 1
                                                                                     : 0;
    pairs.push_back({std::min(fa, fb), std::max(fa, fb), rank});
  });
  if (broadPhase.overflowed() || tooMany) {
    // A degenerate world (bodies piled on one point): the pairs are incomplete, and pushing millions of
    // them apart one by one would cost as much as testing them all. None is, and the step says so.
    stats.eventBudgetReached = true;
    pairs.clear();
  }
  // Pairs of two dynamic bodies first, then those with a kinematic body, those with a static body last:
  // a push between two dynamic bodies may move one into a wall, and the wall's push, coming after it,
  // has the last word (a body is never left pushed into a static body by another's push). Within each,
  // fixture order.
  std::sort(pairs.begin(), pairs.end(),
            [&](const Pair& x, const Pair& y) { return x.rank != y.rank ? x.rank < y.rank : byIds(x, y); });
  stats.candidatePairs = static_cast<int>(pairs.size());

  // Where each dynamic body's own motion took it, before any push: a push that carries its centre
  // across a static fixture's surface from there is taken back (step 3b).
  struct Moved {
    uint32_t body;
    Vec2 position;
    bool pushedByKinematic;
  };
  std::vector<uint32_t> walls;  // scratch of step 3b
  // Moves body `b`'s circle (centre offset `centre`, radius `radius`) out of the static fixtures `statics`,
  // position only, a few rounds at most: a box's corner overlaps a circle at two features, and leaving
  // one may touch the other.
  auto pushOutOf = [&](BodySlot& b, Vec2 centre, double radius, std::span<const uint32_t> statics) {
    for (int k = 0; k < 3; ++k) {
      bool moved = false;
      for (uint32_t g : statics) {
        const auto pen = penetration(b.position + centre, radius, fixtures[g].geometry, bodyOf(g).position);
        if (!pen) continue;
        b.position += pen->normal * pen->depth;
        moved = true;
      }
      if (!moved) break;
    }
  };
  std::vector<Moved> pushed;  // bodies pushed by another dynamic or a kinematic body, in the order first pushed
  std::vector<int>& pushedSlot = jamSlot;  // body -> index into `pushed`; -1 outside it (reset below)
  if (pushedSlot.size() < bodies.size()) pushedSlot.resize(bodies.size(), -1);
  auto notePush = [&](uint32_t body, Vec2 before, bool byKinematic) {
    if (pushedSlot[body] < 0) {
      pushedSlot[body] = static_cast<int>(pushed.size());
      pushed.push_back({body, before, false});
    }
    pushed[pushedSlot[body]].pushedByKinematic |= byKinematic;
  };

  // 3. Push apart and reflect, in that order.
  for (const Pair& p : pairs) {
    // The dynamic circle is `own`; `other` may be anything.
    const bool aDynamic = bodyOf(p.a).type == BodyType::Dynamic;
    const uint32_t own = aDynamic ? p.a : p.b, other = aDynamic ? p.b : p.a;
    BodySlot& body = bodyOf(own);
    BodySlot& partner = bodyOf(other);
    ++stats.timeOfImpactTests;
    const auto pen =
        penetration(body.position + detail::circleCentre(fixtures[own].geometry),
                    detail::circleRadius(fixtures[own].geometry), fixtures[other].geometry, partner.position);
    if (!pen) continue;
    if (stats.eventsProcessed >= def.maxEventsPerStep) {
      stats.eventBudgetReached = true;
      break;
    }
    const double inverseA = body.asleep ? 0.0 : body.inverseMass;
    const double inverseB = (partner.type == BodyType::Dynamic && !partner.asleep) ? partner.inverseMass : 0.0;
    const double inverseSum = inverseA + inverseB;
    if (!(inverseSum > 0)) continue;
    if (partner.type != BodyType::Static) {
      notePush(fixtures[own].body, body.position, partner.type == BodyType::Kinematic);
      if (inverseB > 0) notePush(fixtures[other].body, partner.position, false);
    } else if (pushedSlot[fixtures[own].body] >= 0 && pushed[pushedSlot[fixtures[own].body]].pushedByKinematic) {
      // Pushed by a kinematic body into a static one: a squeeze. The wall holds; the kinematic body
      // overlaps it (README, "Squeezes").
      ++stats.squeezes;
      pushed[pushedSlot[fixtures[own].body]].pushedByKinematic = false;
    }
    body.position += pen->normal * (pen->depth * inverseA / inverseSum);
    partner.position -= pen->normal * (pen->depth * inverseB / inverseSum);
    if (partner.type == BodyType::Static) {
      // A polyline or polygon can overlap the circle at more than one feature (a corner of a box): out of
      // each in turn (the impulse below is the pair's one).
      pushOutOf(body, detail::circleCentre(fixtures[own].geometry), detail::circleRadius(fixtures[own].geometry),
                std::span<const uint32_t>(&other, 1));
    }
    const double vn = dot(body.velocity - partner.velocity, pen->normal);
    // Only an approach is a collision; an overlap that is already separating, or approaching no faster
    // than round-off of the speeds involved, is just pushed apart.
    const double roundOff = 1e-13 * (length(body.velocity) + length(partner.velocity));
    if (!(vn < -roundOff)) continue;
    const double e = std::max(fixtures[own].restitution, fixtures[other].restitution);
    double j = -(1 + e) * vn / inverseSum;
    body.velocity += pen->normal * (j * inverseA);
    partner.velocity -= pen->normal * (j * inverseB);
    // As in the hybrid step: with restitution 0, leave the pair separating, not approaching by round-off.
    for (int k = 0; k < 3; ++k) {
      const double after = dot(body.velocity - partner.velocity, pen->normal);
      if (!(after < 0)) break;
      const double extra = -after / inverseSum;
      body.velocity += pen->normal * (extra * inverseA);
      partner.velocity -= pen->normal * (extra * inverseB);
      j += extra;
    }
    ++stats.eventsProcessed;
    ContactEvent event;
    event.time = dt;
    // Where the two touch once pushed apart: on the circle, opposite its normal.
    event.point = body.position + detail::circleCentre(fixtures[own].geometry) -
                  pen->normal * detail::circleRadius(fixtures[own].geometry);
    event.impulse = j;
    const bool ownIsLower = own < other;
    const uint32_t fa = ownIsLower ? own : other, fb = ownIsLower ? other : own;
    event.fixtureA = {fa, fixtures[fa].generation};
    event.fixtureB = {fb, fixtures[fb].generation};
    event.bodyA = {fixtures[fa].body, bodies[fixtures[fa].body].generation};
    event.bodyB = {fixtures[fb].body, bodies[fixtures[fb].body].generation};
    event.normal = ownIsLower ? -pen->normal : pen->normal;  // pen->normal points from other toward own
    contactEvents.push_back(event);
  }

  // 3b. A push may have carried a body's centre across a static fixture's surface (a thin wall, a
  // polygon's edge), where the wall's own push would only drive it further out on the wrong side. Such a
  // body goes back to where its centre first crossed, on the side it came from, and stops moving into
  // the surface. A body whose box met no static fixture's after its own motion, pushed less than its
  // radius, cannot have crossed one (its centre stayed inside that box): most of a gas is not looked at.
  std::vector<uint32_t> nearStatic;
  for (const Pair& p : pairs) {
    if (p.rank != 2) continue;
    const uint32_t ba = fixtures[p.a].body, bb = fixtures[p.b].body;
    nearStatic.push_back(bodies[ba].type == BodyType::Static ? bb : ba);
  }
  std::sort(nearStatic.begin(), nearStatic.end());
  for (const Moved& m : pushed) {
    pushedSlot[m.body] = -1;
    BodySlot& b = bodies[m.body];
    const Vec2 travel = b.position - m.position;
    if (travel == Vec2{}) continue;
    uint32_t own = 0;
    bool physical = false;
    for (uint32_t f : b.fixtures) {
      if (!fixtures[f].sensor) {
        own = f;
        physical = true;
        break;
      }
    }
    if (!physical) continue;
    const double radius = detail::circleRadius(fixtures[own].geometry);
    if (length(travel) < radius && !std::binary_search(nearStatic.begin(), nearStatic.end(), m.body)) continue;
    const Vec2 centre = detail::circleCentre(fixtures[own].geometry);
    const Vec2 from = m.position + centre;
    Box path{{std::min(from.x, from.x + travel.x), std::min(from.y, from.y + travel.y)},
             {std::max(from.x, from.x + travel.x), std::max(from.y, from.y + travel.y)}};
    std::optional<RayCastHit> first;
    uint32_t firstFixture = 0;
    walls.clear();
    broadPhase.query(path, [&](uint32_t g) {
      if (bodyOf(g).type != BodyType::Static || !canCollide(own, g)) return;
      walls.push_back(g);
      const auto hit = rayCast(fixtures[g].geometry, bodyOf(g).position, from, travel);
      if (!hit || !(hit->fraction > 0)) return;  // none, or the centre started on it or inside it
      if (!first || hit->fraction < first->fraction || (hit->fraction == first->fraction && g < firstFixture)) {
        first = hit;
        firstFixture = g;
      }
    });
    if (!first) continue;
    b.position = first->point + first->normal * radius - centre;
    const double vn = dot(b.velocity, first->normal);
    if (vn < 0) b.velocity -= first->normal * vn;
    // Put back on its side, it may overlap another wall there (a corner): out of those too.
    std::sort(walls.begin(), walls.end());
    pushOutOf(b, centre, radius, walls);
  }
  pushed.clear();

  // 4. Sensors: what overlaps where the bodies ended, after the pushes (a push can move a body into a
  // sensor or out of one), against what overlapped before.
  std::vector<Pair> sensing;
  if (liveSensors > 0) {
    for (const BodySlot& b : bodies) {
      if (!b.alive || b.type == BodyType::Static || b.asleep) continue;
      for (uint32_t f : b.fixtures) broadPhase.setBox(f, worldBox(f));
    }
    broadPhase.findSensorPairs([&](uint32_t fa, uint32_t fb) {
      if (canSense(fa, fb)) sensing.push_back({std::min(fa, fb), std::max(fa, fb)});
    });
    std::sort(sensing.begin(), sensing.end(), byIds);
    stats.candidatePairs += static_cast<int>(sensing.size());
  }
  for (const Pair& p : sensing) {
    sensorOverlapsSeen(p.a, p.b);
    const bool now =
        overlaps(fixtures[p.a].geometry, bodyOf(p.a).position, fixtures[p.b].geometry, bodyOf(p.b).position);
    if (now != isOverlapping(p.a, p.b)) recordSensorChange(p.a, p.b, dt, now, sensorEvents);
  }
  std::vector<uint64_t> unseen;
  for (const auto& [key, seen] : sensorOverlaps) {
    if (seen != stepStamp) unseen.push_back(key);
  }
  std::sort(unseen.begin(), unseen.end());
  for (uint64_t key : unseen) {
    const uint32_t sensor = static_cast<uint32_t>(key >> 32), visitor = static_cast<uint32_t>(key);
    if (!overlaps(fixtures[sensor].geometry, bodyOf(sensor).position, fixtures[visitor].geometry,
                  bodyOf(visitor).position)) {
      recordSensorChange(sensor, visitor, dt, false, sensorEvents);
    }
  }
  time += dt;
}

}  // namespace rattle
