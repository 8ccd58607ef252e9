// The discrete mode: step and check (the seeds' first approach, and the baseline the others are
// measured against). Every body moves the whole step; sort-and-sweep over the boxes where the bodies end
// finds overlapping pairs; each such pair is pushed apart along its normal (in inverse proportion to the
// masses) and, when approaching, gets the same restitution impulse as in the other modes. One response
// per pair per step, all reported at the end of the step. A body fast enough to pass a wall within one
// step passes it, and a body between two close walls meets at most one of them per step: the tests
// document both.
#include <algorithm>
#include <cmath>

#include "closest_point.h"
#include "world_impl.h"

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

void World::Impl::stepDiscrete(double dt) {
  contactEvents.clear();
  sensorEvents.swap(pendingSensorEvents);
  pendingSensorEvents.clear();
  stats = StepStats{};
  ++stepStamp;

  // 1. Move everything a whole step.
  for (BodySlot& b : bodies) {
    if (!b.alive || b.type == BodyType::Static || b.asleep) continue;
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
  };
  auto byIds = [](const Pair& x, const Pair& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; };
  std::vector<Pair> pairs;
  broadPhase.setPairCache(false);  // its responses follow the sweep's order
  broadPhase.findPairs([&](uint32_t fa, uint32_t fb) {
    if (canCollide(fa, fb)) pairs.push_back({std::min(fa, fb), std::max(fa, fb)});
  });
  std::sort(pairs.begin(), pairs.end(), byIds);
  stats.candidatePairs = static_cast<int>(pairs.size());

  // 3. Push apart and reflect, in fixture order.
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
    body.position += pen->normal * (pen->depth * inverseA / inverseSum);
    partner.position -= pen->normal * (pen->depth * inverseB / inverseSum);
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
