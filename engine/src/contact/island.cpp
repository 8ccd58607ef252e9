// Stepped islands: bodies resting on one another under gravity, moved a step at a time.
//
// Under gravity, bodies pressed together (a column standing on a disk that slides on the floor, a pile)
// can only be held by an endless stream of ever smaller collisions when contacts are instantaneous
// events: inelastic collapse (McNamara & Young, Phys. Rev. E 50, R28, 1994; docs/numerics.md). Its cost
// grows with the number of such contacts and not with what moves, and a poured pile of a few thousand
// disks never came to rest.
// So a body that comes to rest on another movable body, and every body of a cluster caught in a
// collapse (more than kJamCollisions collisions in one step), becomes *stepped*: from then on its
// contacts with other stepped bodies and with what cannot move (static, sleeping and kinematic bodies)
// are held by a contact solve once per step instead of by events, as time-stepping engines do (Moreau
// 1988, Jean 1999; Catto's sequential impulses in Box2D), while its meetings with free bodies stay exact
// events.
//
//  - At the start of each step, every stepped body takes gravity for the whole step as an impulse
//    (v += g dt) and then moves along a straight line (acceleration zero) for the step. The solve
//    chooses impulses lambda >= 0 on their contacts so that no contact closes by more than its gap
//    within the step: the relative normal velocity after is >= -gap / dt (a speculative contact,
//    Catto 2013), and >= 0 for a pair already touching. It is the projection of the velocities onto
//    those constraints in the metric of the masses, a linear complementarity problem, solved by
//    projected Gauss-Seidel (Erleben 2007) warm-started from the last step's impulses.
//  - The distance between a moving circle and a fixed convex piece (a circle, a point, a segment) along
//    a straight path is a convex function of time, so meeting the constraint at the end of the step
//    keeps the pair apart all step: distance(t) >= distance(0) + t distance'(0) >= radius.
//  - Energy never rises: the straight path with the whole step's gravity lowers the body by g dt^2 / 2
//    more than the parabola with the same end velocity, and projecting onto constraints that zero
//    satisfies never adds kinetic energy. A projection can still turn a fall into a rise (a wedge lifts
//    the disk on top), so a solve whose members would end the step with more energy than they had
//    scales their velocities down until they do not.
//  - An island of a few bodies is projected exactly (exact_projection.h): under gravity always, without
//    it when the sweeps do not settle (masses far apart).
//  - A free body meeting a stepped body is an event like any other. When it would bounce off slower than
//    restingSpeed (the minimum bounce of resting.cpp), the two join instead (both stepped from then on).
//    When an event changes a stepped body's motion (a join, a hit), its part of the island is solved
//    again for the rest of the step: the stepped bodies within a few candidate pairs of it move, and the
//    rest keep their paths. That part's edge could push it like a moving wall and add energy the whole
//    island would not (it would slow the pusher down), or be impossible to meet; then the solve is undone
//    and tried on a part four times as deep (without gravity then sixteen), and last on the whole island
//    (settleAround).
//  - At the start of a step, a stepped body that no contact held is free again (its gravity impulse is
//    taken back: it falls freely, exactly). At the end of a step, a stepped body slower than
//    restingSpeed sleeps once everything that holds it (pushes it from below or beside) is static,
//    asleep, or sleeps with it: bodies holding one another from beside sleep together, and a body
//    sliding off the top of a settled pile does not keep the pile awake. The solve had cancelled a
//    whole step of gravity on it, so it is held.
//  - Without gravity (a crowd the game drives into a doorway, jam.cpp), a stepped body never sleeps (no
//    up): it is free again when no contact pushes it. The sweeps over-relax there, and the overlap a
//    solve leaves is taken out at the next step's start by moving positions (separateIsland). The solve
//    at a step's start has a fixed number of sweeps; a body whose velocity would still close a contact
//    is stopped for the step (trimIsland), so the step ends with no contact closed beyond kTrimSlack.
//    Under gravity a start solve that stops short (a landing pile's) is trimmed the same way, but only a
//    body that a contact pushes stops: a body no contact pushes is freed onto its parabola.
//  - Cost: one solve of all stepped bodies a step (warm-started, so a resting pile converges in a few
//    sweeps), and a small solve for each join and hit. Accuracy: a solve stops when no impulse changes a
//    velocity by more than 1e-6 of the speeds at play, or under gravity when no contact would close more
//    than kCloseEnough of its disk's radius beyond its bound by the step's end, or after its sweeps (then
//    it is met when no contact closes more than 1e-4 of the speeds at play too fast); disks may overlap
//    by what is left. Contacts with what cannot move get further sweeps of their own, which meet them to
//    round-off.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "collision/closest_point.h"
#include "collision/path_box.h"
#include "contact/exact_projection.h"
#include "contact/islands.h"
#include "contact/response.h"
#include "contact/resting.h"
#include "contact/squeeze.h"
#include "rattle/time_of_impact.h"
#include "world/stepper.h"
#include "world/world_impl.h"

namespace rattle {

using detail::BodySlot;

namespace {

// Sweeps of a solve at most: a part of an island that does not settle in kPartIterations is tried as a
// larger part; an island solved again within a step gets kIslandIterations; the solve at the start of a
// step, which carries a whole step of gravity up a pile (a support passes down a little further with
// each sweep), gets kStartIterations. Under gravity the sweeps are accelerated and stop when close
// enough (sweepIslandAccelerated), and fewer are allowed: a landing pile solved again whole a few dozen
// times in a step made that step's cost, and the overlap the lower limits leave stays far below 1% of a
// radius (bench/README.md, "Piles"). A start solve under gravity that stops short is trimmed as one
// without (trimIsland), which let its sweeps fall from 300: a landing pile's start solves stopped at
// their 300 sweeps and were half of its rows.
constexpr int kPartIterations = 100;
constexpr int kIslandIterations = 300;
constexpr int kStartIterations = 25;
constexpr int kIslandIterationsUnderGravity = 100;
constexpr int kStartIterationsUnderGravity = 100;
// Without gravity the start solve's sweeps are few (kStartIterations), and the bodies whose velocities
// would still close a contact are stopped for the step (trimIsland): a jam of thousands that a game
// drives into a doorway is some 45 layers deep, and its sweeps, which carry a push about a layer each,
// stopped at 1,000 without converging (bench/README.md, "Crowds"). No contact then closes more than
// kTrimSlack of its smaller radius beyond its gap within the step, a quarter of the 1% that a crowd's
// overlap is held to (kJamResidual), which leaves room for the events and solves later in the step.
constexpr double kTrimSlack = 0.0025;
// How many times a solve may gather its contacts again at the speeds it reached (solveIsland).
constexpr int kRegathers = 3;
// A solve gathered again sweeps on for 1 / kCarriedShare of its sweeps: it starts where it stopped, and a
// tenth kept a crowd's squeezed disks apart at about the cost the crowd had before (bench/README.md,
// "Crowds").
constexpr int kCarriedShare = 10;
// How many members ahead the gather asks for a member's pair list (gatherIslandContacts).
constexpr size_t kGatherAhead = 4;
// Parts a settleAround tries, the last the whole island: without gravity hops, 4 x hops, 16 x hops, all.
// A jam of thousands solved again whole for each part that failed spent most of its step there (1,228
// whole solves in the first 30 ticks of rattle-demo --units 5000 --steering naive, two thirds of the
// solves' work); the part sixteen times as deep mostly holds there. Under gravity the deeper part made a
// landing pile slower (rattle-bench's pile of 1,000: 600-713 ms per simulated second against 492), so
// piles go from 4 x hops to the whole island.
constexpr int kSettleAttemptsWithoutGravity = 4;
constexpr int kSettleAttemptsUnderGravity = 3;
// Without gravity the sweeps over-relax (projected SOR): a jam of thousands that a game presses into a
// doorway converges slowly under plain Gauss-Seidel, which carries a push about one layer of bodies a
// sweep. On rattle-soak's crowd of 2,000, when the start solve had 1,000 sweeps and no stops, the worst
// overlap fell from 4.1% of a radius at 1 to 2.0% at 1.5 and 1.4% at 1.8. Under gravity they are
// accelerated instead (sweepIslandAccelerated).
constexpr double kOverRelaxation = 1.8;
// A warm start is at most this many times the island's momentum at the speeds at play
// (solveIslandVelocities): three times what one contact could take to turn every member round, and far
// more than a resting pile's bottom contact carries, so no solve that has an answer is changed.
// Where none has (a crowd that a piston closes on against a wall, several layers deep), the sweeps raise
// the impulses each step, and carried on from one step to the next they doubled every few steps (in a
// crowd of 100 that the game drove into a piston, from 10 to 1e43 in 170 steps), until round-off in the
// velocities threw disks about and a step spent its whole event budget on island solves.
constexpr double kWarmStartMomenta = 6;
// Under gravity the accelerated sweeps (sweepIslandAccelerated) also stop once no contact would end the
// step closer than this fraction of its smaller disk's radius beyond its bound, checked every
// kCloseEnoughInterval sweeps (a check costs about a sweep). Three times larger let a resting pile's
// overlap pass the 1e-4 of a radius that PredictiveGravity.PileInABoxSettlesWithoutSinking holds it to.
constexpr double kCloseEnough = 3e-5;
constexpr int kCloseEnoughInterval = 8;
// The position correction without gravity (separateIsland): its sweeps, and the part of an overlap it
// takes out in one step. The correction moves positions only, so it adds no energy; with too little a
// jam that a step's solve left far from converged keeps a part of what it left, and with all of it
// the sweeps, stopped short, leave a dense crowd more (the overlaps measured at each factor tried are in
// docs/numerics.md).
constexpr int kSeparateIterations = 32;
constexpr double kSeparateFactor = 0.9;
// The rows the position correction sweeps: those whose bound is within this fraction of their smaller
// radius of letting the pair close (separateIsland). On a crowd of 10,000 about half of them.
constexpr double kSeparateReach = 0.01;
// The relative excess of energy a solve may leave (round-off) before its velocities are scaled down.
constexpr double kEnergyRoundOff = 1e-12;

// Every point of a placed geometry that can hold a circle centred at p: its closest point on each
// convex piece (a polyline's segments, a polygon's edges), so a disk in a corner gets both walls. Each
// comes with the normal toward p and p's distance from it.
template <class Found>
void forEachPiece(const Geometry& g, Vec2 position, Vec2 p, Found&& found) {
  const Vec2 q = p - position;
  auto closest = [&](Vec2 local) {
    const Vec2 point = local + position;
    const Vec2 r = p - point;
    const double distance = length(r);
    if (distance > 0) found(point, r * (1.0 / distance), distance);
  };
  // The closest point of the segment a-b. Inside it, the normal is the line's: from a distance far
  // below the coordinates (a disk of radius 1e-12 at y = 6), r / |r| carries the coordinates' round-off
  // as a tilt (4e-4 rad there), and a disk sliding along a floor sank through a tilted contact that the
  // solve took as met (fuzz/regressions/world_api/inside-hybrid-tiny-disk-on-a-polygon-floor). The
  // line's normal is used only there, so that other contacts keep their bits.
  auto onSegment = [&](Vec2 a, Vec2 b, bool endsCollide) {
    const detail::Closest c = detail::closestOnSegment(a, b, q, endsCollide);
    if (!c.collidable) return;
    const Vec2 r = q - c.point;
    const double near = 1e-6 * std::max({1.0, std::fabs(p.x), std::fabs(p.y)});
    const bool inner = !(c.point.x == a.x && c.point.y == a.y) && !(c.point.x == b.x && c.point.y == b.y);
    if (inner && dot(r, r) < near * near) {  // no square root for the far pieces, nearly all of them
      const Vec2 d = b - a;
      const Vec2 left = Vec2{-d.y, d.x} * (1.0 / length(d));
      const double side = dot(left, q - a);
      if (side == 0) return;
      const Vec2 normal = side > 0 ? left : -left;
      found(p - normal * std::fabs(side), normal, std::fabs(side));
      return;
    }
    closest(c.point);
  };
  if (const auto* s = std::get_if<Point>(&g)) {
    closest(s->position);
  } else if (const auto* s = std::get_if<Circle>(&g)) {
    const Vec2 r = q - s->center;
    const double len = length(r);
    if (len > 0) closest(s->center + r * (s->radius / len));
  } else if (const auto* s = std::get_if<Segment>(&g)) {
    // A bare segment's ends are not corners (README, Geometry): they hold nothing.
    onSegment(s->a, s->b, false);
  } else if (const auto* s = std::get_if<Polyline>(&g)) {
    for (size_t i = 0; i + 1 < s->points.size(); ++i) {
      onSegment(s->points[i], s->points[i + 1], true);
    }
  } else if (const auto* s = std::get_if<Polygon>(&g)) {
    // A centre inside the polygon has no side to be held to (as closestPoint says).
    const size_t n = s->points.size();
    bool inside = true;
    for (size_t i = 0; i < n && inside; ++i) inside = !(cross(s->points[(i + 1) % n] - s->points[i], q - s->points[i]) < 0);
    if (inside) return;
    for (size_t i = 0; i < n; ++i) onSegment(s->points[i], s->points[(i + 1) % n], true);
  }
}

// One sweep of projected Gauss-Seidel over the rows, on the members' values x (velocities in the solve,
// displacements in separateIsland): each row's multiplier stays >= 0 while its relative normal value
// (a's minus b's) is pushed up to its target, in the metric of the masses. x holds the `members` first,
// then one slot for each row whose b is held fixed (its value, never written: scheduleSweeps), so that a
// row reads b's value without a branch and carries no copy of it. stepOf(at, row, gap) is the change of
// the row's multiplier asked for its gap to the target before the projection: omega * gap / (inverseA +
// inverseB), over-relaxed by omega. Returns the largest change of a relative value, and adds the sum of
// the squared changes of the multipliers (in the rows' order) to *squaredChanges where it is given.
template <typename StepOf>
double projectedSweep(std::vector<detail::Islands::SweepRow>& rows, std::vector<Vec2>& x, size_t members,
                      StepOf stepOf, double* squaredChanges = nullptr) {
  double worst = 0, squares = 0;
  for (size_t at = 0; at < rows.size(); ++at) {
    detail::Islands::SweepRow& r = rows[at];
    const Vec2 xb = x[r.kb];  // a holder's value sits past the members' (scheduleSweeps)
    const double value = dot(x[r.ka] - xb, r.normal);
    const double next = std::max(0.0, r.lambda + stepOf(at, r, r.target - value));
    const double change = next - r.lambda;
    if (change == 0) continue;
    r.lambda = next;
    x[r.ka] += r.normal * (change * r.inverseA);
    if (static_cast<size_t>(r.kb) < members) x[r.kb] -= r.normal * (change * r.inverseB);
    worst = std::max(worst, std::fabs(change) * (r.inverseA + r.inverseB));
    if (squaredChanges) squares += change * change;
  }
  if (squaredChanges) *squaredChanges += squares;
  return worst;
}

// Plain projected Gauss-Seidel: the step divides by the row's inverse mass sum.
double projectedSweep(std::vector<detail::Islands::SweepRow>& rows, std::vector<Vec2>& x, size_t members,
                      double* squaredChanges = nullptr) {
  return projectedSweep(
      rows, x, members,
      [](size_t, const detail::Islands::SweepRow& r, double gap) { return gap / (r.inverseA + r.inverseB); },
      squaredChanges);
}

}  // namespace

void detail::Islands::islandOf(std::span<const uint32_t> seeds, int hops, std::vector<uint32_t>& members) {
  // Stepped bodies reached from the seeds through candidate pairs, breadth first (so in a deterministic
  // order, seeds first): with hops < 0 everything a change of their motion can push within the step.
  std::vector<int>& slot = jamSlot;
  if (slot.size() < w.bodies.size()) slot.resize(w.bodies.size(), -1);
  members.clear();
  for (uint32_t i : seeds) {
    if (slot[i] >= 0 || !w.bodies[i].stepped) continue;
    slot[i] = 0;
    members.push_back(i);
  }
  for (size_t k = 0, layerEnd = members.size(), depth = 0; k < members.size(); ++k) {
    if (k == layerEnd) {
      ++depth;
      layerEnd = members.size();
    }
    if (hops >= 0 && depth >= static_cast<size_t>(hops)) break;
    for (const auto& pair : w.pairsOfBody[members[k]]) {
      const uint32_t j = w.fixtures[pair.other].body;
      if (slot[j] >= 0 || !w.bodies[j].stepped || w.fixtures[pair.other].sensor) continue;
      slot[j] = 0;
      members.push_back(j);
    }
  }
  for (uint32_t i : members) slot[i] = -1;
}

int detail::Islands::settleAround(std::span<const uint32_t> seeds, int hops, double now, double dt,
                                     uint64_t reportPair) {
  // The seeds and the stepped bodies within `hops` candidate pairs of them move; the rest of the island
  // keeps its paths. That part's edge may push it like a moving wall (a stepped body coming at it) and
  // so add energy that the whole island would not (it would slow the pusher), or ask the impossible of a
  // body caught between two such paths. Then the solve is undone and tried again on a part four times
  // as deep (without gravity, again), and at last on the whole island, which holds no moving walls but
  // kinematic ones.
  if (settleScratch.size() <= settleDepth) settleScratch.resize(settleDepth + 1);
  SettleScratch& scratch = settleScratch[settleDepth];
  std::vector<uint32_t>& members = scratch.members;
  std::vector<Vec2>& before = scratch.before;
  std::vector<uint32_t>& counts = scratch.counts;
  std::vector<detail::LastContact>& lasts = scratch.lasts;
  std::vector<double>& allowances = scratch.allowances;
  IslandSolve solve{0, false};
  const int attempts = w.def.gravity == Vec2{} ? kSettleAttemptsWithoutGravity : kSettleAttemptsUnderGravity;
  for (int attempt = 0, depth = hops; attempt < attempts; ++attempt, depth *= 4) {
    const bool whole = attempt == attempts - 1;
    islandOf(seeds, whole ? -1 : depth, members);
    before.resize(members.size());
    counts.resize(members.size());
    lasts.resize(members.size());
    allowances.resize(members.size());
    // The members' energy at the step's end along their straight paths, less what does not change (the
    // potential energy where they are now): twice sum m (|v|^2 / 2 - h g.v). Kinetic energy alone misses
    // a fall turned into a rise by a holder moving up (a neighbour that bounces): the same speed, higher.
    const double h = dt - now;
    auto endEnergy = [&](Vec2 v, double mass) { return mass * (dot(v, v) - 2 * h * dot(w.def.gravity, v)); };
    double energy = 0, scale = 0;
    for (size_t k = 0; k < members.size(); ++k) {
      const BodySlot& b = w.bodies[members[k]];
      before[k] = b.velocity;
      counts[k] = b.collisionCount;
      lasts[k] = b.last;
      allowances[k] = gravityAllowance[members[k]];
      energy += endEnergy(b.velocity, b.mass);
      scale += b.mass * (dot(b.velocity, b.velocity) + 2 * h * std::fabs(dot(w.def.gravity, b.velocity)));
    }
    const size_t mark = w.contactEvents.size();
    solve = solveIsland(members, now, dt, std::numeric_limits<double>::infinity(), reportPair, false, whole);
    double after = 0;
    for (uint32_t i : members) after += endEnergy(w.bodies[i].velocity, w.bodies[i].mass);
    if (whole || (solve.met && after <= energy + 1e-12 * scale)) break;
    // Undone entirely: the predictions made before it are still good.
    for (size_t k = 0; k < members.size(); ++k) {
      BodySlot& b = w.bodies[members[k]];
      b.velocity = before[k];
      b.collisionCount = counts[k];
      b.setLast(lasts[k]);
      gravityAllowance[members[k]] = allowances[k];
    }
    w.contactEvents.resize(mark);
  }
  // The seeds come first in every list; they changed whatever the solve did.
  const size_t seedCount = std::min(seeds.size(), members.size());
  for (size_t k = 0; k < members.size(); ++k) {
    BodySlot& b = w.bodies[members[k]];
    const bool same = b.velocity.x == before[k].x && b.velocity.y == before[k].y && b.collisionCount == counts[k];
    if (k >= seedCount && same) continue;
    predictor->motionChanged(members[k], now, dt);
  }
  ++settleDepth;
  settleUnsolvedIslandPairs(now, dt);
  --settleDepth;
  return solve.reported;
}

void detail::Islands::settleUnsolvedIslandPairs(double now, double dt) {
  // A solve can send a body beyond the box the sweep saw: asking the broad phase again (repredict) may
  // then find contacts an island holds that no solve has seen, which are solved in turn. Each round moves
  // bodies less; a few rounds at most (the boxes were made with room to spare).
  if (settlingUnsolved) return;
  settlingUnsolved = true;
  for (int round = 0; round < 4 && !unsolvedIslandPairs.empty(); ++round) {
    // Swapped with a kept list, so that both keep their room from one round (and step) to the next.
    std::vector<uint32_t>& seeds = unsolvedSeeds;
    seeds.clear();
    seeds.swap(unsolvedIslandPairs);
    std::sort(seeds.begin(), seeds.end());
    seeds.erase(std::unique(seeds.begin(), seeds.end()), seeds.end());
    settleAround(seeds, 1, now, dt);
  }
  unsolvedIslandPairs.clear();
  settlingUnsolved = false;
}

void detail::Islands::joinIslands(std::span<const uint32_t> joining, double now, double dt) {
  if (gravityAllowance.size() < w.bodies.size()) gravityAllowance.resize(w.bodies.size(), 0.0);
  for (uint32_t i : joining) {
    BodySlot& b = w.bodies[i];
    if (b.stepped) continue;
    w.advance(b, now);
    // The rest of the step's gravity at once, then a straight path (see above).
    b.velocity += w.def.gravity * (dt - now);
    b.acceleration = {};
    b.clearSupport();
    b.stepped = true;
    b.steppedSinceStart = false;
    gravityAllowance[i] = 0.5 * b.mass * dot(w.def.gravity, w.def.gravity) * (dt - now) * (dt - now);
  }
}

// The members' contacts with one another and with what holds them (static, kinematic, sleeping and
// stepped non-member bodies) within reach of the rest of the step, into islandScratch, with their clocks
// moved to `now`. Returns the fastest speed at play (at least restingSpeed), which sets every member's
// reach, or reachSpeeds (by member) when given: the speeds a solve reached, which do not set its
// tolerance (a part squeezed between moving holders can reach 1e11 units/s, and its solve is then
// undone, not loosened).
double detail::Islands::gatherIslandContacts(const std::vector<uint32_t>& members, double now, double h,
                                             std::span<const double> reachSpeeds) {
  std::vector<int>& slot = jamSlot;  // body -> index into members; -1 outside (reset on the way out)
  if (slot.size() < w.bodies.size()) slot.resize(w.bodies.size(), -1);
  for (size_t k = 0; k < members.size(); ++k) slot[members[k]] = static_cast<int>(k);
  // Their velocities change at `now`: their clocks move there first.
  for (uint32_t i : members) w.advance(w.bodies[i], now);
  std::vector<IslandContact>& contacts = islandScratch;
  contacts.clear();
  islandKinematicHolder = false;
  islandSegmentMembers.clear();
  double speed = w.def.restingSpeed;
  for (uint32_t i : members) speed = std::max(speed, length(w.bodies[i].velocity));
  const auto reachSpeed = [&](size_t k) { return reachSpeeds.empty() ? speed : reachSpeeds[k]; };
  for (size_t k = 0; k < members.size(); ++k) {
    const uint32_t i = members[k];
    const BodySlot& body = w.bodies[i];
    // A member's pair list lies apart from its slot and from the last member's: asked for ahead (its
    // header, then its entries) so that the walk does not wait on it.
    if (k + 2 * kGatherAhead < members.size()) __builtin_prefetch(&w.pairsOfBody[members[k + 2 * kGatherAhead]]);
    if (k + kGatherAhead < members.size()) {
      const std::vector<detail::CandidatePair>& ahead = w.pairsOfBody[members[k + kGatherAhead]];
      if (!ahead.empty()) __builtin_prefetch(ahead.data());
    }
    for (const auto& pair : w.pairsOfBody[i]) {
      const detail::FixtureSlot& own = w.fixtures[pair.own];
      const detail::FixtureSlot& other = w.fixtures[pair.other];
      if (own.sensor || other.sensor) continue;
      const uint32_t j = other.body;
      const BodySlot& holder = w.bodies[j];
      if (holder.type == BodyType::Static && std::holds_alternative<Segment>(other.geometry) &&
          (islandSegmentMembers.empty() || islandSegmentMembers.back() != k))
        islandSegmentMembers.push_back(static_cast<uint32_t>(k));
      // A kinematic body passing over a squeezed member holds it no more (squeeze.cpp).
      if (holder.type == BodyType::Kinematic && !w.squeezes.empty() && squeezeExempt(w, pair.own, pair.other)) continue;
      const Vec2 centre = w.positionAt(body, now) + detail::circleCentre(own.geometry);
      const double radius = detail::circleRadius(own.geometry);
      const Vec2 holderPosition = w.positionAt(holder, now);
      // Without gravity, a pair of dynamic bodies passing through each other is no contact; nor, with or
      // without gravity, is one made overlapping (squeeze.cpp): each step's start parts it
      // (separation.cpp). Units spawned onto a queue were held on one another by the jam's solve, their
      // overlap never parted.
      if (holder.type == BodyType::Dynamic) {
        if (w.def.gravity == Vec2{} && !w.squeezes.empty() && squeezeExempt(w, pair.own, pair.other)) continue;
        // Made overlapping is tested on squares first, as nearly no pair is: a pile's gather meets every
        // pair of neighbours, where a square root and a call for each showed in the step's time
        // (bench/README.md). The 1e-9 keeps every pair the exact test could take.
        const double otherRadius = detail::circleRadius(other.geometry);
        const double within = radius + otherRadius - kMadeOverlapping * std::max(radius, otherRadius);
        const Vec2 d = holderPosition + detail::circleCentre(other.geometry) - centre;
        if (within > 0 && dot(d, d) < within * within * (1 + 1e-9) &&
            exemptIfMadeOverlapping(w, pair.own, pair.other, now))
          continue;
      }
      const int kj = slot[j];
      if (kj >= 0 && kj <= static_cast<int>(k)) continue;  // a pair of members: once, from the lower
      // A free body's meetings with the island are events.
      if (kj < 0 && holder.type == BodyType::Dynamic && !holder.asleep && !holder.stepped) continue;
      const Vec2 holderVelocity = kj >= 0 ? Vec2{} : w.velocityAt(holder, now);
      forEachPiece(other.geometry, holderPosition, centre, [&](Vec2 point, Vec2 normal, double distance) {
        const double gap = distance - radius;
        // Out of reach within the step even at twice the speeds at play (each member's, the holder's) and
        // what gravity adds.
        const double reach = (kj >= 0 ? 2 * (reachSpeed(k) + reachSpeed(static_cast<size_t>(kj)))
                                      : 4 * (reachSpeed(k) + length(holderVelocity))) *
                                 h +
                             length(w.def.gravity) * h * h;
        if (gap > reach + 1e-9 * std::max(radius, 1.0)) return;
        IslandContact c;
        c.a = i;
        c.b = j;
        c.fa = pair.own;
        c.fb = pair.other;
        c.ka = static_cast<int>(k);
        c.kb = kj;
        c.normal = normal;
        c.point = point;
        c.holderVelocity = holderVelocity;
        c.inverseA = body.inverseMass;
        c.inverseB = kj >= 0 ? holder.inverseMass : 0.0;
        c.target = gap > 0 ? (h > 0 ? -gap / h : -std::numeric_limits<double>::infinity()) : 0.0;
        c.gap = gap;
        c.radius = kj >= 0 ? std::min(radius, detail::circleRadius(other.geometry)) : radius;
        contacts.push_back(c);
        islandKinematicHolder = islandKinematicHolder || (kj < 0 && holder.type == BodyType::Kinematic);
      });
    }
  }
  for (uint32_t i : members) slot[i] = -1;
  return speed;
}

bool detail::Islands::holdSegmentCrossings(const std::vector<uint32_t>& members, const std::vector<Vec2>& v,
                                           double now, double h) {
  // A bare Segment's ends hold nothing (forEachPiece), so a member beside one, past the Segment's end, has
  // no contact with it, and its straight path for the rest of the step may still cross the Segment's
  // face: a disk at the joint of two Segments of a closed container, stepped through a step of 0.1 s down
  // one into the other, left the container. Such a crossing, found by the member's exact time of impact
  // along its solved path, is held from now on as a contact with the face it meets (its plane, at the
  // gap the member has from it now), and the solve sweeps on. Only static Segments: every other geometry's
  // pieces hold all of it. Returns whether it added a contact.
  // Only the members the gather saw with a pair with a static Segment (islandSegmentMembers): reading
  // every pair of every member again was 2% of rattle-bench's pile.
  if (islandSegmentMembers.empty()) return false;
  std::vector<IslandContact>& contacts = islandScratch;
  // The (member fixture, Segment) pairs the gather holds, sorted; listed only once a path reaches a
  // Segment, as most solves have none near.
  std::vector<std::pair<uint32_t, uint32_t>>& held = islandHeldSegments;
  bool listed = false;
  bool added = false;
  for (const uint32_t k : islandSegmentMembers) {
    const uint32_t i = members[k];
    const BodySlot& body = w.bodies[i];
    const Vec2 position = w.positionAt(body, now);
    const Box path = pathBox(position, v[k], Vec2{}, h);
    for (const auto& pair : w.pairsOfBody[i]) {
      const detail::FixtureSlot& own = w.fixtures[pair.own];
      const detail::FixtureSlot& other = w.fixtures[pair.other];
      if (own.sensor || other.sensor || !std::holds_alternative<Segment>(other.geometry)) continue;
      const BodySlot& holder = w.bodies[other.body];
      if (holder.type != BodyType::Static) continue;
      // Most paths end far from the Segment: their swept box says so without a time of impact.
      const Box swept{path.min + own.localBox.min, path.max + own.localBox.max};
      if (!swept.overlaps(withRoundOff(w.worldBox(pair.other)))) continue;
      if (!listed) {
        held.clear();
        for (const IslandContact& c : contacts) {
          if (c.kb < 0 && std::holds_alternative<Segment>(w.fixtures[c.fb].geometry)) held.emplace_back(c.fa, c.fb);
        }
        std::sort(held.begin(), held.end());
        listed = true;
      }
      const std::pair<uint32_t, uint32_t> key{pair.own, pair.other};
      if (std::binary_search(held.begin(), held.end(), key)) continue;
      const auto impact = detail::fixtureTimeOfImpact(w, pair.own, position, pair.other, holder.position,
                                                      Motion{v[k]}, h, kNoFeature);
      if (!impact) continue;
      const Vec2 centre = position + detail::circleCentre(own.geometry);
      const double radius = detail::circleRadius(own.geometry);
      IslandContact c;
      c.a = i;
      c.b = other.body;
      c.fa = pair.own;
      c.fb = pair.other;
      c.ka = static_cast<int>(k);
      c.kb = -1;
      c.normal = impact->normal;
      c.point = impact->point;
      c.holderVelocity = Vec2{};
      c.inverseA = body.inverseMass;
      c.inverseB = 0.0;
      c.gap = dot(centre - impact->point, impact->normal) - radius;
      c.target = c.gap > 0 && h > 0 ? -c.gap / h : 0.0;
      c.radius = radius;
      contacts.push_back(c);
      held.insert(std::upper_bound(held.begin(), held.end(), key), key);  // once a solve
      added = true;
    }
  }
  return added;
}

void detail::Islands::keepIslandEnergy(const std::vector<uint32_t>& members, std::vector<Vec2>& v, double h,
                                         bool start) {
  // Energy never rises, by construction rather than by convergence. After the solve each member moves
  // along v for the rest of the step, h. Projecting never adds kinetic energy, but under gravity it can
  // turn a fall into a rise: a wedge (a disk on two that part) lifts the disk on top, and along a straight
  // path that lift costs nothing. Over-relaxed sweeps that stop short, or a warm start they stop short of
  // undoing (fuzz/regressions/world_api/energy-hybrid-gravity-resting-row), can do the same. Scaling every
  // velocity by s in [0, 1] keeps every contact met against holders at rest (every target is <= 0), and
  // the energy at the step's end is then a s^2 + b s + c above what the members were to have at the end
  // of the paths they were on, plus what is left of their gravity allowance: the largest s that does not
  // gain is taken.
  //
  // The allowance: a straight path that takes the rest of the step's gravity H at once ends lower than
  // the parabola it stands in for, by g H^2 / 2, with the same velocity, so m g^2 H^2 / 2 less energy.
  // Each stepped body is granted that when its straight path begins (startIslands, joinIslands), and the
  // solves that hold it may spend it, once. Granted again at every solve, a pair that joined a moment
  // after its island began gained 2.6e-2 (fuzz/regressions/world_api/energy-predictive-join-in-a-step).
  //
  // A member that no contact pushed in the step's first solve is freed after it (startIslands): back on
  // its parabola, it regains its whole allowance, whatever its velocity. So that solve may spend only
  // what the held members were granted; spending the freed ones' too, a solve lifted two disks of a
  // settling pile with the allowance of a third that then fell freely
  // (fuzz/regressions/world_api/energy-hybrid-small-pile-in-a-box).
  // Against moving holders (a kinematic body) the energy is not the island's to keep.
  const std::vector<IslandContact>& contacts = islandScratch;
  bool holdersStill = true;
  for (const IslandContact& c : contacts) holdersStill = holdersStill && (c.kb >= 0 || c.holderVelocity == Vec2{});
  if (!holdersStill) return;
  std::vector<char>& held = islandMemberHeld;
  held.assign(members.size(), start ? 0 : 1);
  for (const IslandContact& c : contacts) {
    if (!start || !(c.lambda > 0)) continue;
    held[c.ka] = 1;
    if (c.kb >= 0) held[c.kb] = 1;
  }
  double a = 0, b = 0, planned = 0, allowance = 0;
  for (size_t k = 0; k < members.size(); ++k) {
    const BodySlot& body = w.bodies[members[k]];
    a += 0.5 * body.mass * dot(v[k], v[k]);
    b -= h * body.mass * dot(w.def.gravity, v[k]);
    planned += 0.5 * body.mass * dot(body.velocity, body.velocity) - h * body.mass * dot(w.def.gravity, body.velocity);
    if (held[k]) allowance += gravityAllowance[members[k]];
  }
  const double c = -(planned + allowance);
  double scale = 1;
  // A body sliding on a floor keeps its energy to round-off, which is not scaled away step after step.
  // (a = 0: every velocity is zero already, and no scale changes the energy.)
  if (a > 0 && a + b + c > kEnergyRoundOff * (a + std::fabs(b) + std::fabs(c))) {
    // The larger root of a s^2 + b s + c, below 1 (the energy at s = 1 is above); >= 0 when c <= 0. A
    // path that was to sink slowly ends below where the body is now (c > 0), and stopping it gains: then
    // the s of least energy, if no s in [0, 1] loses.
    const double discriminant = b * b - 4 * a * c;
    if (discriminant >= 0) {
      const double root = std::sqrt(discriminant);
      scale = b > 0 ? -2 * c / (b + root) : (root - b) / (2 * a);
    } else {
      scale = -b / (2 * a);
    }
    scale = std::clamp(scale, 0.0, 1.0);
    for (Vec2& velocity : v) velocity = velocity * scale;
  }
  // What the solve spent of the allowance is gone, from every member in proportion.
  const double spent = std::clamp(a * scale * scale + b * scale - planned, 0.0, allowance);
  if (spent > 0) {
    const double left = (allowance - spent) / allowance;
    for (size_t k = 0; k < members.size(); ++k)
      if (held[k]) gravityAllowance[members[k]] *= left;
  }
}

void detail::Islands::markHeld() {
  for (const IslandContact& c : islandScratch) {
    if (!(c.lambda > 0)) continue;
    steppedHeld[c.a] = 1;
    if (c.kb >= 0) steppedHeld[c.b] = 1;
  }
}

// Reports as collisions the contacts that closed faster than reportAbove (and reportPair's), at most
// maxReports. Returns how many it reported.
int detail::Islands::reportIslandContacts(double now, double reportAbove, uint64_t reportPair, int maxReports) {
  const std::vector<IslandContact>& contacts = islandScratch;
  int reported = 0;
  for (const IslandContact& c : contacts) {
    if (!(c.lambda > 0)) continue;
    if (!(c.approach > reportAbove) && islandKey(c.fa, c.fb) != reportPair) continue;
    if (reported >= maxReports) continue;
    ++reported;
    w.contactEvents.push_back(contactEventOf(w, c.fa, c.fb, now, c.point, c.normal, c.lambda));
  }
  return reported;
}

bool detail::Islands::carryImpulses(const std::vector<IslandContact>& before, std::vector<IslandContact>& after) {
  size_t next = 0;
  for (IslandContact& c : after) {
    if (next == before.size()) break;
    const IslandContact& b = before[next];
    if (b.fa != c.fa || b.fb != c.fb || !(b.normal == c.normal) || !(b.point == c.point)) continue;
    c.lambda = b.lambda;
    ++next;
  }
  if (next == before.size()) return true;
  for (IslandContact& c : after) c.lambda = 0;
  return false;
}

bool detail::Islands::solveIslandVelocities(const std::vector<uint32_t>& members, std::vector<Vec2>& v, double speed,
                                            double h, bool warmStart, bool whole, bool carried) {
  std::vector<IslandContact>& contacts = islandScratch;
  if (!carried) {
    v.resize(members.size());
    for (size_t k = 0; k < members.size(); ++k) v[k] = w.bodies[members[k]].velocity;
  }
  // The approach of each contact before the solve, for what is reported as a collision.
  for (IslandContact& c : contacts) {
    const Vec2 va = w.bodies[c.a].velocity;
    const Vec2 vb = c.kb >= 0 ? w.bodies[c.b].velocity : c.holderVelocity;
    c.approach = -dot(va - vb, c.normal);
  }
  // Converged when no impulse changes a velocity by more than 1e-6 of the speeds at play (the bodies'
  // and what the step's gravity adds): a contact then closes by at most that much too fast.
  const double tolerance = 1e-6 * (speed + length(w.def.gravity) * h);
  const bool noGravity = w.def.gravity.x == 0 && w.def.gravity.y == 0;
  // A few bodies are projected exactly (exact_projection.h). Under gravity always: the sweeps stop within
  // their tolerance of the answer, and from a warm start that can leave a resting stack rising off the
  // floor by that much a step (fuzz/regressions/world_api/energy-predictive-gravity-stack-rises); and a
  // landing pile's many small parts (settleAround) settle at once instead of failing over to larger
  // ones. Without gravity when the sweeps do not settle (up to kExactProjectionMembersWithoutGravity):
  // where masses differ a lot (a light disk between a wall and a heavy disk) they take tens of thousands.
  const bool small = members.size() <= detail::kExactProjectionMembers;
  bool converged = small && !noGravity && projectIslandExactly(members, v, tolerance);
  // Warm start: the impulse the same contact took in the solve at the start of the last step
  // (islandImpulses, sorted by key), applied before the sweeps so that a resting pile starts where it
  // left off (Catto 2005). Only at the start of a step: later the velocities hold this step's impulses.
  // An exact projection needs none.
  double warmStartBound = 0;
  if (warmStart && !carried && !converged && !islandImpulses.empty()) {
    double holderSpeed = 0, mass = 0;
    for (const IslandContact& c : contacts) {
      if (c.kb < 0) holderSpeed = std::max(holderSpeed, length(c.holderVelocity));
    }
    for (uint32_t i : members) mass += w.bodies[i].mass;
    warmStartBound = kWarmStartMomenta * mass * (speed + holderSpeed + length(w.def.gravity) * h);
  }
  for (IslandContact& c : contacts) {
    if (!warmStart || carried || converged) break;
    const uint64_t key = islandKey(c.fa, c.fb);
    auto it = std::lower_bound(islandImpulses.begin(), islandImpulses.end(), key,
                               [](const std::pair<uint64_t, double>& e, uint64_t k) { return e.first < k; });
    if (it == islandImpulses.end() || it->first != key) continue;
    c.lambda = std::min(it->second, warmStartBound);
    v[c.ka] += c.normal * (c.lambda * c.inverseA);
    if (c.kb >= 0) v[c.kb] -= c.normal * (c.lambda * c.inverseB);
  }
  const int fullIterations = noGravity ? (warmStart ? kStartIterations : whole ? kIslandIterations : kPartIterations)
                                       : (warmStart ? kStartIterationsUnderGravity
                                                    : whole ? kIslandIterationsUnderGravity : kPartIterations);
  const int maxIterations = carried ? fullIterations / kCarriedShare : fullIterations;
  bool closeEnough = false;
  if (!converged && noGravity) {
    converged = sweepIsland(v, kOverRelaxation, tolerance, maxIterations);
  } else if (!converged) {
    const SweepEnd end = sweepIslandAccelerated(v, tolerance, h, maxIterations);
    converged = end == SweepEnd::Converged;
    closeEnough = end == SweepEnd::CloseEnough;
  }
  // Not where a kinematic body holds a member: closing on it against a static body (a piston pressing a
  // crowd into a wall) it leaves no velocity that meets every contact, and the projection spent its
  // whole allowance of passes finding that out, in every solve of the step (half a second a step for a
  // crowd of 70). The sweeps and the holders' sweeps below settle it (the kinematic body passes over).
  if (!converged && noGravity && !islandKinematicHolder &&
      members.size() <= detail::kExactProjectionMembersWithoutGravity) {
    converged = projectIslandExactly(members, v, tolerance);
  }

  // What cannot move (a wall, a floor, a sleeping body) is kept out exactly, not within the tolerance:
  // a few more sweeps over those contacts alone, each a projection that lowers the kinetic energy. A
  // kinematic body is such a holder too, but where it closes on a member against a static body no
  // velocity meets both, and the one swept last won: a piston pushed disks of a crowd into the wall
  // behind them (README, "Squeezes": never through a static body). So the bodies that never move get
  // the last sweeps, and the kinematic body passes over the member instead (a squeeze).
  auto sweepHolders = [&](bool kinematicToo) {
    for (int sweep = 0; sweep < 16; ++sweep) {
      bool changed = false;
      for (IslandContact& c : contacts) {
        if (c.kb >= 0) continue;
        if (!kinematicToo && w.bodies[c.b].type == BodyType::Kinematic) continue;
        const double vn = dot(v[c.ka] - c.holderVelocity, c.normal);
        if (!(vn < c.target)) continue;
        const double change = (c.target - vn) / c.inverseA;
        c.lambda += change;
        v[c.ka] += c.normal * (change * c.inverseA);
        changed = true;
      }
      if (!changed) return;
    }
  };
  sweepHolders(true);
  if (islandKinematicHolder) sweepHolders(false);
  return converged || closeEnough;
}

detail::Islands::IslandSolve detail::Islands::solveIsland(const std::vector<uint32_t>& members, double now,
                                                                double dt, double reportAbove, uint64_t reportPair,
                                                                bool warmStart, bool whole, int maxReports) {
  const double h = dt - now;
  double speed = gatherIslandContacts(members, now, h);
  std::vector<Vec2>& v = islandVelocities;
  bool converged = solveIslandVelocities(members, v, speed, h, warmStart, whole);
  if (!converged && islandKinematicHolder && passKinematicOverPushed()) {
    speed = gatherIslandContacts(members, now, h);
    converged = solveIslandVelocities(members, v, speed, h, warmStart, whole);
  }
  // The gather kept the contacts within reach of the speeds before the solve. A squeeze can send members
  // off far faster (at a crowd's doorway mouth, 13 units/s out of 3) toward members whose contact it left
  // out, and two members of one island meet in no event: they would pass into each other unseen until
  // the next step (bench/README.md, "Crowds"). A solve whose members outran their reach gathers again,
  // each member's reach set by the speed it reached, and sweeps on from where it stopped: the contacts
  // it had keep their impulses (a wider reach gathers the same contacts in the same order, and more),
  // the new ones start at none.
  std::vector<double>& reached = islandReachSpeeds;
  reached.clear();
  for (int again = 0; again < kRegathers; ++again) {
    bool outran = false;
    for (size_t k = 0; k < v.size(); ++k) outran = outran || length(v[k]) > 2 * (reached.empty() ? speed : reached[k]);
    if (!outran) break;
    reached.resize(v.size(), speed);
    for (size_t k = 0; k < v.size(); ++k) reached[k] = std::max(reached[k], length(v[k]));
    islandScratchBefore.swap(islandScratch);
    speed = gatherIslandContacts(members, now, h, reached);
    const bool carried = carryImpulses(islandScratchBefore, islandScratch);
    converged = solveIslandVelocities(members, v, speed, h, warmStart, whole, carried);
  }
  for (int again = 0; again < kRegathers && holdSegmentCrossings(members, v, now, h); ++again) {
    converged = solveIslandVelocities(members, v, speed, h, warmStart, whole, true);
  }
  const std::vector<IslandContact>& contacts = islandScratch;
  const bool noGravity = w.def.gravity.x == 0 && w.def.gravity.y == 0;
  keepIslandEnergy(members, v, h, warmStart);
  markHeld();
  // At a step's start: what the sweeps left unmet is taken out of the velocities (trimIsland; under
  // gravity only from members a contact pushes: the others are freed onto their parabolas after the
  // solve, startIslands, and what they close is met as events), and then, without gravity, the overlap
  // left from before out of the positions (separateIsland, which keeps every contact open along the
  // trimmed velocities). In the other order the separation was asked to open what the trim then took out
  // anyway, and its sweeps, short of that, pushed other pairs together.
  if (warmStart && h > 0) {
    if (!converged) trimIsland(members, v, h);
    if (noGravity) separateIsland(members, v, h);
  }
  for (size_t k = 0; k < members.size(); ++k) {
    BodySlot& b = w.bodies[members[k]];
    if (v[k].x == b.velocity.x && v[k].y == b.velocity.y) continue;
    b.velocity = v[k];
    ++b.collisionCount;
    // Whatever it was last resolved against, it may now approach again (see LastContact).
    b.last = detail::LastContact{};
  }
  const int reported = reportIslandContacts(now, reportAbove, reportPair, maxReports);
  // Met when the sweeps converged, or when no contact closes faster than its target by more than 1e-4 of
  // the speeds at play (a large island converges slowly, and that is close enough).
  double violation = 0;
  for (const IslandContact& c : contacts) {
    const Vec2 vb = c.kb >= 0 ? w.bodies[c.b].velocity : c.holderVelocity;
    violation = std::max(violation, c.target - dot(w.bodies[c.a].velocity - vb, c.normal));
  }
  return {reported, converged || violation <= 1e-4 * (speed + length(w.def.gravity) * h)};
}

bool detail::Islands::passKinematicOverPushed() {
  // Under gravity a solve is often unmet while a pile lands, and a kinematic platform carrying the pile
  // must not let it fall through: there a body caught against a kinematic one is squeezed alone, after
  // its count of collisions (squeezeAt).
  if (w.def.gravity.x != 0 || w.def.gravity.y != 0) return false;
  bool passed = false;
  for (const IslandContact& c : islandScratch) {
    if (c.kb >= 0 || !(c.lambda > 0) || w.bodies[c.b].type != BodyType::Kinematic) continue;
    if (squeezeExempt(w, c.fa, c.fb)) continue;  // two pieces of one pair of fixtures
    exemptFromCollisions(w, c.fa, c.fb);
    passed = true;
  }
  return passed;
}

void detail::Islands::scheduleSweeps(size_t memberCount) {
  // A sweep is a chain of dependent arithmetic: each contact reads the velocities the one before it may
  // have just written, and in the contacts' own order (member by member) it usually has. On a crowd's
  // island of thousands of contacts the processor then waits on each contact's division in turn. Two
  // contacts that share no member commute exactly (each reads and writes only its own members and
  // impulse), so any order that keeps, for every member, the order of the contacts that touch it gives
  // the same bits. The wavefront order does: a contact's level is one more than the level of the last
  // contact before it that shares a member, and the sweeps run level by level, in the contacts' order
  // within a level. The contacts of one level are independent, so their arithmetic overlaps
  // (bench/README.md, "Crowds").
  const std::vector<IslandContact>& contacts = islandScratch;
  SweepSchedule& s = sweepSchedule;
  const size_t n = contacts.size();
  s.level.resize(n);
  s.next.assign(memberCount, 0);
  uint32_t levels = 0;
  for (size_t i = 0; i < n; ++i) {
    const IslandContact& c = contacts[i];
    uint32_t level = s.next[static_cast<size_t>(c.ka)];
    if (c.kb >= 0) level = std::max(level, s.next[static_cast<size_t>(c.kb)]);
    s.level[i] = level;
    s.next[static_cast<size_t>(c.ka)] = level + 1;
    if (c.kb >= 0) s.next[static_cast<size_t>(c.kb)] = level + 1;
    levels = std::max(levels, level + 1);
  }
  // A counting sort by level, stable within a level; `next` becomes each level's first position.
  s.next.assign(levels + 1, 0);
  for (size_t i = 0; i < n; ++i) ++s.next[s.level[i] + 1];
  for (uint32_t l = 0; l < levels; ++l) s.next[l + 1] += s.next[l];
  s.rows.resize(n);
  s.holders.clear();
  s.contactAt.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const uint32_t at = s.next[s.level[i]]++;
    const IslandContact& c = contacts[i];
    int kb = c.kb;
    if (kb < 0) {
      kb = static_cast<int>(memberCount + s.holders.size());
      s.holders.push_back(c.holderVelocity);
    }
    s.rows[at] = {c.ka, kb, c.normal, c.inverseA, c.inverseB, c.target, c.lambda};
    s.contactAt[at] = static_cast<uint32_t>(i);
  }
}

void detail::Islands::unscheduleSweeps() {
  const SweepSchedule& s = sweepSchedule;
  for (size_t at = 0; at < s.rows.size(); ++at) islandScratch[s.contactAt[at]].lambda = s.rows[at].lambda;
}

bool detail::Islands::sweepIsland(std::vector<Vec2>& v, double omega, double tolerance, int maxIterations) {
  const size_t members = v.size();
  scheduleSweeps(members);
  std::vector<SweepRow>& rows = sweepSchedule.rows;
  v.insert(v.end(), sweepSchedule.holders.begin(), sweepSchedule.holders.end());
  // Over-relaxed, each row's step is its gap times omega / (inverseA + inverseB), computed once here: a
  // multiplication in the sweeps where a division would lengthen the chain of dependent arithmetic that
  // a sweep is (each row waits on the values the rows before it wrote; bench/README.md, "Crowds").
  std::vector<double>& scale = sweepSchedule.scale;
  scale.resize(rows.size());
  for (size_t at = 0; at < rows.size(); ++at) scale[at] = omega / (rows[at].inverseA + rows[at].inverseB);
  const auto overRelaxed = [&scale](size_t at, const SweepRow&, double gap) { return gap * scale[at]; };
  bool converged = false;
  for (int iteration = 0; iteration < maxIterations && !converged; ++iteration) {
    w.stats.contactRowsSwept += static_cast<long long>(rows.size());
    const double worst = projectedSweep(rows, v, members, overRelaxed);
    converged = worst <= tolerance;
  }
  v.resize(members);
  unscheduleSweeps();
  return converged;
}

detail::Islands::SweepEnd detail::Islands::sweepIslandAccelerated(std::vector<Vec2>& v, double tolerance,
                                                                      double h, int maxIterations) {
  // Under gravity a landing pile is a contact network hundreds of disks deep, most of it in the
  // redundant contacts of a hexagonal packing, and plain or over-relaxed Gauss-Seidel carries a push
  // about a layer a sweep: rattle-bench's pile of 1,000 stopped at its 1000 sweeps in most steps of its
  // landing, far from converged. The sweeps are accelerated by the nonsmooth nonlinear conjugate
  // gradient method (NNCG; Silcowitz, Niebe and Erleben, The Visual Computer 26, 2010): a sweep's change
  // of the multipliers is taken as the residual, and the next multipliers step further along a
  // Fletcher-Reeves direction, restarted whenever the residual grows. The velocities follow every change
  // of a multiplier, so they stay those of the multipliers; the search step can leave a multiplier
  // negative, but the sweep after it projects every one, and the solve ends after a sweep.
  //
  // It also stops once it is close enough to keep disks apart: when no contact would close farther than
  // kCloseEnough of its smaller disk's radius beyond its bound by the step's end (checked every
  // kCloseEnoughInterval sweeps). The speeds at play set the tolerance, and in a landing pile they are
  // those of the impact, so the tolerance alone asked for far more than any overlap anyone sees.
  std::vector<IslandContact>& contacts = islandScratch;
  // The sweeps run in wavefront order (scheduleSweeps), and every other pass is elementwise. The residual
  // is summed by the sweep, in the rows' order: a pass of its own in the contacts' order was a fifth of
  // this function's time, a serial sum over rows read out of order.
  const size_t members = v.size();
  scheduleSweeps(members);
  std::vector<SweepRow>& rows = sweepSchedule.rows;
  v.insert(v.end(), sweepSchedule.holders.begin(), sweepSchedule.holders.end());
  std::vector<double>& previous = islandPreviousImpulses;
  std::vector<double>& direction = islandDirection;
  previous.resize(rows.size());
  direction.assign(rows.size(), 0.0);
  double previousResidual = 0;
  SweepEnd end = SweepEnd::Stopped;
  // previous[] holds the multipliers before each sweep: copied here at the start and after a restart,
  // and written by the search step otherwise, which saves a pass over the rows.
  bool previousHeld = false;
  for (int iteration = 0; iteration < maxIterations; ++iteration) {
    w.stats.contactRowsSwept += static_cast<long long>(rows.size());
    if (!previousHeld) {
      for (size_t at = 0; at < rows.size(); ++at) previous[at] = rows[at].lambda;
    }
    previousHeld = false;
    // The sweep's changes of the multipliers, rows[at].lambda - previous[at], squared and summed.
    double residual = 0;
    const double worst = projectedSweep(rows, v, members, &residual);
    if (worst <= tolerance) {
      end = SweepEnd::Converged;
      break;
    }
    if (h > 0 && iteration % kCloseEnoughInterval == kCloseEnoughInterval - 1) {
      bool close = true;
      for (const IslandContact& c : contacts) {
        const Vec2 vb = c.kb >= 0 ? v[c.kb] : c.holderVelocity;
        if ((c.target - dot(v[c.ka] - vb, c.normal)) * h > kCloseEnough * c.radius) {
          close = false;
          break;
        }
      }
      if (close) {
        end = SweepEnd::CloseEnough;
        break;
      }
    }
    if (iteration + 1 == maxIterations) break;
    const double beta = previousResidual > 0 ? residual / previousResidual : 0.0;
    previousResidual = residual;
    if (beta > 1) {
      std::fill(direction.begin(), direction.end(), 0.0);
      continue;
    }
    // A member's velocity takes these steps in the order of its contacts, which the wavefront order
    // keeps.
    for (size_t at = 0; at < rows.size(); ++at) {
      SweepRow& r = rows[at];
      const double sweepChange = r.lambda - previous[at];
      const double step = beta * direction[at];
      direction[at] = step + sweepChange;
      if (step != 0) {
        r.lambda += step;
        v[r.ka] += r.normal * (step * r.inverseA);
        if (static_cast<size_t>(r.kb) < members) v[r.kb] -= r.normal * (step * r.inverseB);
      }
      previous[at] = r.lambda;
    }
    previousHeld = true;
  }
  v.resize(members);
  unscheduleSweeps();
  return end;
}

bool detail::Islands::projectIslandExactly(const std::vector<uint32_t>& members, std::vector<Vec2>& v,
                                              double tolerance) {
  // The same contacts as the sweeps, from the velocities before them (the bodies', without the warm
  // start).
  const std::vector<IslandContact>& contacts = islandScratch;
  ExactIslandScratch& e = exactIslandScratch;
  e.inverseMass.resize(members.size());
  for (size_t k = 0; k < members.size(); ++k) e.inverseMass[k] = w.bodies[members[k]].inverseMass;
  e.rows.resize(contacts.size());
  for (size_t i = 0; i < contacts.size(); ++i) {
    const IslandContact& c = contacts[i];
    e.rows[i].ka = c.ka;
    e.rows[i].kb = c.kb;
    e.rows[i].normal = c.normal;
    e.rows[i].target = c.kb >= 0 ? c.target : c.target + dot(c.holderVelocity, c.normal);
  }
  e.velocities.resize(members.size());
  for (size_t k = 0; k < members.size(); ++k) e.velocities[k] = w.bodies[members[k]].velocity;
  if (!detail::projectExactly(e.inverseMass, e.velocities, e.rows, e.impulses, 1e-3 * tolerance, e.projection))
    return false;
  v = e.velocities;
  for (size_t i = 0; i < contacts.size(); ++i) islandScratch[i].lambda = e.impulses[i];
  return true;
}

void detail::Islands::separateIsland(const std::vector<uint32_t>& members, const std::vector<Vec2>& v, double h) {
  // Overlap left by a solve that stopped short of its tolerance would otherwise stay (a touching
  // contact's target is 0, not a push apart) and grow step by step in a crowd that keeps pressing. It is
  // taken out by moving positions, not velocities (the split impulse of Catto's Box2D v2.x TOI solver
  // and of Bullet: a pseudo-velocity solve): kinetic energy is untouched, and without gravity there is
  // no potential energy to raise. An overlapping contact asks the displacement d to open it by
  // kSeparateFactor of its overlap (Baumgarte's factor, Catto 2005); every other contact asks
  // that d closes no more than its gap at the step's start and at its end along the solved velocities.
  // A straight path's distance to a convex piece is convex in time, so such a pair stays apart all
  // step. Projected Gauss-Seidel on d in the metric of the masses, as the velocity solve; then the
  // contacts with what cannot move are met exactly, as in the velocity solve.
  std::vector<IslandContact>& contacts = islandScratch;
  std::vector<Vec2>& d = separateScratch.displacements;
  std::vector<double>& lower = separateScratch.lower;
  d.assign(members.size(), Vec2{});
  lower.resize(contacts.size());
  bool any = false;
  for (size_t i = 0; i < contacts.size(); ++i) {
    const IslandContact& c = contacts[i];
    const Vec2 vb = c.kb >= 0 ? v[c.kb] : c.holderVelocity;
    const double endGap = c.gap + h * dot(v[c.ka] - vb, c.normal);
    const double least = std::min(c.gap, endGap);
    lower[i] = least < 0 ? -kSeparateFactor * least : -least;
    any = any || least < 0;
  }
  if (!any) return;
  // In wavefront order, as the velocity sweeps (scheduleSweeps), with multipliers of their own. What
  // cannot move stays where it is: its displacement is zero.
  scheduleSweeps(members.size());
  std::vector<SweepRow>& rows = sweepSchedule.rows;
  for (size_t at = 0; at < rows.size(); ++at) {
    rows[at].target = lower[sweepSchedule.contactAt[at]];
    rows[at].lambda = 0;
  }
  d.resize(members.size() + sweepSchedule.holders.size(), Vec2{});  // holders do not move
  // Most rows are pairs a gap apart that the displacements, a few thousandths of a radius, never reach:
  // their multipliers stay zero and a sweep only reads them. The sweeps run over the rows within
  // kSeparateReach of their radius of their bound, in the same order (a subsequence keeps each member's
  // order of contacts). If the displacements then break a row left out, every row is swept from the
  // start.
  std::vector<SweepRow>& near = separateScratch.nearRows;
  std::vector<uint32_t>& leftOut = separateScratch.leftOut;
  near.clear();
  leftOut.clear();
  for (size_t at = 0; at < rows.size(); ++at) {
    if (rows[at].target > -kSeparateReach * contacts[sweepSchedule.contactAt[at]].radius) {
      near.push_back(rows[at]);
    } else {
      leftOut.push_back(static_cast<uint32_t>(at));
    }
  }
  w.stats.contactRowsSwept += static_cast<long long>(kSeparateIterations) * static_cast<long long>(near.size());
  for (int iteration = 0; iteration < kSeparateIterations; ++iteration) projectedSweep(near, d, members.size());
  const bool reached = std::any_of(leftOut.begin(), leftOut.end(), [&](uint32_t at) {
    const SweepRow& r = rows[at];
    return dot(d[r.ka] - d[r.kb], r.normal) < r.target;
  });
  if (reached) {
    std::fill(d.begin(), d.end(), Vec2{});
    w.stats.contactRowsSwept += static_cast<long long>(kSeparateIterations) * static_cast<long long>(rows.size());
    for (int iteration = 0; iteration < kSeparateIterations; ++iteration) projectedSweep(rows, d, members.size());
  }
  d.resize(members.size());
  for (int sweep = 0; sweep < 16; ++sweep) {
    bool changed = false;
    for (size_t i = 0; i < contacts.size(); ++i) {
      const IslandContact& c = contacts[i];
      if (c.kb >= 0) continue;
      const double dn = dot(d[c.ka], c.normal);
      if (!(dn < lower[i])) continue;
      d[c.ka] += c.normal * (lower[i] - dn);
      changed = true;
    }
    if (!changed) break;
  }
  // Contradictory asks (a disk made wider than the gap between two walls) cannot be met: a body whose
  // displacement would still take it deeper into something that cannot move than it was stays put.
  for (size_t i = 0; i < contacts.size(); ++i) {
    const IslandContact& c = contacts[i];
    if (c.kb >= 0) continue;
    const double radius = detail::circleRadius(w.fixtures[c.fa].geometry);
    if (dot(d[c.ka], c.normal) < std::min(lower[i], 0.0) - 1e-12 * std::max(radius, 1.0)) d[c.ka] = Vec2{};
  }
  // The contacts above are those of the pairs the sweep found for the boxes it saw. A body moved out
  // of its box, along its path for the step, could meet what no pair told of (a disk at rest beside a
  // heavy one it overlaps, pushed down through a floor that only touched its box): it stays put. A path
  // whose end the solve already sent out of the box is asked about again after the solve, displaced or
  // not (startIslandsAndPredict), so only a displacement that takes the end out counts: pinning such a
  // body left its neighbours' displacements closing on it (rattle-soak's crowd, two disks at the
  // doorway 1.1% of a radius into each other).
  for (size_t k = 0; k < members.size(); ++k) {
    if (d[k].x == 0 && d[k].y == 0) continue;
    const BodySlot& b = w.bodies[members[k]];
    for (uint32_t f : b.fixtures) {
      if (w.fixtures[f].sensor || !w.broadPhase.contains(f)) continue;
      const Box& seen = w.broadPhase.box(f);
      const Box& local = w.fixtures[f].localBox;
      const Vec2 start = b.position + d[k], end = start + v[k] * h, undisplacedEnd = b.position + v[k] * h;
      if (!seen.contains(Box{start + local.min, start + local.max}) ||
          (!seen.contains(Box{end + local.min, end + local.max}) &&
           seen.contains(Box{undisplacedEnd + local.min, undisplacedEnd + local.max}))) {
        d[k] = Vec2{};
        break;
      }
    }
  }
  for (size_t k = 0; k < members.size(); ++k) {
    if (d[k].x == 0 && d[k].y == 0) continue;
    BodySlot& b = w.bodies[members[k]];
    w.keep(b);
    b.position += d[k];
    ++b.collisionCount;
    b.last = detail::LastContact{};
  }
}

void detail::Islands::trimIsland(const std::vector<uint32_t>& members, std::vector<Vec2>& v, double h) {
  // A contact that the solved velocities would close more than kTrimSlack of its radius beyond its gap
  // within the step stops the bodies whose velocities close it; a stopped body can break a contact it
  // was opening, which is asked again (a worklist in first-in first-out order, so the bits follow the
  // contacts' order). Each body stops once, so the worklist ends. With every member stopped each contact
  // is met but for an overlap at the start or a kinematic body closing in, which no stop meets and which
  // the contact then does not ask about. As in the solve, a straight path's distance to a disk or a convex
  // piece is convex in time, so meeting the bound at the step's end meets it all step.
  //
  // Stopping rather than slowing each body by the share a contact asks: a slowed body is still met by
  // the bodies behind it within the step, as events and solves, and the crowd cost more, overlapped more
  // and got no more through its doorway (bench/README.md, "Crowds"). Every stop lowers the kinetic
  // energy; what is lost is momentum the exact answer would pass on through the jam, and a contact
  // event's impulse is the solve's, without the stop.
  const std::vector<IslandContact>& contacts = islandScratch;
  const size_t n = members.size();
  TrimScratch& t = trimScratch;
  // Each member's contacts, as offsets into one list (a counting sort by member, in the contacts' order).
  t.first.assign(n + 1, 0);
  for (const IslandContact& c : contacts) {
    ++t.first[static_cast<size_t>(c.ka) + 1];
    if (c.kb >= 0) ++t.first[static_cast<size_t>(c.kb) + 1];
  }
  for (size_t k = 0; k < n; ++k) t.first[k + 1] += t.first[k];
  t.contactsOf.resize(t.first[n]);
  t.next.assign(t.first.begin(), t.first.end() - 1);
  for (uint32_t i = 0; i < contacts.size(); ++i) {
    t.contactsOf[t.next[static_cast<size_t>(contacts[i].ka)]++] = i;
    if (contacts[i].kb >= 0) t.contactsOf[t.next[static_cast<size_t>(contacts[i].kb)]++] = i;
  }
  t.queue.resize(contacts.size());
  std::iota(t.queue.begin(), t.queue.end(), 0u);
  t.queued.assign(contacts.size(), 1);
  // Under gravity a member that no contact pushes is freed after the start solve, its step of gravity
  // taken back (startIslands): stopped, it would rise at g dt. The solve has marked those it pushes
  // (markHeld), and nothing before the start solve had.
  const bool gravity = w.def.gravity.x != 0 || w.def.gravity.y != 0;
  const auto stop = [&](size_t k) {
    if (gravity && !steppedHeld[members[k]]) return;
    v[k] = Vec2{};
    for (uint32_t at = t.first[k]; at < t.first[k + 1]; ++at) {
      const uint32_t j = t.contactsOf[at];
      if (t.queued[j]) continue;
      t.queued[j] = 1;
      t.queue.push_back(j);
    }
  };
  for (size_t head = 0; head < t.queue.size(); ++head) {
    const uint32_t i = t.queue[head];
    t.queued[i] = 0;
    const IslandContact& c = contacts[i];
    const size_t ka = static_cast<size_t>(c.ka), kb = static_cast<size_t>(c.kb);
    // The relative normal velocity is a's share minus b's: a closes it moving against the normal, b
    // moving along it.
    const double ta = dot(v[ka], c.normal);
    const double tb = c.kb >= 0 ? -dot(v[kb], c.normal) : -dot(c.holderVelocity, c.normal);
    if (!((ta + tb) * h < -(c.gap + kTrimSlack * c.radius))) continue;
    if (ta < 0) stop(ka);
    if (tb < 0 && c.kb >= 0) stop(kb);
  }
}

void detail::Islands::beginStep() {
  jamCounterAtStart_ = jamCounter;
  swapped_ = false;
  jamMarks_.clear();
  bursts_.clear();
  // The warm start is kept by fixture index, and a destroyed fixture's index is reused.
  if (w.changes.fixtureRemovals != fixtureRemovalsSeen_) {
    islandNext.clear();
    fixtureRemovalsSeen_ = w.changes.fixtureRemovals;
  }
}

void detail::Islands::undoStep() {
  jamCounter = jamCounterAtStart_;
  if (swapped_) islandImpulses.swap(islandNext);  // last step's warm start, as it was
  swapped_ = false;
  // Scratch whose invariants hold between calls.
  std::fill(jamSlot.begin(), jamSlot.end(), -1);
  unsolvedIslandPairs.clear();
  settlingUnsolved = false;
}

void detail::Islands::startIslands(double dt, std::vector<uint32_t>& freed) {
  islandImpulses.swap(islandNext);
  swapped_ = true;
  islandNext.clear();
  std::sort(islandImpulses.begin(), islandImpulses.end());
  islandScratchStart.clear();
  freed.clear();
  if (gravityAllowance.size() < w.bodies.size()) gravityAllowance.resize(w.bodies.size(), 0.0);
  if (steppedHeld.size() < w.bodies.size()) steppedHeld.resize(w.bodies.size(), 0);
  if (w.stepStartVelocity.size() < w.bodies.size()) w.stepStartVelocity.resize(w.bodies.size());
  for (uint32_t i : stepped) {  // gathered by the step's first pass over the bodies
    BodySlot& b = w.bodies[i];
    w.keep(b);
    w.stepStartVelocity[i] = b.velocity;
    b.steppedSinceStart = true;
    b.velocity += w.def.gravity * dt;
    steppedHeld[i] = 0;
    gravityAllowance[i] = 0.5 * b.mass * dot(w.def.gravity, w.def.gravity) * dt * dt;
  }
  if (stepped.empty()) return;
  // A contact is a collision when it closed faster than restingSpeed before the step's gravity; holding
  // a resting body up against that gravity is not one.
  w.stats.eventsProcessed +=
      solveIsland(stepped, 0, dt, w.def.restingSpeed + length(w.def.gravity) * dt, ~uint64_t{0}, true, true,
                  std::max(0, w.def.maxEventsPerStep - w.stats.eventsProcessed))
          .reported;
  for (const IslandContact& c : islandScratch) {
    if (!(c.lambda > 0)) continue;
    islandScratchStart.push_back(c);
    islandNext.push_back({islandKey(c.fa, c.fb), c.lambda});
  }
  // Nothing held it: it falls freely, exactly, as it did before the step's gravity was added.
  size_t kept = 0;
  for (uint32_t i : stepped) {
    BodySlot& b = w.bodies[i];
    if (steppedHeld[i]) {
      stepped[kept++] = i;
      continue;
    }
    b.velocity -= w.def.gravity * dt;
    b.acceleration = w.def.gravity;
    b.stepped = false;
    freed.push_back(i);
  }
  stepped.resize(kept);
  steppedCounts.resize(stepped.size());
  for (size_t k = 0; k < stepped.size(); ++k) steppedCounts[k] = w.bodies[stepped[k]].collisionCount;
}

void detail::Islands::endIslands(double end) {
  // Without gravity nothing holds a body at rest (no up): it stays stepped while its contacts push, and
  // is free again at the start of the first step in which none does.
  if (stepped.empty() || (w.def.gravity.x == 0 && w.def.gravity.y == 0)) return;
  const Vec2 up = -w.def.gravity * (1.0 / length(w.def.gravity));
  std::vector<int>& slot = jamSlot;
  if (slot.size() < w.bodies.size()) slot.resize(w.bodies.size(), -1);
  for (size_t k = 0; k < stepped.size(); ++k) slot[stepped[k]] = static_cast<int>(k);
  // What held each body at the start of the step: the contacts that pushed it up or sideways (from
  // below or beside), with their other bodies.
  std::vector<std::vector<uint32_t>> holders(stepped.size());
  std::vector<char> candidate(stepped.size(), 0), movingHolder(stepped.size(), 0);
  for (size_t k = 0; k < stepped.size(); ++k) {
    const BodySlot& b = w.bodies[stepped[k]];
    // At rest: still stepped, not moved on by an event since the solve, and slow.
    // Not a body being parted from another (separation.cpp): asleep, it would stay on it.
    candidate[k] = b.stepped && !b.asleep && b.collisionCount == steppedCounts[k] &&
                   length(b.velocity) < w.def.restingSpeed &&
                   !std::binary_search(w.beingParted.begin(), w.beingParted.end(), stepped[k]);
  }
  for (const IslandContact& c : islandScratchStart) {
    const int ka = slot[c.a], kb = c.kb >= 0 ? slot[c.b] : -1;
    if (ka >= 0 && dot(c.normal, up) >= -1e-12) {
      holders[ka].push_back(c.b);
      if (w.bodies[c.b].type == BodyType::Kinematic) movingHolder[ka] = 1;
    }
    if (kb >= 0 && dot(c.normal, up) <= 1e-12) holders[kb].push_back(c.a);
  }
  // A body at rest sleeps once everything that holds it is static, asleep or at rest and held in turn
  // the same way: the largest such set sleeps at once, so bodies that hold each other from beside (a
  // floor row wedged between two walls by the pile on it) sleep together, and a body sliding off the
  // top of a settled pile does not keep the pile awake. The solve had cancelled a whole step of gravity
  // on them with those contacts, so they are held.
  std::vector<char> resting(stepped.size(), 0);
  std::vector<uint32_t> order;
  for (size_t k = 0; k < stepped.size(); ++k)
    if (candidate[k] && !movingHolder[k] && !holders[k].empty()) {
      order.push_back(static_cast<uint32_t>(k));
      resting[k] = 1;
    }
  for (bool changed = true; changed;) {
    changed = false;
    for (uint32_t k : order) {
      if (!resting[k]) continue;
      for (uint32_t h : holders[k]) {
        const BodySlot& holder = w.bodies[h];
        if (holder.type == BodyType::Static || holder.asleep) continue;
        if (holder.type == BodyType::Dynamic && slot[h] >= 0 && resting[slot[h]]) continue;
        resting[k] = 0;
        changed = true;
        break;
      }
    }
  }
  std::vector<uint32_t> supporters;
  for (uint32_t k : order) {
    if (!resting[k]) continue;
    BodySlot& b = w.bodies[stepped[k]];
    supporters.clear();
    for (uint32_t h : holders[k])
      if (w.bodies[h].type == BodyType::Dynamic && std::find(supporters.begin(), supporters.end(), h) == supporters.end())
        supporters.push_back(h);
    w.advance(b, end);
    putToSleep(w, stepped[k], supporters);
  }
  for (uint32_t i : stepped) slot[i] = -1;
}

}  // namespace rattle
