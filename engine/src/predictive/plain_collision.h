// Private: the predictive mode's collision of two plain disks (one circle on the body's centre, the
// default filter), resolved on the compact copies (HotBody, ColdBody) instead of the two
// BodySlots and FixtureSlots, which are written back later (the engine's attach()).
//
// It is detail::resolve() (contact/response.cpp) for the case the predictive mode takes it in
// when the world has no gravity, no sensors and nobody asleep: no wake-ups, no Zeno guard (it counts only
// under gravity), no resting rules (they need gravity pressing the pair together), no slides. What is
// left is the same arithmetic (contact/impulse.h, which both call), so the same bits: Newton's law along
// the normal with
// e = max of the two restitutions, or e = 1 within WorldDef::collapseTime of either body's last collision
// (the TC model, Luding & McNamara, Granular Matter 1, 113, 1998); the round-off clean-up that leaves
// the pair not approaching; the LastContact guard.
#pragma once

#include <algorithm>

#include "contact/impulse.h"
#include "predictive/predictive_step.h"
#include "rattle/types.h"

namespace rattle::detail {

// Motion of a hot copy: the same expressions as detail::WorldState::positionAt and velocityAt, so the same
// values.
inline Vec2 positionAt(const HotBody& b, Vec2 acceleration, double t) {
  const double h = t - b.localTime;
  return b.position + b.velocity * h + acceleration * (0.5 * h * h);
}
inline Vec2 velocityAt(const HotBody& b, Vec2 acceleration, double t) {
  return b.velocity + acceleration * (t - b.localTime);
}

struct PlainDisk {
  HotBody& hot;
  ColdBody& cold;
};

struct PlainOutcome {
  double impulse = 0;
  bool resolved = false;  // false: neither body can be pushed (both of infinite mass); nothing changed but the clocks
  bool approachingAfter = false;  // the pair still approaches faster than `tolerance` (the engine drops the guard)
};

// The contact `c` (c.a the fixture of `a`, c.b of `b`; c.normal from b toward a) at step time c.time,
// world time worldTime + c.time.
inline PlainOutcome resolvePlainDisks(PlainDisk a, PlainDisk b, const PredictiveEvent& c, double worldTime,
                                      double collapseTime, double tolerance, int collapseCollisions) {
  const double t = c.time;
  for (HotBody* h : {&a.hot, &b.hot}) {  // detail::WorldState::advance
    h->position = positionAt(*h, Vec2{}, t);
    h->velocity = velocityAt(*h, Vec2{}, t);
    h->localTime = t;
    h->flags = static_cast<uint8_t>(h->flags | HotBody::kDetached);
  }
  Vec2& va = a.hot.velocity;
  Vec2& vb = b.hot.velocity;
  const Vec2 n = c.normal;
  const double vn = std::min(dot(va - vb, n), 0.0);
  const double inverseA = a.cold.inverseMass, inverseB = b.cold.inverseMass;
  const double inverseSum = inverseA + inverseB;
  PlainOutcome out;
  // The predictive step's check after resolve(): velocityAt at the bodies' own (new) local time.
  auto approaching = [&] { return dot(velocityAt(a.hot, Vec2{}, t) - velocityAt(b.hot, Vec2{}, t), n) < -tolerance; };
  if (!(inverseSum > 0)) {
    out.approachingAfter = approaching();
    return out;
  }

  const double now = worldTime + t;
  // resolve()'s collapse guard without gravity (a plain world has none; collapse_guard.h): the counts
  // of this step's collisions, this one included.
  const bool aCollapsing = ++a.cold.stepCollisions > static_cast<uint32_t>(collapseCollisions);
  const bool bCollapsing = ++b.cold.stepCollisions > static_cast<uint32_t>(collapseCollisions);
  const bool rapid = aCollapsing || bCollapsing || now - a.cold.lastContactTime < collapseTime ||
                     now - b.cold.lastContactTime < collapseTime;
  const double e = rapid ? 1.0 : std::max(a.cold.restitution, b.cold.restitution);
  const PairImpulse impulse = PairImpulse::alongNormal(n, inverseA, inverseB);
  double j = impulse.bounce(va, vb, vn, e);
  impulse.keepSeparating(va, vb, n, j);
  const uint32_t low = std::min(c.a, c.b), high = std::max(c.a, c.b);
  for (PlainDisk* d : {&a, &b}) {
    ++d->hot.collisionCount;
    d->cold.lastTime = t;
    d->cold.lastLow = low;
    d->cold.lastHigh = high;
    d->cold.lastFeature = c.feature;
    d->cold.lastContactTime = now;
  }
  out.impulse = j;
  out.resolved = true;
  out.approachingAfter = approaching();
  return out;
}

}  // namespace rattle::detail
