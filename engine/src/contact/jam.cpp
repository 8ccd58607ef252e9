// Jams: a cluster of touching awake bodies that the one-pair-at-a-time model cannot resolve.
//
// Under gravity, a stack of awake disks pressed together (a chain leaning on a wall, a cluster falling
// into a corner) takes infinitely many ever smaller collisions in finite time: inelastic collapse
// (McNamara & Young, Phys. Rev. E 50, R28, 1994; docs/numerics.md). Resolving one pair at a time is
// then Gauss-Seidel on the cluster's contacts, one iteration per event, converging slowly and stopping
// the step at its event budget. Most such clusters form through slow contacts and join a stepped island
// one pair at a time (island.cpp); when a body still collides more than kJamCollisions times in one step,
// its whole touching cluster joins the islands at once and is solved with the island it touches.
//
// Without gravity the same happens to a cluster the game keeps driving into itself (a crowd steered into
// a doorway: BodySlot::driven, after kJamCollisions) and to one nobody drives that collapses (after the
// collapse guard's count, collapse_guard.h). There a jam is undone when its solve would add more than
// kJamResidual of a radius of overlap within the step: stepped bodies meet only through the solves, so
// what a solve leaves unmet would close for the rest of the step.
#include <algorithm>
#include <cmath>

#include "collision/closest_point.h"
#include "contact/collapse_guard.h"
#include "world/stepper.h"
#include "contact/islands.h"
#include "contact/squeeze.h"
#include "world/world_impl.h"

namespace rattle {

using detail::BodySlot;

namespace {

constexpr size_t kMaxJamBodies = 4096;

// Whether p lies within `tolerance` of the boundary of a placed geometry, on either side: closestPoint
// takes a point on a polygon's edge (or a circle's rim) as inside, and finds no closest point there.
bool onBoundary(const Geometry& g, Vec2 position, Vec2 p, double tolerance) {
  if (const auto closest = detail::closestPoint(g, position, p)) return length(p - closest->point) <= tolerance;
  const Vec2 q = p - position;
  if (const auto* polygon = std::get_if<Polygon>(&g)) {
    const size_t n = polygon->points.size();
    for (size_t i = 0; i < n; ++i) {
      const detail::Closest c = detail::closestOnSegment(polygon->points[i], polygon->points[(i + 1) % n], q, true);
      if (length(q - c.point) <= tolerance) return true;
    }
  } else if (const auto* circle = std::get_if<Circle>(&g)) {
    return length(q - circle->center) >= circle->radius - tolerance;
  }
  return false;
}
}  // namespace

// A dynamic body's circles and points share one centre, so a circle with a radius keeps its points a
// radius from anything they meet: the body is a point only when it has no such circle.
bool detail::Islands::bodyIsPoint(const BodySlot& b) const {
  for (uint32_t f : b.fixtures) {
    if (!w.fixtures[f].sensor && !detail::isPoint(w.fixtures[f].geometry)) return false;
  }
  return true;
}

bool detail::Islands::heldByIslandContacts(uint32_t bodyIndex, double now) const {
  // An island's contacts are built from distances (island.cpp), which cannot tell a point's side of a
  // face it lies on: a point's contacts stay events, where its slide and LastContact tell it.
  const BodySlot& s = w.bodies[bodyIndex];
  if (bodyIsPoint(s)) return false;
  // Nor a circle's whose centre lies on a static fixture's boundary: the gather finds no contact there.
  // A point resting in a box's corner, given a second fixture of radius 2.68 (wider than the box),
  // jammed when a falling point kept hitting it, and its island, holding it against nothing, let gravity
  // and the hits carry it 0.046 into the floor
  // (fuzz/regressions/world_api/inside-hybrid-disk-made-on-a-corner-of-a-box). Its events hold it: its
  // point's contacts with the floor and the wall. A centre inside a polygon finds no contact with it
  // either, but such a body was made there and its island's other contacts hold it: left to events,
  // disks made inside a second box's floor spent a step's budget
  // (fuzz/regressions/world_api/budget-hybrid-disks-inside-a-second-box-floor).
  if (bodyIndex >= w.pairsOfBody.size()) return true;
  const Vec2 position = w.positionAt(s, now);
  for (const detail::CandidatePair& pair : w.pairsOfBody[bodyIndex]) {
    const detail::FixtureSlot& own = w.fixtures[pair.own];
    const detail::FixtureSlot& other = w.fixtures[pair.other];
    const BodySlot& holder = w.bodies[other.body];
    if (holder.type != BodyType::Static || own.sensor || other.sensor || detail::isPoint(own.geometry)) continue;
    const Vec2 centre = position + detail::circleCentre(own.geometry);
    if (onBoundary(other.geometry, holder.position, centre, detail::pointRoundOff(centre, holder.position)))
      return false;
  }
  return true;
}

// canJam but for the centres' look at the static fixtures near (heldByIslandContacts), which isJammed
// leaves until a body's count is reached: it asks at every collision.
bool detail::Islands::mayJam(uint32_t bodyIndex) const {
  const BodySlot& s = w.bodies[bodyIndex];
  if (s.type != BodyType::Dynamic || s.asleep || jamMarkOf(bodyIndex).time == kJamRefused) return false;
  return w.def.restingSpeed > 0 && !bodyIsPoint(s);
}

bool detail::Islands::canJam(uint32_t bodyIndex, double now) const {
  return mayJam(bodyIndex) && heldByIslandContacts(bodyIndex, now);
}

bool detail::Islands::collapsing(uint32_t bodyIndex, double now, double dt) {
  // A crowd of 150 nobody drives, crushed against a wall by a gate, collapsed in a cluster of seven
  // disks with thousands of collisions each within 7e-4 s (2% of the step), every body's some 3e-7 s
  // apart: 14,000 events of a step before the collapse guard's count. A gas's collisions of one body
  // are a mean free time apart, far longer. Only a body past kBurstStart collisions in the step is
  // followed, so that a gas marks none.
  if (w.bodies[bodyIndex].stepCollisions <= kBurstStart) return false;
  Burst burst = bursts_.get(bodyIndex);
  burst.count = burst.count > 0 && now - burst.time <= kBurstWindow * dt ? burst.count + 1 : 1;
  burst.time = now;
  bursts_.set(bodyIndex, burst);
  return burst.count > static_cast<uint32_t>(kJamCollisions);
}

bool detail::Islands::isJammed(uint32_t bodyIndex, double now, double dt) {
  if (!mayJam(bodyIndex)) return false;
  BodySlot& s = w.bodies[bodyIndex];
  // Without gravity resolve() counts every collision already (the collapse guard, collapse_guard.h). A
  // body the game drives jams as under gravity; one it does not (a gas) only where the collapse guard
  // would otherwise make its collisions elastic: it is then in an inelastic collapse (a cluster with low
  // restitution in a corner), which exact events cannot end within the step's budget. A body already
  // wedged against a static face this step (squeezeAt) is caught in such a collapse against the wall:
  // a crowd nobody drives, pressed there by a gate, took hundreds of thousands of events in a step
  // before its bodies reached the collapse guard's count. It jams as a driven one does.
  const bool counted =
      w.def.gravity.x == 0 && w.def.gravity.y == 0
          ? s.stepCollisions >
                (detail::jamsAsDriven(w, bodyIndex) || collapsing(bodyIndex, now, dt)
                     ? kJamCollisions
                     : detail::collapseCollisions(w.def.maxEventsPerStep))
          : s.countStepCollision() > kJamCollisions;
  return counted && heldByIslandContacts(bodyIndex, now);
}

bool detail::Islands::settleJamAt(const detail::PredictedContact& c, double dt, bool caughtA, bool caughtB) {
  const uint32_t ia = w.fixtures[c.a].body, ib = w.fixtures[c.b].body;
  const bool jamA = isJammed(ia, c.time, dt) || (caughtA && canJam(ia, c.time));
  const bool jamB = isJammed(ib, c.time, dt) || (caughtB && canJam(ib, c.time));
  if (!jamA && !jamB) return false;
  const uint32_t seed = jamA ? ia : ib, partner = jamA ? ib : ia;
  // A jam settled at this instant already, met by an awake body its cluster cannot take (a point:
  // heldByIslandContacts): settling it again solves the same cluster, leaves this pair as it was, and its
  // contact comes back at once. A point driving a disk into one sunk in a floor took 19,700 such
  // settles at one instant, until the step's budget ran out
  // (fuzz/regressions/world_api/budget-predictive-point-drives-a-disk-into-one-sunk-in-a-floor). The
  // pair is met as any free body meets a stepped one: a collision, a squeeze or an absorb.
  const BodySlot& other = w.bodies[partner];
  if (jamMarkOf(seed).time == c.time && other.type == BodyType::Dynamic && !other.asleep &&
      !heldByIslandContacts(partner, c.time)) {
    return false;
  }
  const int events = settleJam(seed, c.time, dt, w.def.maxEventsPerStep - w.stats.eventsProcessed);
  w.stats.eventsProcessed += events;
  return events > 0;
}

bool detail::Islands::settledTogether(uint32_t ia, uint32_t ib, double now) const {
  const BodySlot& a = w.bodies[ia];
  const BodySlot& b = w.bodies[ib];
  const bool aFree = a.type == BodyType::Dynamic && !a.asleep, bFree = b.type == BodyType::Dynamic && !b.asleep;
  if (!aFree && !bFree) return false;
  const JamMark settled = jamMarkOf(aFree ? ia : ib);
  const JamMark other = jamMarkOf(aFree ? ib : ia);
  const BodySlot& otherBody = aFree ? b : a;
  if (settled.time != now) return false;
  return !(otherBody.type == BodyType::Dynamic && !otherBody.asleep) ||
         (other.jam == settled.jam && other.time == now);
}

void detail::Islands::refuseJam(const std::vector<uint32_t>& cluster) {
  for (uint32_t i : cluster) jamMarks_.set(i, {kJamRefused, 0});
}

double detail::Islands::islandResidual(double h) const {
  // The worst overlap the last solve's contacts reach within h beyond what they had (a fixture created
  // overlapping others is not the solve's doing), beyond kJamResidual of the radius.
  double worst = -std::numeric_limits<double>::infinity();
  for (const IslandContact& c : islandScratch) {
    const Vec2 vb = c.kb >= 0 ? w.bodies[c.b].velocity : c.holderVelocity;
    const double end = c.gap + h * dot(w.bodies[c.a].velocity - vb, c.normal);
    const double radius = detail::circleRadius(w.fixtures[c.fa].geometry);
    worst = std::max(worst, std::min(c.gap, 0.0) - std::min(end, 0.0) - kJamResidual * radius);
  }
  return worst;
}

int detail::Islands::settleJam(uint32_t seed, double now, double dt, int budget) {
  // Touching: within the gap a contact at restingSpeed closes before it rests, under gravity (v^2 / g),
  // and without it within what restingSpeed closes in the step.
  const double g = length(w.def.gravity);
  const double reachBase = g > 0 ? w.def.restingSpeed * w.def.restingSpeed / g : w.def.restingSpeed * dt;
  // The cluster: awake dynamic bodies connected by touching pairs, in the order found from the seed (each
  // body's pairs are in a deterministic order).
  std::vector<uint32_t> cluster{seed};
  std::vector<int>& slot = jamSlot;  // body -> index into cluster; -1 outside it (reset on the way out)
  if (slot.size() < w.bodies.size()) slot.resize(w.bodies.size(), -1);
  slot[seed] = 0;
  for (size_t k = 0; k < cluster.size(); ++k) {
    const uint32_t i = cluster[k];
    const BodySlot& body = w.bodies[i];
    for (const auto& pair : w.pairsOfBody[i]) {
      const detail::FixtureSlot& own = w.fixtures[pair.own];
      const detail::FixtureSlot& other = w.fixtures[pair.other];
      const uint32_t j = other.body;
      const BodySlot& holder = w.bodies[j];
      if (holder.type != BodyType::Dynamic || holder.asleep || slot[j] >= 0) continue;
      if (!heldByIslandContacts(j, now)) continue;  // as in isJammed
      const Vec2 centre = w.positionAt(body, now) + detail::circleCentre(own.geometry);
      const double radius = detail::circleRadius(own.geometry);
      const auto closest = detail::closestPoint(other.geometry, w.positionAt(holder, now), centre);
      if (!closest || !closest->collidable) continue;
      const double distance = length(centre - closest->point);
      if (!(distance > 0) || distance - radius > 1e-7 * std::max(radius, 1e-9) + reachBase) continue;
      if (cluster.size() >= kMaxJamBodies) continue;
      slot[j] = static_cast<int>(cluster.size());
      cluster.push_back(j);
    }
  }
  for (uint32_t i : cluster) slot[i] = -1;
  // Without gravity a body alone (a disk rattling between walls) is no jam: its collisions are exact
  // events, and the collapse guard bounds them.
  const bool noGravity = w.def.gravity.x == 0 && w.def.gravity.y == 0;
  if (noGravity && cluster.size() < 2) {
    refuseJam(cluster);
    return 0;
  }
  // Kept to undo the jam (below).
  std::vector<BodySlot> saved;
  if (noGravity) {
    for (uint32_t i : cluster) saved.push_back(w.bodies[i]);
  }
  const size_t eventMark = w.contactEvents.size();
  // They join the islands, and the whole island they are now part of is solved (island.cpp). Its
  // contacts that were collisions are reported, as many as the step's budget has room for (at least the
  // one event the jam counts is left to it: the caller checked the budget had room).
  joinIslands(cluster, now, dt);
  const std::vector<uint32_t> island = islandOf(cluster);
  for (size_t k = cluster.size(); noGravity && k < island.size(); ++k) saved.push_back(w.bodies[island[k]]);
  ++jamCounter;
  for (uint32_t i : cluster) {
    BodySlot& b = w.bodies[i];
    w.keep(b);
    jamMarks_.set(i, {now, jamCounter});
    b.stepCollisions = 0;
    b.stepLocalsSet = true;
    b.lastContactTime = w.time + now;
    ++b.collisionCount;
  }
  std::vector<Vec2> before(island.size());
  for (size_t k = 0; k < island.size(); ++k) before[k] = w.bodies[island[k]].velocity;
  const IslandSolve solve =
      solveIsland(island, now, dt, length(w.def.gravity) * (dt - now) + w.def.restingSpeed, ~uint64_t{0}, false, true,
                  std::max(budget - 1, 0));
  // Stepped bodies meet each other only through the solves, so what a solve leaves unmet closes for the
  // rest of the step. Without gravity a jam is held only if that stays within kJamResidual of a radius;
  // otherwise (a light disk between heavy ones converges slowly, and a long step multiplies what is left)
  // it is undone and its collisions stay exact events.
  if (noGravity && !(islandResidual(dt - now) <= 0)) {
    for (size_t k = 0; k < island.size(); ++k) w.bodies[island[k]] = saved[k];
    w.contactEvents.resize(eventMark);
    --jamCounter;
    refuseJam(cluster);
    return 0;
  }
  const int reported = solve.reported;
  for (size_t k = 0; k < island.size(); ++k) {
    const BodySlot& b = w.bodies[island[k]];
    if (k < cluster.size() || b.velocity.x != before[k].x || b.velocity.y != before[k].y) {
      predictor->motionChanged(island[k], now, dt);
    }
  }
  settleUnsolvedIslandPairs(now, dt);
  return std::max(reported, 1);
}

}  // namespace rattle
