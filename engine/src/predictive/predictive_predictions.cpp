// The predictive step's predictions: each tracked body's next event (a collision or a cell crossing),
// found among the bodies of the cells around it.
// Part of the predictive step's Engine (predictive_engine.h); predictive_step.cpp's opening comment
// describes the mode as a whole.
#include "predictive/predictive_engine.h"
#include "predictive/predictive_engine_inl.h"

namespace rattle::predictive {

void Engine::crossing(const Predicting& p, double& h, int& side) const {
  const Vec2 c = p.position + p.centre;
  const Vec2 v = p.velocity;
  const Vec2 a = p.acceleration;
  const double s = s_.cellSize, d = s_.hysteresis;
  const int32_t x = p.cold->cx, y = p.cold->cy;
  h = kInf;
  side = -1;
  auto keep = [&](double t, int k) {
    if (t < h) {
      h = t;
      side = k;
    }
  };
  if (x > -kMaxCoord) keep(exitTime(c.x - (s_.x0 + x * s - d), v.x, 0.5 * a.x), 0);
  if (x < kMaxCoord) keep(exitTime((s_.x0 + (x + 1.0) * s + d) - c.x, -v.x, -0.5 * a.x), 1);
  if (y > -kMaxCoord) keep(exitTime(c.y - (s_.y0 + y * s - d), v.y, 0.5 * a.y), 2);
  if (y < kMaxCoord) keep(exitTime((s_.y0 + (y + 1.0) * s + d) - c.y, -v.y, -0.5 * a.y), 3);
}

// When, from `now`, the centre of circle or point `own` leaves `polygon` (fixture `other`), which it lies
// inside by more than its coordinates' round-off, along the pair's relative path: the first time it
// crosses an edge's line outward. +infinity when it is not inside or never leaves.
double Engine::centreExit(uint32_t own, uint32_t other, const Polygon& polygon, double now) const {
  const Geometry& g = w_.fixtures[own].geometry;
  const auto* circle = std::get_if<Circle>(&g);
  const auto* point = std::get_if<Point>(&g);
  if (circle == nullptr && point == nullptr) return kInf;
  const BodySlot& a = w_.bodyOf(own);
  const BodySlot& b = w_.bodyOf(other);
  const Vec2 pb = w_.positionAt(b, now);
  const Vec2 centre = w_.positionAt(a, now) + (circle != nullptr ? circle->center : point->position);
  const Vec2 v = w_.velocityAt(a, now) - w_.velocityAt(b, now), acc = a.acceleration - b.acceleration;
  const size_t n = polygon.points.size();
  double exit = kInf;
  for (size_t i = 0; i < n; ++i) {
    const Vec2 p = polygon.points[i] + pb, e = polygon.points[(i + 1) % n] - polygon.points[i];
    const double length = std::sqrt(dot(e, e));
    if (!(length > 0)) continue;
    const Vec2 outward{e.y / length, -e.x / length};  // counter-clockwise points
    const double gap = -dot(outward, centre - p);
    if (!(gap > detail::pointRoundOff(centre, pb, p))) return kInf;  // outside this edge's line, or on it
    exit = std::min(exit, exitTime(gap, -dot(outward, v), -0.5 * dot(outward, acc)));
  }
  return exit;
}

void Engine::predictPair(uint32_t own, uint32_t other, double now, double horizon, PredictiveEvent& best,
                            int dismissed) {
  // the hybrid step's HybridStep::predict, up to the body's horizon instead of the step's end.
  attachFixture(own);
  attachFixture(other);
  const BodySlot& a = w_.bodyOf(own);
  const BodySlot& b = w_.bodyOf(other);
  ++w_.stats.timeOfImpactTests;
  const int resolved = dismissed != kNoFeature ? dismissed : resolvedFeature(w_, a, b, own, other, now);
  const auto impact = predictImpact(w_, a, b, own, other, now, horizon - now, resolved);
  // A centre inside a polygon has no side to be held to (README, Geometry), and its time of impact sees
  // nothing; once the centre is out the polygon holds the body again. Predictions outlive the step here,
  // so the instant the centre leaves is an event of its own (the body predicted again there, as at a
  // horizon): a disk made with its centre in a floor block, rising out of it and falling back before a
  // cell crossing came, fell through the block (fuzz/regressions/world_api/inside-predictive-disk-
  // rises-out-of-a-block-and-falls-back).
  if (const auto* polygon = std::get_if<Polygon>(&w_.fixtures[other].geometry)) {
    const double exit = centreExit(own, other, *polygon, now);
    // (Only when the clock moves on: an exit sooner than its round-off would be the same instant again.)
    if (exit < kInf && now + exit > now && now + exit < std::min(horizon, impact ? now + impact->time : kInf)) {
      const PredictiveEvent e{now + exit, own, own, -1, 0, PredictiveKind::Cross, PredictiveState::kNone, {}, {}};
      if (earlier(e, best)) best = e;
      return;
    }
  }
  if (!impact) return;
  // A pair made overlapping passes through from now on, with no event (as in HybridStep::predict): its
  // event, and the predictions of both bodies again that it cost, made a wave made at one point cubic.
  if (impact->time == 0 && exemptIfMadeOverlapping(w_, own, other, now)) return;
  const Vec2 vb = w_.velocityAt(b, now);
  const double h = impact->time;
  const double time = std::min(now + h, horizon);
  if (time > best.time) return;
  const Vec2 travelOfB = vb * h + b.acceleration * (0.5 * h * h);
  const PredictiveEvent e{time,
                          own,
                          other,
                          impact->feature,
                          b.collisionCount,
                          PredictiveKind::Contact,
                          s_.slotOfBody[w_.fixtures[other].body],
                          impact->point + travelOfB,
                          impact->normal};
  if (earlier(e, best)) best = e;
}

[[gnu::always_inline]] inline
void Engine::predictCircles(const Predicting& p, uint32_t j, double horizon, PredictiveEvent& best) {
  // Two single-circle dynamic bodies, from their copies: the same arithmetic as predictPair through the
  // dispatcher (timeOfImpact's circle-circle entry), with a cheap rejection of receding pairs first.
  const HotBody& a = *p.hot;
  const HotBody& b = s_.hot[j];
  if ((a.flags | b.flags) & HotBody::kCustomFilter) {
    // canCollide() (the bodies differ, are dynamic and physical): the filters.
    const detail::RareBody& ca = s_.rare[p.slot];
    const detail::RareBody& cb = s_.rare[j];
    if (ca.group != 0 && ca.group == cb.group) return;
    if ((ca.categoryBits & cb.maskBits) == 0 || (cb.categoryBits & ca.maskBits) == 0) return;
  }
  if ((a.flags & HotBody::kDismissals) && isDismissed(p.slot, a.fixture, b.fixture)) return;
  const double now = p.now;
  ++w_.stats.timeOfImpactTests;
  const Vec2 accB = accelerationOf(b, s_.rare[j]);
  const Vec2 centreB = (b.flags & HotBody::kOffCentre) ? s_.rare[j].centre : Vec2{};
  const Vec2 pb = positionAt(b, accB, now);
  const Vec2 vb = velocityAt(b, accB, now);
  const Motion relative{p.velocity - vb, p.acceleration - accB};
  Circle circleA{p.centre + p.position, a.radius};
  circleA.center -= pb;
  const Circle circleB{centreB, b.radius};
  const double maxTime = horizon - now;
  if (relative.acceleration == Vec2{}) {
    // A straight relative path: no impact unless approaching (r.v < 0; time_of_impact.cpp's
    // timeToReach), and none before c / (-2 r.v) (|r + v t|^2 - reach^2 >= c + 2 (r.v) t).
    const Vec2 r = circleA.center - circleB.center;
    const double rv = dot(r, relative.velocity);
    if (!(rv < 0)) return;
    const double reach = circleA.radius + circleB.radius;
    const double c = dot(r, r) - reach * reach;
    if (c > 0 && c > -2 * rv * maxTime * (1 + 1e-9)) return;
  }
  const ColdBody& ca = *p.cold;
  const ColdBody& cb = s_.cold[j];
  // detail::resolvedFeature() from the copies: both bodies' last contact is this pair, at this instant.
  int resolved = kNoFeature;
  if (ca.lastTime == now) {
    const uint32_t low = std::min(a.fixture, b.fixture), high = std::max(a.fixture, b.fixture);
    if (ca.lastLow == low && ca.lastHigh == high && cb.lastTime == now && cb.lastLow == low && cb.lastHigh == high) {
      resolved = ca.lastFeature;
    }
  }
  auto impact = timeOfImpactCircleCircle(circleA, relative, circleB, maxTime, resolved);
  if (!impact) return;
  if (impact->time == 0) {
    // As in predictPair: a pair made overlapping passes through, with no event.
    attach(p.slot);
    attach(j);
    if (exemptIfMadeOverlapping(w_, a.fixture, b.fixture, now)) return;
  }
  const double h = impact->time;
  const double time = std::min(now + h, horizon);
  if (time > best.time) return;
  impact->point += pb;
  const Vec2 travelOfB = vb * h + accB * (0.5 * h * h);
  const PredictiveEvent e = contactEvent(time, a.fixture, b, j, impact->feature, impact->point + travelOfB, impact->normal);
  if (earlier(e, best)) best = e;
}

void Engine::startPrediction(uint32_t i, double now, Prediction& q) const {
  // The body's earliest event from `now` on. A moving body looks at everything near it up to its cell
  // crossing (or a horizon), after which it is predicted again anyway. A body at rest has no crossing:
  // it looks at each moving neighbour up to that neighbour's own next event, when the neighbour is
  // predicted again and sees it; with nothing due it holds no event (and costs nothing).
  const HotBody& hb = s_.hot[i];
  const ColdBody& cb = s_.cold[i];
  Predicting& p = q.p;
  p.slot = i;
  p.now = now;
  p.hot = &hb;
  p.cold = &cb;
  p.acceleration = accelerationOf(hb, s_.rare[i]);
  p.position = positionAt(hb, p.acceleration, now);
  p.velocity = velocityAt(hb, p.acceleration, now);
  p.centre = (hb.flags & HotBody::kOffCentre) ? s_.rare[i].centre : Vec2{};
  q.moving = isMoving(hb);
  q.hasDismissals = dismissals(i);
  q.single = (hb.flags & HotBody::kSingle) != 0;
  // A pair exempt from collisions (squeeze.cpp) is skipped by pairWith() only: pairPlain() does not look.
  q.plain = isPlain(hb) && !q.hasDismissals && w_.squeezes.empty();
  PredictiveEvent& best = q.best;
  best = PredictiveEvent{};
  best.time = kInf;
  best.a = best.b = hb.fixture;
  best.feature = -1;
  if (q.moving || s_.movingKinematic) {
    double h = kInf;
    int side = -1;
    if (q.moving) crossing(p, h, side);
    best.kind = PredictiveKind::Cross;
    if (h < kInf) {
      best.feature = side;
      best.time = now + h;
    } else {
      best.time = now + s_.capTime;
    }
  }
  q.horizon = best.time;
}

void Engine::pairWith(Prediction& q, uint32_t j, double until) {
  const uint32_t i = q.p.slot;
  ++w_.stats.candidatePairs;
  // (A pair of dynamic bodies may be exempt, passing through each other: squeeze.cpp. Rare: the fast
  // path below does not look.)
  if (q.single && (s_.hot[j].flags & HotBody::kSingle) && w_.squeezes.empty()) {
    predictCircles(q.p, j, until, q.best);
    return;
  }
  forEachPhysical(i, [&](uint32_t f) {
    forEachPhysical(j, [&](uint32_t g) {
      if (!canCollide(w_, f, g) || (q.hasDismissals && isDismissed(i, f, g))) return;
      if (!w_.squeezes.empty() && squeezeExempt(w_, f, g)) return;
      predictPair(f, g, q.p.now, until, q.best);
    });
  });
}

[[gnu::always_inline]] inline void Engine::pairPlain(Prediction& q, uint32_t j) {
  // pairWith() and predictCircles() for two plain bodies (isPlain(), the predicted one without dismissals),
  // the moving one's neighbour up to its horizon: the same expressions with the zero acceleration and
  // centre written in, so the same values, without the branches on flags and the call per pair. A scene
  // of plain disks (a gas) pays only for this.
  const Predicting& p = q.p;
  const HotBody& b = s_.hot[j];
  ++w_.stats.candidatePairs;
  ++w_.stats.timeOfImpactTests;
  const double now = p.now;
  const Vec2 pb = positionAt(b, Vec2{}, now);
  const Vec2 vb = velocityAt(b, Vec2{}, now);
  const Motion relative{p.velocity - vb, p.acceleration - Vec2{}};
  Circle circleA{p.centre + p.position, p.hot->radius};
  circleA.center -= pb;
  double within;
  {
    // As predictCircles: a straight relative path, approaching, and close enough to meet in time (no
    // impact before c / (-2 r.v)).
    const Vec2 r = circleA.center - Vec2{};
    const double rv = dot(r, relative.velocity);
    if (!(rv < 0)) return;
    // An impact is kept only if no later than the best so far (q.best): the search stops at searchBound.
    within = searchBound(q.horizon, q.best.time, now);
    const double reach = circleA.radius + b.radius;
    const double c = dot(r, r) - reach * reach;
    if (c > 0 && c > -2 * rv * within * (1 + 1e-9)) return;
  }
  // As predictCircles, with the neighbour's ColdBody read only when the pair is the body's own last
  // contact (the neighbour's record is a cache miss more often than not).
  const ColdBody& ca = *p.cold;
  int resolved = kNoFeature;
  if (ca.lastTime == now) {
    const uint32_t low = std::min(p.hot->fixture, b.fixture), high = std::max(p.hot->fixture, b.fixture);
    if (ca.lastLow == low && ca.lastHigh == high) {
      const ColdBody& cb = s_.cold[j];
      if (cb.lastTime == now && cb.lastLow == low && cb.lastHigh == high) resolved = ca.lastFeature;
    }
  }
  auto impact = timeOfImpactCircleCircle(circleA, relative, Circle{Vec2{}, b.radius}, within, resolved);
  if (!impact) return;
  if (impact->time == 0) {
    // As in predictPair: a pair made overlapping passes through, with no event.
    attach(p.slot);
    attach(j);
    if (exemptIfMadeOverlapping(w_, p.hot->fixture, b.fixture, now)) return;
  }
  const double h = impact->time;
  const double time = std::min(now + h, q.horizon);
  PredictiveEvent& best = q.best;
  if (time > best.time) return;
  impact->point += pb;
  const Vec2 travelOfB = vb * h + Vec2{} * (0.5 * h * h);
  const PredictiveEvent e =
      contactEvent(time, p.hot->fixture, b, j, impact->feature, impact->point + travelOfB, impact->normal);
  if (earlier(e, best)) best = e;
}

void Engine::finishPrediction(Prediction& q) {
  // Static fixtures, kinematic bodies and the slide's end; then the event goes into the queue. A pair
  // whose boxes, swept up to the horizon, stay clearly apart cannot meet before it: its time of impact
  // (a search along both paths, the costliest test there is against a polygon that moves) is not sought.
  // A cell lists every static fixture within half a cell of it, and every prediction sees every kinematic
  // fixture, so most are that far.
  const uint32_t i = q.p.slot;
  const double now = q.p.now, horizon = q.horizon;
  // The body's swept box (all its physical fixtures' boxes in one), worked out once, when first needed.
  std::optional<Box> swept;
  auto ownBox = [&] {
    if (!swept) {
      Box local{{kInf, kInf}, {-kInf, -kInf}};
      forEachPhysical(i, [&](uint32_t f) { local = unionOf(local, w_.fixtures[f].localBox); });
      swept = sweptBox(local, q.p.position, q.p.velocity, q.p.acceleration, horizon - now);
    }
    return *swept;
  };
  if (q.moving && (q.p.hot->flags & HotBody::kStaticNear)) {
    const size_t cell = cellOf(i);
    for (uint32_t k = s_.staticBegin[cell]; k < s_.staticBegin[cell + 1]; ++k) {
      const uint32_t g = s_.staticList[k];
      forEachPhysical(i, [&](uint32_t f) {
        if (!canCollide(w_, f, g)) return;
        const int dismissed = q.hasDismissals ? dismissedFeature(i, f, g) : kNotDismissed;
        if (dismissed == kWholePair) return;
        if (clearlyApart(ownBox(), w_.worldBox(g))) return;
        predictPair(f, g, now, horizon, q.best, dismissed == kNotDismissed ? kNoFeature : dismissed);
      });
    }
  }
  for (uint32_t g : s_.kinematicFixtures) {
    const BodySlot& kinematic = w_.bodyOf(g);
    if (!q.moving && kinematic.velocity == Vec2{}) continue;
    const Box theirs = sweptBox(w_.fixtures[g].localBox, w_.positionAt(kinematic, now), w_.velocityAt(kinematic, now),
                                kinematic.acceleration, horizon - now);
    forEachPhysical(i, [&](uint32_t f) {
      if (!canCollide(w_, f, g)) return;
      const int dismissed = q.hasDismissals ? dismissedFeature(i, f, g) : kNotDismissed;
      if (dismissed == kWholePair) return;
      if (!w_.squeezes.empty() && squeezeExempt(w_, f, g)) return;
      if (clearlyApart(ownBox(), theirs)) return;
      predictPair(f, g, now, horizon, q.best, dismissed == kNotDismissed ? kNoFeature : dismissed);
    });
  }
  if (q.p.hot->flags & HotBody::kSliding) {
    attach(i);
    const BodySlot& b = w_.bodies[s_.bodyOfSlot[i]];
    const double until = q.moving ? horizon : now + s_.capTime;
    if (const auto t = slideEndTime(w_, b, now, until)) {
      const PredictiveEvent e{std::min(*t, until), b.fixtures.front(), b.support.fixture, b.support.feature, 0,
                              PredictiveKind::SlideEnd};
      if (earlier(e, q.best)) q.best = e;
    }
  }
  if (q.best.kind == PredictiveKind::None) {
    unschedule(i);
  } else {
    schedule(i, q.best);
  }
  if (i == popped_) popped_ = PredictiveState::kNone;
}

void Engine::predictBody(uint32_t i, double now) {
  if (predictsPlain(i)) {
    predictPlain(i, now);
    return;
  }
  // The neighbours are gathered first, which asks for their records (forEachNeighbour), so that they
  // arrive while the body's own motion and cell crossing are worked out.
  std::vector<uint32_t>& neighbours = s_.neighbours;
  gatherNeighbours(i, neighbours);
  Prediction q;
  startPrediction(i, now, q);
  if (q.plain && q.moving) {
    for (uint32_t j : neighbours) {
      if (isPlain(s_.hot[j])) {
        pairPlain(q, j);
      } else {
        pairWith(q, j, q.horizon);
      }
    }
  } else if (q.moving) {
    for (uint32_t j : neighbours) pairWith(q, j, q.horizon);
  } else {
    for (uint32_t j : neighbours) {
      // A neighbour without an event is at rest too, or is about to be predicted (and then sees this).
      if (j == popped_ || s_.event[j].kind == PredictiveKind::None || !isMoving(s_.hot[j])) continue;
      pairWith(q, j, std::max(s_.event[j].time, now));
    }
  }
  finishPrediction(q);
}

[[gnu::always_inline]] inline
void Engine::crossingStraight(Vec2 c, Vec2 v, const ColdBody& cell, double& h, int& side) const {
  // crossing() for a centre `c` moving in a straight line at `v`: exitTime() with no acceleration leaves
  // each side's time infinite unless the centre moves toward that side, so at most one side of each axis
  // has a finite time. The same arguments and the same tie rule (the first side in 0..3 wins), so the
  // same values.
  const double s = s_.cellSize, d = s_.hysteresis;
  const int32_t x = cell.cx, y = cell.cy;
  auto leave = [](double gap, double speed) { return gap <= 0 ? 0.0 : gap / speed; };  // exitTime, A = 0, b < 0
  // One axis: the centre's coordinate, its speed, the cell's index and origin on that axis, and the
  // axis's low side's number (the high side's is the next).
  auto axis = [&](double centre, double speed, int32_t cellIndex, double origin, int lowSide, double& time,
                  int& which) {
    time = kInf;
    which = -1;
    if (speed < 0) {
      if (cellIndex > -kMaxCoord) {
        time = leave(centre - (origin + cellIndex * s - d), -speed);
        which = lowSide;
      }
    } else if (-speed < 0) {
      if (cellIndex < kMaxCoord) {
        time = leave((origin + (cellIndex + 1.0) * s + d) - centre, -(-speed));
        which = lowSide + 1;
      }
    }
  };
  axis(c.x, v.x, x, s_.x0, 0, h, side);
  double t;
  int k;
  axis(c.y, v.y, y, s_.y0, 2, t, k);
  if (t < h) {
    h = t;
    side = k;
  }
}

void Engine::predictPlain(uint32_t i, double now) {
  // predictBody() for a moving plain body without dismissals in a plain world, where every neighbour is
  // a plain disk too (plainWorld_; no acceleration anywhere): pairPlain() over the neighbours with
  // everything the general path carries from pair to pair (the Prediction, the best event, the bound
  // `within`) kept in registers, and the contact point and normal worked out once, for the earliest
  // impact (plain_disk_impact.h). The same arithmetic and the same total order of events as
  // predictBody(), so the same event, bit for bit (tests/test_predictive_plain.cpp).
  uint32_t found[kNeighbourBuffer];
  const size_t count = gatherNeighbours(i, found, kNeighbourBuffer);
  predictPlainAmong(i, now, found, count);
}

void Engine::predictPlainAmong(uint32_t i, double now, const uint32_t* neighbours, size_t count) {
  // predictPlain() with the neighbours gathered already (into a buffer of kNeighbourBuffer: a longer
  // list is gathered again here).
  if (count > kNeighbourBuffer) {
    gatherNeighbours(i, s_.neighbours);
    neighbours = s_.neighbours.data();
  }
  const HotBody& hb = s_.hot[i];
  const ColdBody& cb = s_.cold[i];
  const Vec2 position = positionAt(hb, Vec2{}, now);
  const Vec2 velocity = velocityAt(hb, Vec2{}, now);
  const Vec2 centre = Vec2{} + position;  // the circle's centre (Predicting: centre + position)
  double h;
  int side;
  crossingStraight(centre, velocity, cb, h, side);
  const double horizon = h < kInf ? now + h : now + s_.capTime;

  // The best so far: the crossing, or a contact with neighbour impact.partner at `bestTime`.
  double bestTime = horizon;
  PlainImpact impact;
  // No impact later than this can beat the best (searchBound).
  double within = searchBound(horizon, bestTime, now);
  const double radius = hb.radius;
  const uint32_t fixture = hb.fixture;
  const bool lastNow = cb.lastTime == now;
  w_.stats.candidatePairs += static_cast<int>(count);
  w_.stats.timeOfImpactTests += static_cast<int>(count);
  // The neighbour's motion at `now` and the pair's relative motion, both coordinates at once (two lanes
  // of one register, each lane the scalar expression of positionAt, velocityAt and dot, so the same
  // values).
  using Lanes = double __attribute__((vector_size(16)));
  auto lanes = [](Vec2 a) { return Lanes{a.x, a.y}; };
  const Lanes zero{0.0, 0.0};  // the zero acceleration's terms, kept: 0 * x is not always +0
  const Lanes ownCentre = lanes(centre), ownVelocity = lanes(velocity);
  struct Relative {
    Lanes pb, vb, v, r;
    double rv, c, reach;
  };
  auto relative = [&](const HotBody& b) {
    Relative m;
    const double dt = now - b.localTime;
    const Lanes step{dt, dt};
    const double half = 0.5 * dt * dt;
    m.pb = (lanes(b.position) + lanes(b.velocity) * step) + zero * Lanes{half, half};
    m.vb = lanes(b.velocity) + zero * step;
    m.v = ownVelocity - m.vb;
    m.r = ownCentre - m.pb;
    const Lanes rv = m.r * m.v, rr = m.r * m.r;
    m.rv = rv[0] + rv[1];
    m.reach = radius + b.radius;
    m.c = (rr[0] + rr[1]) - m.reach * m.reach;
    return m;
  };
  // Two passes. The first, without a branch per pair (whether a pair approaches is a coin toss that
  // the branch predictor loses half the time), keeps the pairs that approach and can meet within the
  // bound as it stands at the start; the second takes them in order with the bound as it tightens. The
  // bound only tightens, so a pair dropped by the first would have been dropped by the second: the
  // pairs whose time of impact is sought are pairPlain()'s.
  // (A crowd beyond the buffer goes to the second pass whole.)
  const bool filtered = count <= kNeighbourBuffer;
  uint32_t kept[kNeighbourBuffer];
  size_t keptCount = 0;
  if (filtered) {
    // The second pass's test, -2 rv within (1 + 1e-9) < c, with a bound a little looser (and worked
    // out once): what it drops, the second pass would have dropped too.
    const double reachLimit = -2 * within * (1 + 4e-9);
    for (size_t k = 0; k < count; ++k) {
      const Relative m = relative(s_.hot[neighbours[k]]);
      const bool far = (m.c > 0) & (m.c > m.rv * reachLimit);
      kept[keptCount] = static_cast<uint32_t>(k);
      keptCount += (m.rv < 0) & !far;
    }
  }
  const size_t tested = filtered ? keptCount : count;
  for (size_t q = 0; q < tested; ++q) {
    const size_t k = filtered ? kept[q] : q;
    const uint32_t j = neighbours[k];
    const HotBody& b = s_.hot[j];
    const Relative m = relative(b);
    const double rv = m.rv;
    if (!(rv < 0)) continue;
    const Vec2 r{m.r[0], m.r[1]}, v{m.v[0], m.v[1]};
    const Vec2 pb{m.pb[0], m.pb[1]}, vb{m.vb[0], m.vb[1]};
    const double reach = m.reach;
    const double c = m.c;
    if (c > 0 && c > -2 * rv * within * (1 + 1e-9)) continue;
    // The LastContact guard: the pair is both bodies' last contact, resolved at this instant.
    const bool justResolved = lastNow && plainJustResolved(cb, fixture, j, now);
    double t;
    if (!detail::plainTimeToReach(r, c, rv, v, reach, within, justResolved, t)) continue;
    const double time = std::min(now + t, horizon);
    if (time > bestTime) continue;
    if (time == bestTime && impact.partner != PredictiveState::kNone &&
        !beatsHeldContact(time, fixture, b, impact.partner)) {
      continue;
    }
    // (A contact at the crossing's time comes first: Contact < Cross in the order.)
    bestTime = time;
    impact = PlainImpact{j, t, r, v, pb, vb};
    within = searchBound(horizon, bestTime, now);
  }
  finishPlain(i, now, position, velocity, horizon, h, side, bestTime, impact);
}

[[gnu::always_inline]] inline
bool Engine::plainJustResolved(const ColdBody& own, uint32_t fixture, uint32_t other, double now) const {
  const uint32_t otherFixture = s_.hot[other].fixture;
  const uint32_t low = std::min(fixture, otherFixture), high = std::max(fixture, otherFixture);
  if (own.lastLow != low || own.lastHigh != high) return false;
  const ColdBody& o = s_.cold[other];
  return o.lastTime == now && o.lastLow == low && o.lastHigh == high && own.lastFeature == 0;
}

bool Engine::beatsHeldContact(double time, uint32_t fixture, const HotBody& b, uint32_t held) const {
  // The contacts differ in the partner only.
  PredictiveEvent e, h;
  e.time = h.time = time;
  e.kind = h.kind = PredictiveKind::Contact;
  e.a = h.a = fixture;
  e.b = b.fixture;
  e.countB = b.collisionCount;
  h.b = s_.hot[held].fixture;
  h.countB = s_.hot[held].collisionCount;
  return earlier(e, h);
}

[[gnu::always_inline]] inline
void Engine::finishPlain(uint32_t i, double now, Vec2 position, Vec2 velocity, double horizon, double h, int side,
                         double bestTime, const PlainImpact& impact) {
  const HotBody& hb = s_.hot[i];
  const ColdBody& cb = s_.cold[i];
  const uint32_t fixture = hb.fixture;

  // The cell crossing, unless a contact comes first: one or the other, each built in its own branch
  // (the crossing built first and then overwritten by the contact was stored twice).
  PredictiveEvent best;
  if (impact.partner == PredictiveState::kNone) {
    best = PredictiveEvent{horizon, fixture, fixture, h < kInf ? side : -1, 0, PredictiveKind::Cross};
  } else {
    const HotBody& b = s_.hot[impact.partner];
    Vec2 point, normal;
    detail::plainContact(impact.r, impact.v, b.radius, impact.time, point, normal);
    point += impact.pb;
    const Vec2 travelOfB = impact.vb * impact.time + Vec2{} * (0.5 * impact.time * impact.time);
    best = contactEvent(bestTime, fixture, b, impact.partner, 0, point + travelOfB, normal);
  }
  if ((hb.flags & (HotBody::kStaticNear | HotBody::kSliding)) == 0 && s_.kinematicFixtures.empty()) {
    // Nothing else to look at (finishPrediction()): into the queue.
    schedule(i, best);
    if (i == popped_) popped_ = PredictiveState::kNone;
    return;
  }
  Prediction q;
  q.p.slot = i;
  q.p.now = now;
  q.p.hot = &hb;
  q.p.cold = &cb;
  q.p.position = position;
  q.p.velocity = velocity;
  q.moving = true;
  q.single = true;
  q.plain = true;
  q.horizon = horizon;
  q.best = best;
  finishPrediction(q);
}

void Engine::fillPairs(uint32_t i) {
  // The body's candidate pairs, for the resting rules (detail::supportsAt reads them).
  auto& pairs = w_.pairsOfBody[s_.bodyOfSlot[i]];
  pairs.clear();
  auto add = [&](uint32_t f, uint32_t g) {
    if (canCollide(w_, f, g)) pairs.push_back({f, g});
  };
  forEachNeighbour(i, [&](uint32_t j) {
    forEachPhysical(i, [&](uint32_t f) { forEachPhysical(j, [&](uint32_t g) { add(f, g); }); });
  });
  const size_t cell = cellOf(i);
  for (uint32_t k = s_.staticBegin[cell]; k < s_.staticBegin[cell + 1]; ++k) {
    forEachPhysical(i, [&](uint32_t f) { add(f, s_.staticList[k]); });
  }
  for (uint32_t g : s_.kinematicFixtures) {
    forEachPhysical(i, [&](uint32_t f) { add(f, g); });
  }
}

}  // namespace rattle::predictive
