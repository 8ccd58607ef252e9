// The arithmetic of one collision that every mode shares: Newton's restitution impulse along the contact
// normal, the round-off clean-up after it, and the ContactEvent that reports it. resolve() (response.cpp),
// the predictive mode's plain-disk fast path (plain_collision.h) and the discrete mode's reflection
// (discrete_step.cpp) call these instead of writing them out, so the modes cannot drift apart, and the
// fast path stays bit for bit what resolve() would do.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

#include "rattle/types.h"
#include "rattle/vec2.h"

namespace rattle::detail {

/// Where an impulse j along a contact's normal n (from b toward a) acts: a takes +j along directionA and
/// b takes -j along directionB, each scaled by its inverse mass. The directions are n, except for a
/// sliding point held on its face, which takes the impulse along the face (a bead on a wire): then
/// effectiveA (or B) is its inverse mass times directionA . n, and the pair's inverse mass along n is
/// their sum.
struct PairImpulse {
  Vec2 directionA, directionB;
  double inverseA = 0, inverseB = 0;
  double effectiveA = 0, effectiveB = 0;

  /// Both along n: the plain case.
  static PairImpulse alongNormal(Vec2 n, double inverseA, double inverseB) {
    return {n, n, inverseA, inverseB, inverseA, inverseB};
  }
  double inverseSum() const { return effectiveA + effectiveB; }

  void apply(Vec2& va, Vec2& vb, double j) const {
    va += directionA * (j * inverseA);
    vb -= directionB * (j * inverseB);
  }

  /// Newton's law: the impulse that turns the normal velocity vn (< 0: approaching) into a separation of
  /// -e vn, applied to va and vb. Returns it.
  double bounce(Vec2& va, Vec2& vb, double vn, double e) const {
    const double separation = -e * vn;
    const double j = (separation - vn) / inverseSum();
    apply(va, vb, j);
    return j;
  }

  /// With restitution 0 the normal speed after an impulse is zero only up to round-off; the pair is taken
  /// to be separating from then on (LastContact), so it must not be left approaching: up to three more
  /// impulses, each taking out what round-off left, added to j one by one.
  void keepSeparating(Vec2& va, Vec2& vb, Vec2 n, double& j) const {
    for (int k = 0; k < 3; ++k) {
      const double after = dot(va - vb, n);
      if (!(after < 0)) break;
      const double extra = -after / inverseSum();
      apply(va, vb, extra);
      j += extra;
    }
  }
};

/// The nearest to v of the velocities that meet u.f >= 0 and u.n >= target: the exact projection onto the
/// two half-planes is the nearest of v, its projection on either boundary that meets the other, and
/// (when `withCorner`) their corner, u.f = 0 and u.n = target. A candidate on a boundary meets it only to
/// the round-off of the products, on either side; one that misses a constraint by no more than that is
/// moved past it by a few ulps, along the normals it misses where they are acute, else along f/|f| +
/// n/|n| (a move along one of two obtuse normals costs the other product; this gains both alike, by 1 +
/// the cosine of the angle between the normals per unit of the move). Left out, such candidates made the
/// nearest missed, and where zero meets neither constraint nothing was found. (Alternate projections
/// gain no more than that cosine a round, a few parts in a billion in a cusp.) None when no candidate
/// meets both.
inline std::optional<Vec2> nearestOfBoundaryCandidates(Vec2 v, Vec2 f, Vec2 n, double target, bool withCorner) {
  auto meets = [&](Vec2 u) { return dot(u, f) >= 0 && dot(u, n) >= target; };
  if (meets(v)) return v;
  constexpr double ulps = 8 * std::numeric_limits<double>::epsilon();
  const double lf = length(f), ln = length(n);
  const Vec2 inward = f * (1 / lf) + n * (1 / ln);
  const double gain = 1 + dot(f, n) / (lf * ln);
  const auto intoBoth = [&](Vec2 u) {
    for (int k = 0; k < 4 && !meets(u); ++k) {
      // The candidates are made from v: their products carry v's round-off as well as their own.
      const double scale = length(u) + length(v);
      const double slackF = ulps * scale * lf, slackN = ulps * (scale * ln + std::fabs(target));
      const double missF = -dot(u, f), missN = target - dot(u, n);
      if (k == 0 && (missF > slackF || missN > slackN)) break;  // missed by more than round-off
      if (gain >= 1 || gain < 1e-6) {
        // Along the normals missed: where they are acute neither move costs the other product, and
        // where they are opposed to round-off no short move gains both (the move below is the slack
        // over `gain`).
        if (missF > 0) u += f * ((missF + slackF) / (lf * lf));
        if (missN > 0) u += n * ((missN + slackN) / (ln * ln));
      } else {
        u += inward * (std::max((std::max(missF, 0.0) + slackF) / lf, (std::max(missN, 0.0) + slackN) / ln) / gain);
      }
    }
    return u;
  };
  std::optional<Vec2> best;
  double bestDistance = std::numeric_limits<double>::infinity();
  auto consider = [&](Vec2 candidate) {
    const Vec2 u = intoBoth(candidate);
    const Vec2 d = u - v;
    if (meets(u) && dot(d, d) < bestDistance) {
      best = u;
      bestDistance = dot(d, d);
    }
  };
  consider(v - f * (dot(v, f) / dot(f, f)));
  consider(v + n * ((target - dot(v, n)) / dot(n, n)));
  const double det = cross(f, n);
  if (withCorner && det != 0) consider(Vec2{-f.y, f.x} * (target / det));
  return best;
}

/// The velocity nearest v with v.f >= 0 and v.n >= target (target <= 0, so that zero meets both): a body
/// held by two contacts at once that each other's impulse would break, such as a point sliding on a face
/// into the cusp where a disk touches that face (nearestOfBoundaryCandidates). Zero when no candidate
/// meets both: zero meets both and, nearer than v to nothing, never speeds the body up.
inline Vec2 nearestVelocityMeeting(Vec2 v, Vec2 f, Vec2 n, double target) {
  return nearestOfBoundaryCandidates(v, f, n, target, true).value_or(Vec2{});
}

/// The velocity nearest v with v.f >= 0 and v.n >= leave > 0: a body that must leave one contact at
/// `leave` without entering the other, such as a point bounced off a disk beside a face. Zero meets
/// neither: a point on a feather disk 4.6e-13 from a wall, whose corner round-off rejected, got zero,
/// approached the disk again at once and met it every 4.5e-16 s. The corner's speed is leave / |f x n|,
/// so where the normals are within kLeavingSine of parallel (opposed, as in a cusp, or alike) only the two
/// projections are candidates. None when no candidate meets both.
inline constexpr double kLeavingSine = 0.1;
inline std::optional<Vec2> nearestVelocityLeaving(Vec2 v, Vec2 f, Vec2 n, double leave) {
  const bool corner = std::fabs(cross(f, n)) >= kLeavingSine * length(f) * length(n);
  return nearestOfBoundaryCandidates(v, f, n, leave, corner);
}

/// One side of a reported contact: its fixture and body, with their generations at the time.
struct ContactSide {
  uint32_t fixture = 0, fixtureGeneration = 0;
  uint32_t body = 0, bodyGeneration = 0;
};

/// The ContactEvent of a contact between a and b whose normal points from b toward a: A is the side with
/// the lower fixture index, and the event's normal points from A toward B.
inline ContactEvent makeContactEvent(double time, Vec2 point, Vec2 normal, double impulse, const ContactSide& a,
                                     const ContactSide& b) {
  const bool aIsLower = a.fixture < b.fixture;
  const ContactSide& lower = aIsLower ? a : b;
  const ContactSide& upper = aIsLower ? b : a;
  ContactEvent event;
  event.time = time;
  event.point = point;
  event.impulse = impulse;
  event.fixtureA = {lower.fixture, lower.fixtureGeneration};
  event.fixtureB = {upper.fixture, upper.fixtureGeneration};
  event.bodyA = {lower.body, lower.bodyGeneration};
  event.bodyB = {upper.body, upper.bodyGeneration};
  event.normal = aIsLower ? -normal : normal;
  return event;
}

}  // namespace rattle::detail
