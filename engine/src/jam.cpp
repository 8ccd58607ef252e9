// Jams: a cluster of touching awake bodies that the one-pair-at-a-time model cannot resolve.
//
// Under gravity, a stack of awake disks pressed together (a column on a disk that slides, a chain leaning
// on a wall) takes infinitely many ever smaller collisions in finite time: inelastic collapse (McNamara &
// Young 1994; NUMERICS.md). Resolving one pair at a time is then Gauss-Seidel on the cluster's contacts,
// one iteration per event, converging slowly and stopping the step at its event budget. When a body
// collides more than kJamCollisions times in one step, the whole touching cluster is resolved at once
// instead, as a simultaneous contact: the impulses lambda >= 0 that leave no touching pair approaching
// with the least kinetic energy, the linear complementarity problem of Moreau's sweeping process, solved
// by projected Gauss-Seidel to convergence (Erleben 2007). With a target of zero every projection lowers
// kinetic energy. The one exception: two awake bodies that gravity presses together part at restingSpeed,
// as a single slow contact does (the minimum bounce of resting.cpp), which is where energy can rise, by
// the same kind of bounded amount. Then every body of the cluster that is slow and held up sleeps,
// bottom up, so the cluster settles instead of chattering.
#include <algorithm>
#include <cmath>

#include "closest_point.h"
#include "world_impl.h"

namespace rattle {

using detail::BodySlot;

namespace {

struct JamContact {
  uint32_t a, b;    // body indices; b may be static, kinematic or sleeping
  uint32_t fa, fb;  // their fixtures
  int ka, kb;       // index into the cluster's velocities, -1 when the body is held fixed
  Vec2 normal;      // from b toward a
  Vec2 point;
  double inverseSum;
  double target = 0;  // separation speed after
  double lambda = 0;
};

constexpr size_t kMaxJamBodies = 4096;
constexpr int kMaxIterations = 500;

}  // namespace

bool World::Impl::isJammed(uint32_t bodyIndex) {
  BodySlot& s = bodies[bodyIndex];
  if (s.type != BodyType::Dynamic || s.asleep) return false;
  if (!(def.restingSpeed > 0) || (def.gravity.x == 0 && def.gravity.y == 0)) return false;
  return ++s.stepCollisions > kJamCollisions;
}

World::Impl::Jam World::Impl::settleJamAt(const detail::PredictedContact& c, double dt) {
  const uint32_t ia = fixtures[c.a].body, ib = fixtures[c.b].body;
  const bool jamA = isJammed(ia), jamB = isJammed(ib);
  if (!jamA && !jamB) return Jam::None;
  const int used = settleJam(jamA ? ia : ib, c.time, dt, def.maxEventsPerStep - stats.eventsProcessed);
  if (used < 0) {
    stats.eventBudgetReached = true;
    return Jam::OverBudget;
  }
  stats.eventsProcessed += used;
  return Jam::Settled;
}

bool World::Impl::settledTogether(const BodySlot& a, const BodySlot& b, double now) const {
  const bool aFree = a.type == BodyType::Dynamic && !a.asleep, bFree = b.type == BodyType::Dynamic && !b.asleep;
  if (!aFree && !bFree) return false;
  const BodySlot& settled = aFree ? a : b;
  const BodySlot& other = aFree ? b : a;
  if (settled.jamTime != now) return false;
  return !(other.type == BodyType::Dynamic && !other.asleep) || (other.jam == settled.jam && other.jamTime == now);
}

int World::Impl::settleJam(uint32_t seed, double now, double dt, int budget) {
  const double reachBase = def.restingSpeed * def.restingSpeed / length(def.gravity);
  // 1. The cluster: awake dynamic bodies connected by touching pairs, in the order found from the seed
  // (each body's pairs are in a deterministic order), and every touching contact of theirs.
  std::vector<uint32_t> cluster{seed};
  std::vector<int>& slot = jamSlot;  // body -> index into cluster; -1 outside it (reset on the way out)
  if (slot.size() < bodies.size()) slot.resize(bodies.size(), -1);
  slot[seed] = 0;
  std::vector<JamContact> contacts;
  for (size_t k = 0; k < cluster.size(); ++k) {
    const uint32_t i = cluster[k];
    BodySlot& body = bodies[i];
    advance(body, now);
    for (const auto& pair : pairsOfBody[i]) {
      const detail::FixtureSlot& own = fixtures[pair.own];
      const detail::FixtureSlot& other = fixtures[pair.other];
      const uint32_t j = other.body;
      const BodySlot& holder = bodies[j];
      const bool movable = holder.type == BodyType::Dynamic && !holder.asleep;
      if (movable && slot[j] >= 0 && static_cast<size_t>(slot[j]) < k) continue;  // seen from j's side
      const Vec2 centre = positionAt(body, now) + detail::circleCentre(own.geometry);
      const double radius = detail::circleRadius(own.geometry);
      const auto closest = detail::closestPoint(other.geometry, positionAt(holder, now), centre);
      if (!closest || !closest->collidable) continue;
      const Vec2 r = centre - closest->point;
      const double distance = length(r);
      const double reach = 1e-7 * std::max(radius, 1e-9) + reachBase;
      if (!(distance > 0) || distance - radius > reach) continue;
      if (movable && slot[j] < 0) {
        if (cluster.size() >= kMaxJamBodies) continue;
        slot[j] = static_cast<int>(cluster.size());
        cluster.push_back(j);
      }
      JamContact c;
      c.a = i;
      c.b = j;
      c.fa = pair.own;
      c.fb = pair.other;
      c.ka = static_cast<int>(k);
      c.kb = movable ? slot[j] : -1;
      c.normal = r * (1.0 / distance);
      c.point = closest->point;
      c.inverseSum = body.inverseMass + (movable ? holder.inverseMass : 0.0);
      // Two awake bodies that gravity presses together (one of them slides on a floor) would meet again
      // at once: they part at restingSpeed, as a single slow contact does (resting.cpp). Against what
      // cannot move, the pair rests, and the body may sleep below.
      if (movable && dot(body.acceleration - holder.acceleration, c.normal) < 0) c.target = def.restingSpeed;
      contacts.push_back(c);
    }
  }
  for (uint32_t i : cluster) slot[i] = -1;
  // Each contact may report an event: the whole solve fits in the step's budget or waits for the next.
  if (static_cast<long long>(contacts.size()) > budget) return -1;
  for (uint32_t i : cluster) advance(bodies[i], now);

  // 2. Projected Gauss-Seidel on the velocities, in the fixed order of the contacts.
  std::vector<Vec2> v(cluster.size());
  for (size_t k = 0; k < cluster.size(); ++k) v[k] = bodies[cluster[k]].velocity;
  double scale = 0;
  for (const Vec2& u : v) scale = std::max(scale, length(u));
  const double tolerance = 1e-14 * std::max(scale, def.restingSpeed);
  for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
    double worst = 0;
    for (JamContact& c : contacts) {
      const Vec2 vb = c.kb >= 0 ? v[c.kb] : velocityAt(bodies[c.b], now);
      const double vn = dot(v[c.ka] - vb, c.normal);
      const double next = std::max(0.0, c.lambda + (c.target - vn) / c.inverseSum);
      const double change = next - c.lambda;
      if (change == 0) continue;
      c.lambda = next;
      v[c.ka] += c.normal * (change * bodies[c.a].inverseMass);
      if (c.kb >= 0) v[c.kb] -= c.normal * (change * bodies[c.b].inverseMass);
      worst = std::max(worst, std::fabs(change) * c.inverseSum);
    }
    if (worst <= tolerance) break;
  }
  const double end = time + now;
  ++jamCounter;
  for (size_t k = 0; k < cluster.size(); ++k) {
    BodySlot& b = bodies[cluster[k]];
    b.velocity = v[k];
    b.jam = jamCounter;
    b.jamTime = now;
    // A slide goes on when the solve left the body moving along its face; otherwise it has left it.
    if (b.support.generation != 0) {
      const double vn = dot(b.velocity, b.support.normal);
      if (std::fabs(vn) <= tolerance) {
        b.velocity -= b.support.normal * vn;
      } else {
        stopSliding(b);
      }
    }
    ++b.collisionCount;
    b.stepCollisions = 0;
    b.lastContactTime = end;
  }

  // 3. Bottom up: whatever is slow and held by static or sleeping bodies sleeps, which may hold up more.
  for (bool changed = true; changed;) {
    changed = false;
    for (uint32_t i : cluster) {
      BodySlot& b = bodies[i];
      if (b.asleep || !(length(b.velocity) < def.restingSpeed)) continue;
      if (supportsAt(i, now, supporters)) {
        putToSleep(i, supporters);
        changed = true;
      }
    }
  }

  // 4. The impulses are contacts like any other, reported at this instant.
  int reported = 0;
  for (const JamContact& c : contacts) {
    if (!(c.lambda > 0)) continue;
    ++reported;
    const bool aIsLower = c.fa < c.fb;
    const uint32_t fa = aIsLower ? c.fa : c.fb, fb = aIsLower ? c.fb : c.fa;
    ContactEvent event;
    event.time = now;
    event.point = c.point;
    event.impulse = c.lambda;
    event.fixtureA = {fa, fixtures[fa].generation};
    event.fixtureB = {fb, fixtures[fb].generation};
    event.bodyA = {fixtures[fa].body, bodies[fixtures[fa].body].generation};
    event.bodyB = {fixtures[fb].body, bodies[fixtures[fb].body].generation};
    event.normal = aIsLower ? -c.normal : c.normal;
    contactEvents.push_back(event);
  }
  for (uint32_t i : cluster) repredict(i, now, dt);
  return std::max(reported, 1);
}

}  // namespace rattle
