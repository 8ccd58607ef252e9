// The hybrid step (the default): swept boxes through sort-and-sweep, then exact events inside the step.
//
//  1. Every fixture of a moving body gets the box of its path over the step (a straight line, or a
//     parabola under gravity); sleeping bodies count as resting. Without gravity a slow plain disk's box
//     also has room for a turn at 1.5 times its speed (HybridStep::kPlainSlack), so that after most of
//     its collisions step 4 need not ask the broad phase again.
//  2. Sort-and-sweep turns overlapping boxes into candidate pairs (static-static and filtered pairs
//     never get this far; sensors wait for step 6). Without gravity the broad phase keeps the pairs of
//     slightly widened boxes from step to step and sweeps again only when many boxes have left them
//     (broad_phase.h, the pair cache): the same pairs, in another order.
//  3. Each candidate pair gets its exact time of impact within the step; the predictions go into one
//     queue ordered by time, kind and then ids.
//  4. Events are resolved in time order. A prediction carries the collision counters its bodies had when
//     it was made; when one has changed since, the prediction is stale and dropped (lazy invalidation:
//     Sedgewick & Wayne, Algorithms 6.1). After a collision the two bodies are predicted again from that
//     instant, and when a body's new path leaves the swept box the sweep saw, the broad phase is asked
//     again for it, so a path changed mid-step misses nothing.
//  5. Every body moves to the end of the step.
//  Under gravity, bodies resting on one another are stepped islands (island.cpp): between 3 and 4 one
//  solve a step holds their contacts, they move along straight lines, and their meetings with free bodies
//  are events as above.
//  6. (Before 5.) When the world has sensors, each body's path was recorded piece by piece (one piece
//     from each change of its motion), and the sensor events are found along those paths, exactly, as
//     the predictive mode finds them (sensor_paths.cpp). Re-predicting every sensor pair of a body at
//     each of its collisions instead cost most of a crowd's step: a unit sits in dozens of sight circles.
//
// Within a step each body keeps its position at its own local time (the time of its last collision), so
// bodies that do not collide are moved once per step and times stay in [0, dt] where they are precise.
#include "hybrid/hybrid_step.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "collision/closest_point.h"
#include "collision/path_box.h"
#include "common/same_bits.h"
#include "contact/collapse_guard.h"
#include "contact/response.h"
#include "contact/resting.h"
#include "contact/squeeze.h"
#include "contact/tolerances.h"
#include "hybrid/hybrid_state.h"
#include "rattle/time_of_impact.h"
#include "sensors/sensors.h"
#include "world/stepper.h"
#include "world/world_impl.h"

namespace rattle {

namespace {

// Stores `value` unless `to` already holds its very bits.
template <class T>
void storeIfChanged(T& to, const T& value) {
  if (!detail::sameBits(to, value)) to = value;
}

}  // namespace

using detail::BodySlot;
using detail::PredictedContact;
using detail::pathBox;

namespace {

// One hybrid step over the world's state, in named phases (run). It holds only references: what the
// hybrid step keeps between steps, its islands and jams among it, is the HybridState its caller owns
// (hybrid_state.h); the contact response it shares with the other modes stays WorldState's. While it
// lives it is its islands' EventPredictor: the islands and jams tell it whose motion they changed
// (motionChanged).
class HybridStep final : public detail::EventPredictor {
 public:
  // Steps are not nested: outside one the islands have no predictor.
  HybridStep(detail::WorldState& world, detail::HybridState& state) : w_(world), h_(state) {
    state.islands.predictor = this;
  }
  ~HybridStep() { h_.islands.predictor = nullptr; }
  HybridStep(const HybridStep&) = delete;
  HybridStep& operator=(const HybridStep&) = delete;
  void run(double dt, int eventsBefore);
  void motionChanged(uint32_t body, double now, double dt) override { repredict(body, now, dt); }

 private:
  /// Without gravity, a plain disk's swept box holds every straight path from its start at this many
  /// times its speed, besides its own path. On the bench's gas at 10^6 disks (packing 0.3, dt 1/60) the
  /// broad phase was asked again 21,500 times a step without it, 5,400 at 1, 1,650 at 1.5 and 850 at 2;
  /// the whole step was fastest at 1.5 (per-phase clocks, two alternating runs): the events' time fell
  /// from about 31 ms to 17, for 30% more candidate pairs.
  static constexpr double kPlainSlack = 1.5;
  /// ... as long as that room is at most this fraction of its radius. Without the limit the demo's arena
  /// (fast projectiles: room all round for 1.5 steps of travel is a box many times the path's) stepped
  /// 5-10% slower in three alternating runs at 100 and 1000 units a team; with it, as fast as without
  /// the slack, and the bench's gas (speeds about 1, radius 0.5, dt 1/60) keeps all of its gain.
  static constexpr double kPlainSlackLimit = 0.25;
  /// How many bodies ahead the hybrid step's passes over all bodies ask for their slots.
  static constexpr uint32_t kStreamAhead = 16;

  // The phases, in order.
  double sweepBoxes(double dt);
  void predictCandidatePairs(double dt);
  void startIslandsAndPredict(double dt);
  double processEvents(double dt, double approachTolerance);
  double lastChangeBefore(double next) const;
  // processEvents' cases.
  void dismissContact(const detail::PredictedContact& c, double dt, double vn, Vec2 relativeVelocity,
                      double restTolerance, int& featureRepredictions);
  void collide(const detail::PredictedContact& c, double dt, std::vector<uint32_t>& woken);
  /// squeezeAt, and when it squeezed, the event counted and its bodies predicted again.
  bool squeezeAndPredict(const detail::PredictedContact& c, double dt);
  /// Whether a contact would leave two bodies that both move (awake, not static) bouncing off each other
  /// slower than restingSpeed while gravity presses them together: they join a stepped island.
  /// stepEnd as for detail::resolve.
  bool joinsIsland(const detail::PredictedContact& c, double stepEnd) const;
  /// Asks for what the first pass will read of body i + kStreamAhead (a prefetch). Inline: a call to a
  /// function that only prefetches is one GCC may drop (it finds it has no effect), and did.
  inline void prefetchFirstPass(uint32_t i, uint32_t count, const detail::DiskShape* shapes) const;
  /// The sweep's pair of two plain disks (fixtures fa and fb of bodies ba and bb) at the step's start, as
  /// canCollide, addPair and predict would take it, from their bodies' first lines and DiskShapes.
  void predictPlainPair(uint32_t fa, uint32_t fb, uint32_t ba, uint32_t bb, double dt);

  // The predictions into the queue.
  /// A candidate pair, in the pair lists of its dynamic bodies.
  void addPair(uint32_t fa, uint32_t fb);
  /// `dismissed`: a feature of `other` whose contact at `now` was found not to be approaching and
  /// dropped; it is taken as separating (like a feature just resolved), the other features as usual.
  void predict(uint32_t own, uint32_t other, double now, double dt, int dismissed = kNoFeature);
  /// Queues the contact `impact` found at `now` (in the frame where `other` rests, which moves on with
  /// the given velocity and acceleration), carrying both bodies' collision counters.
  void queueContact(const Impact& impact, uint32_t own, uint32_t other, uint32_t countOwn, uint32_t countOther,
                    Vec2 velocityOfOther, Vec2 accelerationOfOther, double now, double dt,
                    bool afterDismissal = false);
  void predictSlideEnd(uint32_t body, double now, double dt);
  /// A body's motion changed at `now`: its pairs are predicted again, and the broad phase is asked again
  /// when its new path leaves the box the sweep saw (or with forceRequery: it just woke).
  void repredict(uint32_t body, double now, double dt, bool forceRequery = false);

  // Each member function reads these into locals first, as the discrete stepper does: a local reference
  // stays in a register, where a member may be loaded again through `this` after a store.
  detail::WorldState& w_;
  detail::HybridState& h_;
};

}  // namespace

void HybridStep::addPair(uint32_t fa, uint32_t fb) {
  detail::WorldState& w = w_;
  const uint32_t ba = w.fixtures[fa].body, bb = w.fixtures[fb].body;
  if (w.bodies[ba].type == BodyType::Dynamic) w.pairsOfBody[ba].push_back({fa, fb});
  if (w.bodies[bb].type == BodyType::Dynamic) w.pairsOfBody[bb].push_back({fb, fa});
}

namespace {

// Polylines and polygons: a contact with one of their features says nothing of the others.
bool hasSeveralFeatures(const Geometry& g) {
  return std::holds_alternative<Polyline>(g) || std::holds_alternative<Polygon>(g);
}

}  // namespace

void HybridStep::predict(uint32_t own, uint32_t other, double now, double dt, int dismissed) {
  detail::WorldState& w = w_;
  const BodySlot& a = w.bodyOf(own);
  const BodySlot& b = w.bodyOf(other);
  if (detail::Islands::heldByIsland(a, b)) return;  // the island's solve holds this contact (island.cpp)
  if (!w.squeezes.empty() && squeezeExempt(w, own, other)) return;  // squeeze.cpp
  ++w.stats.timeOfImpactTests;

  int resolved = resolvedFeature(w, a, b, own, other, now);
  if (dismissed != kNoFeature) resolved = dismissed;

  const auto impact = predictImpact(w, a, b, own, other, now, dt - now, resolved);
  // An impact now may be a pair made overlapping (squeeze.cpp), parted by moving it rather than by events.
  if (impact && impact->time == 0 && exemptIfMadeOverlapping(w, own, other, now)) return;
  if (impact) {
    queueContact(*impact, own, other, a.collisionCount, b.collisionCount, w.velocityAt(b, now), b.acceleration, now, dt,
                 dismissed != kNoFeature);
  }
}

void HybridStep::queueContact(const Impact& impact, uint32_t own, uint32_t other, uint32_t countOwn,
                              uint32_t countOther, Vec2 velocityOfOther, Vec2 accelerationOfOther, double now,
                              double dt, bool afterDismissal) {
  // The impact's point is in the frame where `other` rests; in the world it has moved with it.
  const double h = impact.time;
  const double time = std::min(now + h, dt);
  const Vec2 travelOfOther = velocityOfOther * h + accelerationOfOther * (0.5 * h * h);
  std::vector<PredictedContact>& queue = h_.queue;
  queue.push_back(PredictedContact{time, detail::EventKind::Contact, afterDismissal, own, other, impact.feature,
                                   countOwn, countOther, impact.point + travelOfOther, impact.normal});
  std::push_heap(queue.begin(), queue.end(), detail::later);
}

void HybridStep::predictPlainPair(uint32_t fa, uint32_t fb, uint32_t ba, uint32_t bb, double dt) {
  detail::WorldState& w = w_;
  // The sweep's candidate pair of two plain disks at the step's start: canCollide, addPair and
  // predict(own, other, 0, dt) as for any pair, reading each body's first line and its DiskShape instead
  // of its fixture. The arithmetic is predict's and timeOfImpact's for two circles centred on their
  // bodies, step by step, so the prediction has the same bits. (The broad phase has checked the filter
  // bits; neither is a sensor.)
  const detail::DiskShape& sa = w.diskShapes[ba];
  const detail::DiskShape& sb = w.diskShapes[bb];
  if (ba == bb || (sa.group != 0 && sa.group == sb.group)) return;
  ++w.stats.candidatePairs;
  w.pairsOfBody[ba].push_back({fa, fb});
  w.pairsOfBody[bb].push_back({fb, fa});
  const bool aFirst = fa < fb;
  const uint32_t own = aFirst ? fa : fb, other = aFirst ? fb : fa;
  const BodySlot& a = w.bodies[aFirst ? ba : bb];
  const BodySlot& b = w.bodies[aFirst ? bb : ba];
  const double radiusA = aFirst ? sa.radius : sb.radius, radiusB = aFirst ? sb.radius : sa.radius;
  ++w.stats.timeOfImpactTests;
  const Vec2 positionA = w.positionAt(a, 0), positionB = w.positionAt(b, 0);
  const Vec2 velocityB = w.velocityAt(b, 0);
  // Both accelerate by the world's gravity, which is zero for a plain disk: g - g = +0.
  const Motion relative{w.velocityAt(a, 0) - velocityB, w.def.gravity - w.def.gravity};
  Circle circle{Vec2{0.0, 0.0} + positionA, radiusA};  // as circleVs: the centre (+0, +0) plus the position
  circle.center -= positionB;
  auto impact = timeOfImpactCircleCircle(circle, relative, Circle{Vec2{0.0, 0.0}, radiusB}, dt - 0.0, kNoFeature);
  if (!impact) return;
  if (impact->time == 0 && exemptIfMadeOverlapping(w, own, other, 0.0)) return;  // as in predict()
  impact->point += positionB;
  queueContact(*impact, own, other, a.collisionCount, b.collisionCount, velocityB, w.def.gravity, 0.0, dt);
}

void HybridStep::predictSlideEnd(uint32_t bodyIndex, double now, double dt) {
  detail::WorldState& w = w_;
  detail::HybridState& h = h_;
  const BodySlot& b = w.bodies[bodyIndex];
  if (!b.sliding) return;
  const auto t = slideEndTime(w, b, now, dt);
  if (!t) return;
  h.queue.push_back(PredictedContact{std::min(*t, dt),
                                   detail::EventKind::SlideEnd,
                                   false,
                                   b.fixtures.front(),
                                   b.support.fixture,
                                   b.support.feature,
                                   b.collisionCount,
                                   0,
                                   {},
                                   {}});
  std::push_heap(h.queue.begin(), h.queue.end(), detail::later);
}

void HybridStep::repredict(uint32_t bodyIndex, double now, double dt, bool forceRequery) {
  detail::WorldState& w = w_;
  detail::HybridState& h = h_;
  BodySlot& body = w.bodies[bodyIndex];
  w.recordPath(bodyIndex, now);
  auto& pairs = w.pairsOfBody[bodyIndex];
  const Box path = pathBox(w.positionAt(body, now), w.velocityAt(body, now), body.acceleration, dt - now);
  for (uint32_t f : body.fixtures) {
    if (w.fixtures[f].sensor) continue;  // sensed along the paths after the step (sensor_paths.cpp)
    Box box{path.min + w.fixtures[f].localBox.min, path.max + w.fixtures[f].localBox.max};
    if (detail::isPoint(w.fixtures[f].geometry)) box = detail::withRoundOff(box);
    if (!forceRequery && w.broadPhase.box(f).contains(box)) continue;
    // The new path leaves the swept box (or the body just woke and the sweep skipped it as resting):
    // grow the box and ask the broad phase again.
    ++w.stats.requeries;
    w.broadPhase.grow(f, unionOf(w.broadPhase.box(f), box));
    ++h.stampCounter;
    for (const auto& p : pairs) {
      if (p.own == f) h.stamp[p.other] = h.stampCounter;
    }
    w.broadPhase.queryAround(f, [&](uint32_t g) {
      if (h.stamp[g] == h.stampCounter || !canCollide(w, f, g)) return;
      h.stamp[g] = h.stampCounter;
      ++w.stats.candidatePairs;
      addPair(f, g);
      // A contact an island holds that its last solve did not see (island.cpp).
      if (detail::Islands::heldByIsland(body, w.bodyOf(g))) h.islands.unsolvedIslandPairs.push_back(bodyIndex);
    });
  }
  // `pairs` may have grown above (addPair); index, do not iterate by reference.
  for (size_t i = 0; i < pairs.size(); ++i) predict(pairs[i].own, pairs[i].other, now, dt);
  predictSlideEnd(bodyIndex, now, dt);
}

bool HybridStep::joinsIsland(const PredictedContact& c, double stepEnd) const {
  const detail::WorldState& w = w_;
  if (!(w.def.restingSpeed > 0)) return false;
  const uint32_t ia = w.fixtures[c.a].body, ib = w.fixtures[c.b].body;
  const BodySlot& a = w.bodies[ia];
  const BodySlot& b = w.bodies[ib];
  auto movable = [](const BodySlot& s) { return s.type == BodyType::Dynamic && !s.asleep; };
  if (!movable(a) || !movable(b)) return false;
  // An island's contacts are built from distances (island.cpp), which cannot tell a point's side of a
  // face it lies on: a point's contacts stay events, where its slide and LastContact tell it.
  if (detail::isPoint(w.fixtures[c.a].geometry) || detail::isPoint(w.fixtures[c.b].geometry)) return false;
  // Pressed together by gravity, or one of them already held by an island that pushes it into the other.
  if (!a.stepped && !b.stepped && !(dot(a.acceleration - b.acceleration, c.normal) < 0)) return false;
  // The bounce resolve() would give (Newton's law with the TC model's exception), against restingSpeed,
  // from the approach resolve() reads (impactNormalVelocity: the paths' reading, or the slower reading of
  // a body stepped since the step's start on the parabola it began the step on), where the paths close no
  // faster than restingSpeed plus a step of gravity: a free disk landing on a pile then joins it instead
  // of bouncing on it, and the landing takes fewer collisions. Where the paths close faster, from the
  // paths' approach alone: read the other way there too, pairs that came together at speed joined, and a
  // pile of 2,000 poured into a container overlapped by 1.2% of a radius (tests: GravityPile).
  const double path = pathNormalVelocity(w, a, b, c.normal, c.time, stepEnd);
  const bool slowPaths = -std::min(path, 0.0) <= w.def.restingSpeed + length(w.def.gravity) * stepEnd;
  const double vn = std::min(slowPaths ? slowerOnStartParabola(w, ia, ib, c.normal, c.time, stepEnd, path) : path, 0.0);
  const double now = w.time + c.time;
  const bool rapid = now - a.lastContactTime < w.def.collapseTime || now - b.lastContactTime < w.def.collapseTime;
  const double e = rapid ? 1.0 : std::max(w.fixtures[c.a].restitution, w.fixtures[c.b].restitution);
  if (!(-e * vn < w.def.restingSpeed)) return false;
  // Nor a body with a circle centred on a static fixture's boundary (made over a wall's face): no island
  // contact would hold it there (Islands::heldByIslandContacts).
  return h_.islands.heldByIslandContacts(ia, c.time) && h_.islands.heldByIslandContacts(ib, c.time);
}

[[gnu::always_inline]] inline void HybridStep::prefetchFirstPass(uint32_t i, uint32_t count,
                                                                const detail::DiskShape* shapes) const {
  const detail::WorldState& w = w_;
  // The first pass streams several arrays at once (the bodies' first lines, the pair lists' headers, the
  // disk shapes, the proxies and their reaches), which the hardware prefetcher does not keep ahead of:
  // it stops at every 4 KiB page, 21 BodySlots. Asked for kStreamAhead bodies ahead, and what depends on
  // a slot's first line half as far ahead, once that line has arrived.
  if (i + kStreamAhead < count) {
    __builtin_prefetch(&w.bodies[i + kStreamAhead], 1);
    __builtin_prefetch(&w.pairsOfBody[i + kStreamAhead], 1);
  }
  constexpr uint32_t kHalf = kStreamAhead / 2;
  if (i + kHalf >= count) return;
  const BodySlot& b = w.bodies[i + kHalf];
  if (!b.alive) return;
  if (b.diskShape) {
    w.broadPhase.prefetch(shapes[i + kHalf].fixture);
  }
  if (b.stepLocalsSet || b.sliding || !b.diskShape) {
    const char* slot = reinterpret_cast<const char*>(&b);
    for (size_t line = 64; line < sizeof(BodySlot); line += 64) __builtin_prefetch(slot + line, 1);
  }
}

// 1. Swept boxes. A sleeping body does not move this step: its proxies count as resting. Returns the
// fastest speed in the world this step.
double HybridStep::sweepBoxes(double dt) {
  detail::WorldState& w = w_;
  detail::HybridState& h = h_;
  // Read once: stores into the bodies below could alias the array's pointer for all the compiler knows.
  const detail::DiskShape* const shapes = w.diskShapes.data();
  double speedScale = 0, straightSpeedSquared = 0;
  h.slidingAtStart.clear();
  h.islands.stepped.clear();
  const uint32_t bodyCount = static_cast<uint32_t>(w.bodies.size());
  const bool noGravity = w.def.gravity.x == 0 && w.def.gravity.y == 0;
  for (uint32_t i = 0; i < bodyCount; ++i) {
    prefetchFirstPass(i, bodyCount, shapes);
    BodySlot& b = w.bodies[i];
    if (!b.alive) continue;
    // The stores below are skipped when they would not change a bit: most bodies of a large world
    // start the step as the last one left them, and a line that is only read is not written back.
    if (!w.pairsOfBody[i].empty()) w.pairsOfBody[i].clear();
    storeIfChanged(b.localTime, 0.0);
    // Most bodies of a large world did not collide last step: their step-local state is as reset, and
    // its lines (and the support's) are left unread (BodySlot::stepLocalsSet, BodySlot::sliding).
    if (b.stepLocalsSet) {
      b.last = detail::LastContact{};
      b.stepCollisions = 0;
      b.stepLocalsSet = false;
    }
    if (b.sliding &&
        (!w.fixtures[b.support.fixture].alive || w.fixtures[b.support.fixture].generation != b.support.generation)) {
      stopSliding(w, b);
    }
    if (b.type == BodyType::Dynamic && !b.asleep && !b.sliding) {
      storeIfChanged(b.acceleration, b.stepped ? Vec2{} : w.def.gravity);
    }
    if (b.sliding) h.slidingAtStart.push_back(i);
    if (b.stepped) h.islands.stepped.push_back(i);
    const bool moving = w.moves(b) && !b.asleep;
    // A body standing still all step (a crowd's waiting units) meets another still one only after
    // something sets one of them moving, and then its path leaves this box and the broad phase is asked
    // again (repredict): the sweep pairs it only with what moves, as it does a sleeping body.
    const bool still = b.velocity.x == 0 && b.velocity.y == 0 && b.acceleration.x == 0 && b.acceleration.y == 0 &&
                       !b.stepped;
    if (moving) {
      if (b.acceleration.x == 0 && b.acceleration.y == 0) {
        // |v| + |a| dt with a = 0 is |v| = sqrt(v.v); sqrt is correctly rounded and monotone, so the
        // largest of them is the square root of the largest v.v, one root a step instead of one a body.
        straightSpeedSquared = std::max(straightSpeedSquared, dot(b.velocity, b.velocity));
      } else {
        speedScale = std::max(speedScale, length(b.velocity) + length(b.acceleration) * dt);
      }
    }
    if (b.type == BodyType::Static) continue;
    Box path = moving ? pathBox(b.position, b.velocity, b.acceleration, dt) : Box{b.position, b.position};
    if (b.stepped) {
      // The island's solve (after the sweep) adds the step's gravity and pushes: room for the path
      // with gravity and for twice that speed.
      const Vec2 withGravity = b.velocity + w.def.gravity * dt;
      const double reach = (length(b.velocity) + length(withGravity)) * dt;
      path = unionOf(path, pathBox(b.position, withGravity, {}, dt));
      path = Box{path.min - Vec2{reach, reach}, path.max + Vec2{reach, reach}};
    }
    // A sensor takes no part in the collisions (the collision sweep and queries never see one): its box
    // is set by the sweep of the paths after the step (sensor_paths.cpp).
    if (b.diskShape) {
      // One physical circle centred on the body (DiskShape). Moving on a straight line, awake, in no
      // island and sliding on nothing, it is a plain disk: its proxy is tagged with its body, and a
      // candidate pair of two plain disks is predicted from their bodies' first lines and DiskShapes
      // (predictPlainPair), without a look at their fixtures.
      const detail::DiskShape& shape = shapes[i];
      const bool plain = b.type == BodyType::Dynamic && moving && !still && b.acceleration.x == 0 &&
                         b.acceleration.y == 0 && !b.sliding && !b.stepped;
      w.broadPhase.setMoving(shape.fixture, moving && !still);
      Box swept{path.min + Vec2{-shape.radius, -shape.radius}, path.max + Vec2{shape.radius, shape.radius}};
      if (plain && noGravity) {
        // Room around the path for kPlainSlack times the disk's own speed in any direction: a disk
        // sent off another way by a collision mid-step then mostly stays inside the box the sweep saw,
        // and the broad phase is not asked again for it (repredict). Under gravity the island solves
        // read the sweep's pairs, and get none they did not get before. Only for a disk that moves
        // little in a step for its size (kPlainSlackLimit): a fast one's box is mostly its path, and
        // room all round would multiply its area (and its candidate pairs) many times.
        const double slack = kPlainSlack * std::sqrt(dot(b.velocity, b.velocity)) * dt;
        if (slack <= kPlainSlackLimit * shape.radius) {
          const double reach = shape.radius + slack;
          swept = unionOf(swept, Box{b.position - Vec2{reach, reach}, b.position + Vec2{reach, reach}});
        }
      }
      w.broadPhase.setBox(shape.fixture, shape.radius == 0 ? detail::withRoundOff(swept) : swept);
      w.broadPhase.setTag(shape.fixture, plain ? i : detail::BroadPhase::kNoTag);
      continue;
    }
    for (uint32_t f : b.fixtures) {
      const detail::FixtureSlot& fixture = w.fixtures[f];
      if (fixture.sensor) continue;
      w.broadPhase.setMoving(f, moving && !still);
      const Box box{path.min + fixture.localBox.min, path.max + fixture.localBox.max};
      w.broadPhase.setBox(f, detail::isPoint(fixture.geometry) ? detail::withRoundOff(box) : box);
      w.broadPhase.setTag(f, detail::BroadPhase::kNoTag);
    }
  }
  startPaths(w);
  return std::max(speedScale, std::sqrt(straightSpeedSquared));

}

// 2 and 3. Candidate pairs and their first predictions; a pair with a stepped body waits for its
// island's solve (deferred).
void HybridStep::predictCandidatePairs(double dt) {
  detail::WorldState& w = w_;
  detail::HybridState& h = h_;
  h.deferred.clear();
  // Without gravity nothing reads the pairs in the order the sweep found them (island solves do), so the
  // broad phase may keep them from step to step.
  w.broadPhase.setPairCache(w.def.gravity.x == 0 && w.def.gravity.y == 0);
  // What a plain pair's report will read (predictPlainPair), asked for ahead of it in two stages: the
  // disk paths and the pair lists' headers kReportAhead pairs ahead, and the lists' ends (whose address
  // is in the header) half as far ahead, from the pairs told kReportAhead / 2 calls ago. On the bench's
  // gas at 10^6 disks this made the whole step about 7% faster (5 of 6 alternating runs).
  constexpr size_t kHalfAhead = detail::BroadPhase::kReportAhead / 2;
  uint32_t toldPairs[kHalfAhead][2];
  for (auto& told : toldPairs) told[0] = told[1] = detail::BroadPhase::kNoTag;
  size_t toldCount = 0;
  auto reportAhead = [&](uint32_t, uint32_t, uint32_t plainA, uint32_t plainB) {
    uint32_t* told = toldPairs[toldCount++ % kHalfAhead];
    if (told[0] != detail::BroadPhase::kNoTag) {
      const auto& pairsA = w.pairsOfBody[told[0]];
      const auto& pairsB = w.pairsOfBody[told[1]];
      __builtin_prefetch(pairsA.data() + pairsA.size(), 1);
      __builtin_prefetch(pairsB.data() + pairsB.size(), 1);
    }
    const bool plain = plainA != detail::BroadPhase::kNoTag && plainB != detail::BroadPhase::kNoTag;
    told[0] = plain ? plainA : detail::BroadPhase::kNoTag;
    told[1] = plainB;
    if (plain) {
      __builtin_prefetch(&w.bodies[plainA]);
      __builtin_prefetch(&w.bodies[plainB]);
      __builtin_prefetch(&w.diskShapes[plainA]);
      __builtin_prefetch(&w.diskShapes[plainB]);
      __builtin_prefetch(&w.pairsOfBody[plainA], 1);
      __builtin_prefetch(&w.pairsOfBody[plainB], 1);
    }
  };
  w.broadPhase.setPairTestBudget(w.pairTestBudget());
  w.broadPhase.findPairs([&](uint32_t fa, uint32_t fb, uint32_t plainA, uint32_t plainB) {
    if (plainA != detail::BroadPhase::kNoTag && plainB != detail::BroadPhase::kNoTag) {
      predictPlainPair(fa, fb, plainA, plainB, dt);
      return;
    }
    if (canCollide(w, fa, fb)) {
      ++w.stats.candidatePairs;
      addPair(fa, fb);
      // Predict with a dynamic body's circle first (the time-of-impact functions' moving side); of two
      // dynamic ones, the lower fixture, so that the contact's last bits (computed from that side) do
      // not depend on the order in which the sweep meets the pair.
      const bool aMoves = w.bodyOf(fa).type == BodyType::Dynamic;
      const bool bMoves = w.bodyOf(fb).type == BodyType::Dynamic;
      const bool aFirst = aMoves && (!bMoves || fa < fb);
      const uint32_t own = aFirst ? fa : fb, other = aFirst ? fb : fa;
      // A stepped body's path is known once its island is solved.
      if (w.bodyOf(fa).stepped || w.bodyOf(fb).stepped) {
        h.deferred.push_back({own, other});
      } else {
        predict(own, other, 0, dt);
      }
    }
  }, reportAhead);
}

// Stepped islands (island.cpp): gravity and the solve, then the predictions that wait for them.
void HybridStep::startIslandsAndPredict(double dt) {
  detail::WorldState& w = w_;
  detail::HybridState& h = h_;
  std::vector<uint32_t>& freed = h.islandFreed;
  h.islands.startIslands(dt, freed);
  for (uint32_t i : h.islands.stepped) w.recordPath(i, 0);
  for (uint32_t i : freed) w.recordPath(i, 0);
  for (const auto& p : h.deferred) predict(p.own, p.other, 0, dt);
  // A stepped body the solve sent out of the box the sweep saw is asked about again; contacts found so
  // are solved in turn.
  for (uint32_t i : h.islands.stepped) {
    const BodySlot& b = w.bodies[i];
    const Box path = pathBox(b.position, b.velocity, b.acceleration, dt);
    for (uint32_t f : b.fixtures) {
      if (w.fixtures[f].sensor) continue;
      const Box box{path.min + w.fixtures[f].localBox.min, path.max + w.fixtures[f].localBox.max};
      if (!w.broadPhase.box(f).contains(box)) {
        repredict(i, 0, dt);
        break;
      }
    }
  }
  h.islands.settleUnsolvedIslandPairs(0, dt);
  for (uint32_t i : h.slidingAtStart) predictSlideEnd(i, 0, dt);
}

bool HybridStep::squeezeAndPredict(const PredictedContact& c, double dt) {
  detail::WorldState& w = w_;
  const uint32_t ia = w.fixtures[c.a].body, ib = w.fixtures[c.b].body;
  const uint32_t countA = w.bodies[ia].collisionCount, countB = w.bodies[ib].collisionCount;
  const size_t squeezesBefore = w.squeezes.size();
  if (!squeezeAt(w, c)) return false;
  // A squeeze changes a body's motion exactly when it moves its collision count; only such a body is
  // predicted again. Setting two bodies to pass through each other changes neither: their queued
  // predictions are still valid (the counts did not move), and predicting them again queued each a
  // second time, whose exempt pairs, met again, queued theirs. Units made at one point, all overlapping,
  // doubled the queue so, and a step of 200 of them did not return (tests:
  // Squeeze.UnitsMadeAtOnePointPassThroughEachOther). A second prediction of a pair already set to pass
  // through (made before the first came) changes nothing at all: it is stale, not an event.
  const bool movedA = w.bodies[ia].collisionCount != countA, movedB = w.bodies[ib].collisionCount != countB;
  if (w.squeezes.size() == squeezesBefore && !movedA && !movedB) {
    ++w.stats.staleEvents;
    return true;
  }
  ++w.stats.eventsProcessed;
  if (movedA) repredict(ia, c.time, dt);
  if (movedB && w.bodies[ib].type == BodyType::Dynamic) repredict(ib, c.time, dt);
  return true;
}

// 4. Events in time order, up to the step's end or the instant the event budget runs out (returned).
// A predicted contact that no longer approaches (beyond round-off) and that nothing presses: no collision.
// Its tiny approach is absorbed, or the pair is predicted again without the feature it names.
void HybridStep::dismissContact(const PredictedContact& c, double dt, double vn, Vec2 relativeVelocity,
                                        double restTolerance, int& featureRepredictions) {
  detail::WorldState& w = w_;
  const BodySlot& a = w.bodyOf(c.a);
  const BodySlot& b = w.bodyOf(c.b);
  ++w.stats.staleEvents;
  // A jam just settled these two together: what approach is left is its solve's round-off, and
  // absorbing it (or settling the cluster again) would repeat at this instant without end.
  if (h_.islands.settledTogether(w.fixtures[c.a].body, w.fixtures[c.b].body, c.time)) return;
  // Absorbing is pointless (and would repeat forever) when vn is itself the round-off of the
  // velocities, or when the two are at rest relative to each other. The round-off of a relative
  // velocity is that of the two velocities it is the difference of: two disks moving together at
  // 10 units/s cannot have their approach absorbed below about 1e-15.
  const double speed = length(relativeVelocity);
  const double roundOff = length(w.velocityAt(a, c.time)) + length(w.velocityAt(b, c.time));
  if (vn < -detail::kAbsorbRoundOff * roundOff && speed > restTolerance &&
      w.stats.eventsProcessed < w.def.maxEventsPerStep) {
    const uint32_t ia = w.fixtures[c.a].body, ib = w.fixtures[c.b].body;
    // A body that keeps absorbing in one step is in a cluster pressed together at one instant: each
    // absorb leaves its neighbours approaching by round-off again (the alternating projections of an
    // inelastic collapse). A crowd nobody drives, crushed against a wall by a gate, took tens of
    // thousands of them among seven disks, 1e-12 s apart (tests: Squeeze.APistonClosingOnACrowdThat-
    // FillsTheGapPassesOverIt). Past the jam count it jams, as a driven body does.
    const auto caught = [&](uint32_t body) { return h_.absorbs.get(body) > detail::Islands::kJamCollisions; };
    if (h_.islands.settleJamAt(c, dt, caught(ia), caught(ib))) return;
    if (squeezeAndPredict(c, dt)) return;
    // Its approach is below round-off: leaving it moves the pair together by no more than the
    // round-off of their coordinates over the step, and ends a run of absorbs that would not.
    const int absorbLimit =
        std::min<int>(detail::collapseCollisions(w.def.maxEventsPerStep), std::numeric_limits<uint16_t>::max() - 1);
    if (h_.absorbs.get(ia) > absorbLimit || h_.absorbs.get(ib) > absorbLimit) return;
    if (absorb(w, c, vn)) {
      for (uint32_t body : {ia, ib}) {
        if (w.bodies[body].type == BodyType::Dynamic) h_.countAbsorb(body);
      }
    }
    ++w.stats.eventsProcessed;  // bounded by the budget like any other change of motion
    for (uint32_t body : {ia, ib}) {
      if (w.bodies[body].type == BodyType::Dynamic) repredict(body, c.time, dt);
    }
  } else if (speed <= restTolerance && w.stats.eventsProcessed < w.def.maxEventsPerStep &&
             detail::stopPointAtRest(w, c, vn)) {
    ++w.stats.eventsProcessed;
    repredict(w.fixtures[c.a].body, c.time, dt);
  } else if (hasSeveralFeatures(w.fixtures[c.b].geometry) && featureRepredictions < w.def.maxEventsPerStep) {
    // Dropped: but only this feature's contact. The fixture's other features (the wall beyond a
    // box's corner, for a disk sliding along its floor) are still ahead of the body, so the pair is
    // predicted again without this one. Bounded per step like the events, as two features of one
    // fixture could otherwise take turns at one instant.
    ++featureRepredictions;
    // A second feature dropped at the same instant (a body at rest in a corner, touching both
    // walls): both are separating, and so is any other touching then; the features beyond (the far
    // wall a body sliding along the floor runs into) are still predicted. Without this the two took
    // turns at one instant until the step's budget of repredictions ran out, and other bodies' drops
    // went unpredicted (a disk passed through a wall: fuzz/regressions/world_api).
    predict(c.a, c.b, c.time, dt, c.afterDismissal ? kEveryFeature : c.feature);
  }
}

// A collision at c.time: a jam, a squeeze, a join to an island, or resolved as a pair (then the parts of
// their islands that its stepped bodies are in are solved again for the rest of the step).
void HybridStep::collide(const PredictedContact& c, double dt, std::vector<uint32_t>& woken) {
  detail::WorldState& w = w_;
  // A body caught in a collapse or a jam collides ever faster without coming to rest (jam.cpp).
  if (h_.islands.settleJamAt(c, dt)) return;
  // Or between bodies that do not yield (squeeze.cpp).
  if (squeezeAndPredict(c, dt)) return;
  const uint32_t ia = w.fixtures[c.a].body, ib = w.fixtures[c.b].body;
  if (joinsIsland(c, dt)) {
    // It would bounce off slower than restingSpeed from a body that moves: the two rest on each
    // other from now on, in a stepped island (island.cpp), instead of bouncing ever lower.
    const std::array<uint32_t, 2> pair{ia, ib};
    h_.islands.joinIslands(pair, c.time, dt);
    for (uint32_t body : pair) {
      BodySlot& s = w.bodies[body];
      w.keep(s);
      ++s.collisionCount;
      s.lastContactTime = w.time + c.time;
    }
    const int settled = h_.islands.settleAround(pair, 2, c.time, dt, detail::islandKey(c.a, c.b));
    w.stats.eventsProcessed += std::max(1, settled);
    return;
  }
  woken.clear();
  const bool aAsleep = w.bodies[ia].asleep, bAsleep = w.bodies[ib].asleep;
  // Points never jam (jam.cpp: an island's contacts cannot tell a point's side of a face); one driven
  // into a corner of two faces bounces between them at one instant without end, and the predictive
  // mode's Zeno guard puts it to sleep there when the faces hold it up.
  const bool zenoGuard = h_.islands.bodyIsPoint(w.bodies[ia]) || h_.islands.bodyIsPoint(w.bodies[ib]);
  resolve(w, c, woken, zenoGuard, dt);
  ++w.stats.eventsProcessed;
  // A body that has just gone to sleep holds its stepped neighbours from now on: the islands' solve
  // did not see it as fixed, so they keep clear of it for the rest of the step.
  for (const auto& [body, wasAsleep] : {std::pair{ia, aAsleep}, std::pair{ib, bAsleep}}) {
    if (wasAsleep || !w.bodies[body].asleep) continue;
    for (const auto& p : w.pairsOfBody[body]) {
      const uint32_t other = w.fixtures[p.other].body;
      if (!w.bodies[other].stepped) continue;
      h_.islands.settleAround(std::span(&other, 1), 1, c.time, dt);
    }
  }
  // A stepped body hit by a free one moves its island for the rest of the step.
  for (uint32_t body : {ia, ib}) {
    if (!w.bodies[body].stepped) continue;
    // Its neighbours move with it; beyond them the island keeps its paths.
    h_.islands.settleAround(std::span(&body, 1), 1, c.time, dt);
  }
  // A point that keeps meeting a stepped body there meets one that does not yield (squeeze.cpp).
  if (zenoGuard) detail::stopPointAtSteppedBody(w, c, dt);
  for (uint32_t body : woken) {
    if (body != ia && body != ib) repredict(body, c.time, dt, true);
  }
  const bool aWoke = std::find(woken.begin(), woken.end(), ia) != woken.end();
  const bool bWoke = std::find(woken.begin(), woken.end(), ib) != woken.end();
  if (w.bodies[ia].type == BodyType::Dynamic) repredict(ia, c.time, dt, aWoke);
  if (w.bodies[ib].type == BodyType::Dynamic) repredict(ib, c.time, dt, bWoke);
}

// Where a step out of budget stops: the latest instant at which an event changed a body's motion, not the
// time `next` of the event it could not take. At `next` that event's bodies touch and approach; a point's
// place there is off by its speed times the round-off of `next` (2.7e-11 at 1e9 units/s after 1.4e-4 s),
// far more than the slack within which a point counts as on a face, so the next step could read it as
// past the face and let it through. At the last change every body that just met something moves away.
double HybridStep::lastChangeBefore(double next) const {
  double last = 0;
  for (const BodySlot& b : w_.bodies) {
    if (b.alive && b.type == BodyType::Dynamic) last = std::max(last, b.localTime);
  }
  return std::min(last, next);
}

double HybridStep::processEvents(double dt, double approachTolerance) {
  detail::WorldState& w = w_;
  detail::HybridState& h = h_;
  std::vector<uint32_t> woken;
  int featureRepredictions = 0;
  double budgetTime = dt;
  while (!h.queue.empty()) {
    std::pop_heap(h.queue.begin(), h.queue.end(), detail::later);
    const PredictedContact c = h.queue.back();
    h.queue.pop_back();
    // An event reads its two bodies, their pair lists and swept boxes one after another; at 10^6 bodies
    // each is a wait for memory. Asked for together they wait once, and the next event's fixtures (most
    // often the next popped) arrive while this one is handled: about 10% off the events' time there.
    for (const uint32_t f : {c.a, c.b}) {
      const uint32_t body = w.fixtures[f].body;
      const char* slot = reinterpret_cast<const char*>(&w.bodies[body]);
      for (size_t line = 0; line < sizeof(BodySlot); line += 64) __builtin_prefetch(slot + line, 1);
      __builtin_prefetch(&w.pairsOfBody[body]);
      __builtin_prefetch(&w.broadPhase.box(f));
    }
    if (!h.queue.empty()) {
      __builtin_prefetch(&w.fixtures[h.queue.front().a]);
      __builtin_prefetch(&w.fixtures[h.queue.front().b]);
    }
    BodySlot& a = w.bodyOf(c.a);
    const BodySlot& b = w.bodyOf(c.b);
    if (c.kind == detail::EventKind::SlideEnd) {
      if (a.collisionCount != c.countA || !a.sliding) {
        ++w.stats.staleEvents;
        continue;
      }
      w.advance(a, c.time);
      stopSliding(w, a);
      ++a.collisionCount;
      repredict(w.fixtures[c.a].body, c.time, dt);
      continue;
    }
    if (a.collisionCount != c.countA || b.collisionCount != c.countB) {
      ++w.stats.staleEvents;
      continue;
    }
    // The prediction said "approaching". An approach no faster than round-off (below `tolerance`) with
    // nothing pressing the two together is not a collision: it is absorbed (the tiny normal approach is
    // removed, without an event) when the bodies still move, and ignored when they are at rest. Without
    // this, bodies meeting at one instant with restitution below 1 (a light disk caught between two
    // heavy ones, a disk driven into a wedge) trade ever smaller impulses forever.
    const Vec2 relativeVelocity = w.velocityAt(a, c.time) - w.velocityAt(b, c.time);
    const double vn = dot(relativeVelocity, c.normal);
    const bool pressing = detail::pressedTogether(a.acceleration - b.acceleration, c.normal);
    // Also round-off: an approach that closes no more than the round-off of the contact's coordinates
    // within the whole step, which decides when everything is nearly at rest.
    const double restTolerance = detail::kRestRoundOff * (std::fabs(c.point.x) + std::fabs(c.point.y)) / dt;
    const double tolerance = approachTolerance + restTolerance;
    if (!(vn < -tolerance) && !pressing) {
      dismissContact(c, dt, vn, relativeVelocity, restTolerance, featureRepredictions);
      continue;
    }
    if (w.stats.eventsProcessed >= w.def.maxEventsPerStep) {
      w.stats.eventBudgetReached = true;
      budgetTime = lastChangeBefore(c.time);
      break;
    }
    collide(c, dt, woken);
  }
  return budgetTime;
}

void HybridStep::run(double dt, int eventsBefore) {
  detail::WorldState& w = w_;
  detail::HybridState& h = h_;
  w.contactEvents.clear();
  w.sensorEvents.swap(w.pendingSensorEvents);
  w.pendingSensorEvents.clear();
  ++w.stepStamp;
  w.stats = StepStats{};
  w.stats.eventsProcessed = eventsBefore;
  h.queue.clear();
  h.absorbs.clear();
  w.carriedPoints.clear();  // a step that threw (step_undo.cpp) may have left some
  if (w.pairsOfBody.size() < w.bodies.size()) w.pairsOfBody.resize(w.bodies.size());
  if (h.stamp.size() < w.fixtures.size()) h.stamp.resize(w.fixtures.size(), 0);

  const double speedScale = sweepBoxes(dt);
  // Approach speeds below this are round-off: 1e-13 of the fastest speed in the world this step.
  const double approachTolerance = detail::kApproachRoundOff * speedScale;
  predictCandidatePairs(dt);
  if (w.broadPhase.overflowed()) {
    // A degenerate world (bodies piled on one point): its pairs are incomplete, so no body may move.
    // As at the event budget at time 0: everything stays where it is for this step.
    w.stats.eventBudgetReached = true;
    h.queue.clear();
    w.pathLog.active = false;
    for (const BodySlot& b : w.bodies) {
      if (b.alive && b.type == BodyType::Dynamic && b.asleep) ++w.stats.sleeping;
    }
    w.time += dt;
    return;
  }
  startIslandsAndPredict(dt);
  const double budgetTime = processEvents(dt, approachTolerance);
  h.queue.clear();
  const uint32_t bodyCount = static_cast<uint32_t>(w.bodies.size());

  // 5. Everyone to the end of the step; out of budget, to the last change of motion before the event it
  // could not take, a state every resolved event is consistent with (nothing overlaps, nothing has passed
  // through, nothing is about to).
  const double end = w.stats.eventBudgetReached ? budgetTime : dt;
  // 6. Sensor events, from the paths the bodies took (sensor_paths.cpp).
  if (w.pathLog.active) {
    sensePaths(w, w.pathLog, end);
    w.pathLog.active = false;
  }
  h.islands.endIslands(end);
  detail::restoreCarriedPoints(w, end);
  // Nothing from here on allocates: the last pass changes every body without keeping it (step_undo.cpp).
  w.stepStart.keeping = false;
  for (uint32_t i = 0; i < bodyCount; ++i) {
    // As in the first pass, the slots are asked for ahead (only their first line is read and written).
    if (i + kStreamAhead < bodyCount) __builtin_prefetch(&w.bodies[i + kStreamAhead], 1);
    BodySlot& b = w.bodies[i];
    if (!b.alive || !w.moves(b)) continue;
    if (b.type == BodyType::Dynamic) {
      w.moveTo(b, end);  // advance without its keep (above)
      if (b.asleep) ++w.stats.sleeping;
    } else {
      b.position = b.position + b.velocity * end;
    }
    b.localTime = 0;
  }
  w.time += dt;
}

void detail::stepHybrid(WorldState& world, HybridState& state, double dt, int eventsBefore) {
  HybridStep(world, state).run(dt, eventsBefore);
}

namespace {

class HybridStepper final : public detail::Stepper {
 public:
  explicit HybridStepper(detail::WorldState& world) : w_(world), state_(world) {}
  void step(double dt) override {
    state_.islands.beginStep();
    detail::stepHybrid(w_, state_, dt);
  }
  void forget() override { state_.forget(); }
  detail::Islands* islands() override { return &state_.islands; }

 private:
  detail::WorldState& w_;
  detail::HybridState state_;
};

}  // namespace

std::unique_ptr<detail::Stepper> detail::makeHybridStepper(detail::WorldState& world) {
  return std::make_unique<HybridStepper>(world);
}

}  // namespace rattle
