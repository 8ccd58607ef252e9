// The collision response shared by the exact modes and the islands: which feature a prediction takes as
// just resolved (the round-off guard, LastContact), the inelastic absorb of a round-off approach, the
// resolution of a collision (Newton's law with restitution, the round-off clean-up, resting: sleep,
// slide or a bounce at restingSpeed, the collapse guard and the TC model), and the ContactEvent every
// mode reports. The arithmetic of an impulse and of the event is contact/impulse.h's, which the discrete
// step and the predictive mode's plain disks (predictive/plain_collision.h) call on their own data.
#include "contact/response.h"

#include <algorithm>
#include <cmath>
#include <optional>

#include "collision/closest_point.h"
#include "collision/polyline_impact.h"
#include "contact/collapse_guard.h"
#include "contact/impulse.h"
#include "contact/resting.h"
#include "contact/tolerances.h"
#include "world/world_impl.h"

namespace rattle {

using detail::BodySlot;
using detail::PredictedContact;

namespace {

// A point (radius 0) resolved at `now` against a face of something static or kinematic that it remembers
// (Support), meeting another such fixture `other` at that instant: it may sit in the corner between them,
// and which of the other's faces it leaves is told as in a corner of one fixture (featureLeftByPoint).
// A kinematic body's faces are read where it is at `now`, its motion taken out (resting.cpp), as the time
// of impact reads them in its frame.
bool pointJustResolvedBeside(const detail::WorldState& w, const BodySlot& a, uint32_t own, uint32_t other,
                             double now) {
  if (a.last.time != now || a.support.fixture == other || !detail::remembersLiveFace(w, a)) return false;
  if (!a.last.is(own, a.support.fixture, now) || a.last.feature != a.support.feature) return false;
  if (w.bodyOf(a.support.fixture).type == BodyType::Dynamic) return false;
  if (w.bodyOf(other).type == BodyType::Dynamic) return false;
  return detail::isPoint(w.fixtures[own].geometry);
}

// A point (radius 0) that remembers its side of a face of something static or kinematic (Support),
// predicted against another such fixture, when it moves toward that side relative to the face (any face
// of the other on the remembered face's line it leaves too) or lies on the remembered face (in a corner
// between the two, on the other's line as well): which faces of the other it leaves is told by
// featureLeftByPoint.
bool pointBesideRememberedFace(const detail::WorldState& w, const BodySlot& a, uint32_t own, uint32_t other,
                               double now) {
  if (a.support.fixture == other || !detail::remembersLiveFace(w, a)) return false;
  const BodySlot& face = w.bodyOf(a.support.fixture);
  if (face.type == BodyType::Dynamic || w.bodyOf(other).type == BodyType::Dynamic) return false;
  if (!detail::isPoint(w.fixtures[own].geometry)) return false;
  return dot(w.velocityAt(a, now) - face.velocity, a.support.normal) > 0 || detail::pointOnRememberedFace(w, a, now);
}

}  // namespace

// The feature of `other` that `own` cannot be approaching now (TimeOfImpact's resolvedFeature): the
// face its body slides on, the one both bodies of the pair were last resolved on at this instant, or
// (a point) the one it last touched, when it moves away toward the side it touched it from.
int detail::resolvedFeature(const WorldState& w, const BodySlot& a, const BodySlot& b, uint32_t own, uint32_t other,
                            double now) {
  int resolved = kNoFeature;
  // Round-off guard (see LastContact): if every dynamic body of the pair was last resolved against
  // this same pair at this same instant, the feature it touched cannot be approaching now.
  auto resolvedHereNow = [&](const BodySlot& s) {
    return s.type != BodyType::Dynamic || s.last.is(own, other, now);
  };
  const bool lastHere = a.last.time == now && resolvedHereNow(a) && resolvedHereNow(b);
  // A point, not sliding, that remembers its side of a feature of `other` (Support). Asked only on the
  // paths below that need it: most predictions are of disks.
  auto remembersSide = [&] {
    return !a.sliding && a.support.fixture == other && remembersLiveFace(w, a) &&
           detail::isPoint(w.fixtures[own].geometry);
  };
  // A point has no overlap to tell which side of a line it is on (time_of_impact.h); in a corner it is
  // on two lines at once, and which of them it leaves is told by leavesCorner(w).
  const bool point = a.sliding && lastHere && detail::circleRadius(w.fixtures[own].geometry) == 0;
  if (a.sliding && a.support.fixture == other) {
    // Sliding on this fixture: the face it slides on is a constraint; it only matters again if the
    // body leaves it and comes back. A point in the corner of two of its faces, resolved against the
    // other one at this instant and leaving it, leaves both.
    resolved = a.support.feature;
    if (point && a.last.feature != a.support.feature && leavesCorner(w, a, other, a.last.feature, now)) {
      resolved = kEveryFeature;
    } else if (point && a.last.feature == a.support.feature) {
      // It began to slide at this instant, maybe in a corner, on another face's line too, which it may
      // be leaving (featureLeftByPoint). Taken as just arriving there, a point that bounced in the bottom
      // of a V and slid up one face from the joint met the other face at once from below, where
      // round-off put it, and was sent down through it.
      resolved = featureLeftByPoint(w, a, other, now);
    }
  } else if (pointJustResolvedBeside(w, a, own, other, now)) {
    // A corner between two fixtures (two Segments in a V). Taken as just arriving, a point that bounced
    // off one at the joint and moved away from the other met it at once from below and was sent through.
    resolved = featureLeftByPoint(w, a, other, now);
  } else if (lastHere && !(point && !leavesCorner(w, a, other, a.last.feature, now))) {
    resolved = a.last.feature;
    // A point just resolved against the face it now remembers may sit in a corner, on another face's
    // line too, which it may be leaving as well (featureLeftByPoint).
    if (remembersSide() && a.support.feature == resolved) resolved = featureLeftByPoint(w, a, other, now);
  } else if (remembersSide() && dot(w.velocityAt(a, now) - w.velocityAt(b, now), a.support.normal) > 0) {
    // A point lying on a line has no overlap to tell its side, and the time of impact takes it to have
    // just arrived from the side it comes from: one at rest on a floor that the game sends up would be
    // "arriving from below" and bounce down through it (fuzz/regressions/world_api/
    // escape-point-woken-upward-off-a-floor). It last touched this feature from the side `normal`
    // points to, and moves toward that side: it is leaving. (Away from the line this matters to no
    // root: the rule only concerns a contact at this instant.) In a corner it may leave the other
    // face there too (featureLeftByPoint).
    resolved = featureLeftByPoint(w, a, other, now);
  } else if (remembersSide() && pointOnRememberedFace(w, a, now)) {
    // On the remembered face and moving across it, in a corner of the fixture's faces: it meets that face
    // from the side it remembers, and leaves the other face there if it moves to the side where the
    // remembered face lies.
    resolved = featureLeftByPoint(w, a, other, now, false);
  } else if (pointBesideRememberedFace(w, a, own, other, now)) {
    // Another static fixture with a face on the remembered face's line (two boxes made in the same
    // place): the point is on the remembered side of that face too, and leaves it as well. Taken as
    // just arriving there, a point on one box's floor that the game sent up met the other's floor from
    // below and was sent down through both
    // (fuzz/regressions/world_api/escape-predictive-point-between-two-boxes-made-as-one).
    // Or a corner of two Segments, where it rests on the remembered one: sent off across that one, it
    // moves away from the other's line, toward the side the remembered face lies on. Taken as just
    // arriving at the other from outside, it bounced off it out of the container.
    resolved = featureLeftByPoint(w, a, other, now);
  }
  return resolved;
}

namespace {

// Whether `impact` (of `own`, a point, with a face of the static or kinematic `other` at `now`) meets that
// face at once (before the point has moved beyond the round-off of where it is) from the side opposite
// the one the point knows it is on (pointKnowsSideOfFace).
//
// A point on a face's line has no overlap to tell its side, and the time of impact reads it from the
// motion (time_of_impact.cpp): moving along the line, the side its acceleration presses it into;
// moving across it, the side it comes from unless the face was just resolved. A point that knows its
// side of the face knows better, and the face of a body that is not dynamic is never crossed, so a
// contact from the other side at this instant is a misreading. Taken as one, a point squeezed along a
// wall by a disk inside a container met the wall from outside, slid on its outer side and, sent off by
// the game, left the container through it; a point at rest in a corner met the other face there from
// outside and slept on its outer side; and a point bounced off one face of an apex onto the floor it
// remembered, leaving the floor's line 5e-14 s before gravity brought it back, was taken as arriving at
// the floor from below and sent out through it.
bool meetsKnownFaceFromBehind(const detail::WorldState& w, const BodySlot& a, uint32_t own, uint32_t other,
                              double now, const Impact& impact) {
  if (!detail::isPoint(w.fixtures[own].geometry)) return false;
  const BodySlot& b = w.bodyOf(other);
  if (b.type == BodyType::Dynamic) return false;
  // At once: before the point has moved across the face farther than the round-off of where it is.
  // Along the face it may have slid any distance: a point sliding up one face of an apex, out of the
  // corner, 3e-16 on the wrong side of the other face's line (round-off of the corner), met that face
  // 2e-8 s later from outside as gravity pulled it in, and remembered its outer side.
  const Vec2 v = w.velocityAt(a, now) - b.velocity;
  const double t = impact.time;
  const double travel =
      std::fabs(dot(v, impact.normal)) * t + 0.5 * std::fabs(dot(a.acceleration, impact.normal)) * t * t;
  const double roundOff = detail::pointRoundOff(w.positionAt(a, now), impact.point);
  if (travel <= roundOff) {
    Vec2 side;
    if (!detail::pointKnowsSideOfFace(w, a, other, impact.feature, now, side)) return false;
    return dot(impact.normal, side) < 0;
  }
  // A fast point's position carries its time's round-off times its speed, far beyond its coordinates'
  // (a point bouncing between a box's floor and ceiling at 3.8e6 units/s was placed 1.25e-11 below the
  // floor by a bounce off it, met it from below at that instant, was stopped along it as squeezed, and
  // slid out through the box's corner: fuzz/regressions/world_api/escape-hybrid-fast-point-between-floor-
  // and-ceiling). Within that, the face it remembers keeps its remembered side.
  if (!(travel <= roundOff + detail::timeRoundOff(std::fabs(now) + t, length(v)))) return false;
  if (!detail::remembersLiveFace(w, a) || a.support.fixture != other || a.support.feature != impact.feature)
    return false;
  return dot(impact.normal, a.support.normal) < 0;
}

}  // namespace

void detail::dropMisreadFace(const WorldState& w, const BodySlot& a, uint32_t own, uint32_t other, double now,
                             double maxTime, int resolved, std::optional<Impact>& impact) {
  if (!meetsKnownFaceFromBehind(w, a, own, other, now, *impact)) return;
  // The face is asked again as one the point leaves at this instant (the time of impact's resolved
  // feature, read on the side the point moves to, which is the side it knows): it may come back to it
  // later. Left out for the rest of the step, a point that moved up out of a V's corner, the other
  // face's line round-off behind it, was not met when gravity brought it back to that face, and fell
  // out under it. Moving along the face's line the reading is its acceleration's either way: met from
  // behind again, the face is left out (nothing on the known side is met along such a path). In a
  // corner another face may then be met from behind in turn (the point is on both lines), and is read
  // the same way: left to the time of impact, a point in an apex that bounced off one face and slid up
  // the other met that other from outside 3e-8 s later and slept on its outer side.
  const Geometry& gb = w.fixtures[other].geometry;
  const BodySlot& b = w.bodyOf(other);
  const Motion relative{w.velocityAt(a, now) - w.velocityAt(b, now), a.acceleration - b.acceleration};
  const Geometry& ga = w.fixtures[own].geometry;
  const Vec2 at = w.positionAt(a, now), otherAt = w.positionAt(b, now);
  if (const auto* polyline = std::get_if<Polyline>(&gb)) {
    KnownFaces known;
    do {
      const int face = impact->feature;
      const bool again = known.readingOf(face) == KnownFaces::Reading::Resolved;
      if (!known.read(face, again ? KnownFaces::Reading::LeftOut : KnownFaces::Reading::Resolved)) break;
      impact = detail::timeOfImpactPolylineWith(ga, at, *polyline, otherAt, relative, maxTime, resolved, known);
    } while (impact && impact->time < kMisreadWindow && meetsKnownFaceFromBehind(w, a, own, other, now, *impact));
  } else if (std::holds_alternative<Segment>(gb) ||
             (std::holds_alternative<Polygon>(gb) && b.type == BodyType::Kinematic)) {
    // A static Polygon's face met from behind is left to the time of impact: in a corner of a wall
    // polygon on a floor polygon the point bounces between the two faces on the floor's line at one
    // instant and comes to rest there (the Zeno guard), and re-asked, 124 of the 10,368 throws of
    // BodiesInCorners.PointsThrownIntoATiltedBoxFarOutStayIn left the box. A kinematic body's point does
    // not come to rest, and one in that corner of a box 1,000 units out, a round-off beside the wall
    // and moving up off the floor, met the wall's bottom face from below and was sent through the floor.
    impact = fixtureTimeOfImpact(w, own, at, other, otherAt, relative, maxTime, impact->feature);
    if (impact && impact->time < kMisreadWindow && meetsKnownFaceFromBehind(w, a, own, other, now, *impact))
      impact.reset();
  }
}

std::optional<Impact> detail::pointSegmentTimeOfImpact(const WorldState& w, uint32_t own, Vec2 positionOwn,
                                                       uint32_t other, Vec2 positionOther,
                                                       const Motion& relativeMotion, double maxTime, int resolved) {
  const Geometry& ga = w.fixtures[own].geometry;
  const Geometry& gb = w.fixtures[other].geometry;
  const detail::SegmentNeighbours& neighbours = w.segmentNeighbours[other];
  if (!neighbours.any()) return timeOfImpact(ga, positionOwn, gb, positionOther, relativeMotion, maxTime, resolved);
  return timeOfImpactSegmentWith(ga, positionOwn, std::get<Segment>(gb), positionOther, relativeMotion, maxTime,
                                 resolved, neighbours);
}

namespace {

// A point (radius 0) sliding on a face that a movable body's impulse would push into that face stays on
// it: the face holds it at this same instant, so the impulse moves it only along the face, with the
// effective inverse mass (1/m) (1 - (n.f)^2) for the face's normal f (a bead on a wire; the face, static,
// does no work). Left to a second contact at this instant, the face's own, a point, which has no overlap
// to tell which side of the line it is on, read as leaving the face and fell through
// (fuzz/regressions/world_api/escape-point-inside-a-disk-that-overlaps-the-floor). A disk's overlap
// tells it, and its face's own contact resolves it as before: holding disks too moved the piles' pinned
// hashes and raised rattle-soak's worst pile overlap from 0 to 0.4% of a radius. Against what cannot
// move (a corner) a point's slide ends as before (leavesCorner). The impulse j >= 0 pushes a along n and
// b against it.
struct FaceHold {
  detail::PairImpulse impulse;
  bool heldA = false, heldB = false;
};

// The geometries are looked at only for a sliding body: most contacts have none.
// `againstStatic`: a point's approach to another face of a corner that absorb() takes out is taken along
// its own face as well (the other face does not move, so the impulse does no work either way), unless
// the two faces are parallel to within kParallelFaces (a point between two walls that overlap, their
// faces on one line), where no impulse along the face reaches the other. Taken along the other face's
// normal, the absorbed approach left a point sliding on a floor a velocity of 1.7e-13 across it: it slid
// on for ten steps and reached the far corner of its Polyline 3.7e-13 below the floor's line, beyond the
// round-off by which the next face reaches past the joint, passed under the joint and left the box.
constexpr double kParallelFaces = 1e-3;
FaceHold holdOnFaces(const BodySlot& a, double inverseA, const Geometry& ga, const BodySlot& b, double inverseB,
                     const Geometry& gb, Vec2 n, bool againstStatic = false) {
  FaceHold h{detail::PairImpulse::alongNormal(n, inverseA, inverseB)};
  auto hold = [&](const BodySlot& s, double inverse, const Geometry& g, double otherInverse, double side,
                  Vec2& direction, double& effective, bool& held) {
    if (!s.sliding || !(inverse > 0) || !(side * dot(n, s.support.normal) < 0)) return;
    if (!(otherInverse > 0) && !(againstStatic && std::fabs(cross(n, s.support.normal)) > kParallelFaces)) return;
    if (!detail::isPoint(g)) return;
    direction = n - s.support.normal * dot(n, s.support.normal);
    effective = inverse * dot(direction, n);
    held = true;
  };
  hold(a, inverseA, ga, inverseB, 1.0, h.impulse.directionA, h.impulse.effectiveA, h.heldA);
  hold(b, inverseB, gb, inverseA, -1.0, h.impulse.directionB, h.impulse.effectiveB, h.heldB);
  // Pushed straight into both faces, neither can take the impulse along them: left to the faces' own
  // contacts as before.
  if (!(h.impulse.inverseSum() > 0)) h = FaceHold{detail::PairImpulse::alongNormal(n, inverseA, inverseB)};
  return h;
}

}  // namespace

bool detail::absorb(WorldState& w, const PredictedContact& c, double vn) {
  BodySlot& a = w.bodyOf(c.a);
  BodySlot& b = w.bodyOf(c.b);
  w.advance(a, c.time);
  w.advance(b, c.time);
  const double inverseA = a.asleep ? 0.0 : a.inverseMass;
  const double inverseB = b.asleep ? 0.0 : b.inverseMass;
  if (!(inverseA + inverseB > 0)) return false;
  const FaceHold hold = holdOnFaces(a, inverseA, w.fixtures[c.a].geometry, b, inverseB, w.fixtures[c.b].geometry,
                                    c.normal, /*againstStatic=*/true);
  hold.impulse.apply(a.velocity, b.velocity, -vn / hold.impulse.inverseSum());
  const detail::LastContact last{std::min(c.a, c.b), std::max(c.a, c.b), c.feature, c.time};
  for (BodySlot* s : {&a, &b}) {
    if (s->type != BodyType::Dynamic) continue;
    ++s->collisionCount;
    s->setLast(last);
  }
  rememberFace(w, c);
  return true;
}

// A point's side of a feature of what cannot move (Support): kept at each contact with it.
void detail::rememberFace(WorldState& w, const PredictedContact& c) {
  BodySlot& a = w.bodyOf(c.a);
  if (a.type != BodyType::Dynamic || w.bodyOf(c.b).type == BodyType::Dynamic) return;
  if (!detail::isPoint(w.fixtures[c.a].geometry)) return;
  a.rememberFace(detail::Support{c.b, w.fixtures[c.b].generation, c.feature, c.normal});
}

ContactEvent detail::contactEventOf(const WorldState& w, uint32_t a, uint32_t b, double time, Vec2 point, Vec2 normal,
                                    double impulse) {
  auto side = [&](uint32_t f) {
    const uint32_t body = w.fixtures[f].body;
    return detail::ContactSide{f, w.fixtures[f].generation, body, w.bodies[body].generation};
  };
  return detail::makeContactEvent(time, point, normal, impulse, side(a), side(b));
}

namespace {

// Whether the other body of `body`'s last contact cannot move (static, kinematic or asleep): resolved
// against it, `body` stays resolved whatever else changes its own velocity at that instant.
bool lastPartnerHolds(const detail::WorldState& w, uint32_t body) {
  const BodySlot& partner = w.bodyOf(w.lastPartnerFixture(body));
  return partner.type != BodyType::Dynamic || partner.asleep;
}

// Whether a point on a static face meets, at contact `holderFixture` (whose normal toward the point is
// `toward`), something at rest on that face's side: a sleeping or static body whose normal opposes the
// face's, so that the point is caught in the cusp between the two (at the foot of a disk asleep on the
// floor). Each contact's own impulse then drives it into the other. On the face: sliding on it, or,
// where gravity does not press it in (a wall it falls along), lying on the static face it remembers.
bool inCusp(const detail::WorldState& w, const BodySlot& point, uint32_t pointFixture, uint32_t holderFixture,
            Vec2 toward, double now) {
  if (!detail::isPoint(w.fixtures[pointFixture].geometry)) return false;
  const bool onFace = point.sliding || (detail::pointOnRememberedFace(w, point, now) &&
                                        w.bodyOf(point.support.fixture).type == BodyType::Static);
  if (!onFace) return false;
  if (point.support.fixture == holderFixture) return false;
  const BodySlot& holder = w.bodyOf(holderFixture);
  if (holder.type != BodyType::Static && !holder.asleep) return false;
  return dot(toward, point.support.normal) < 0;
}

// The stepped side of an impulse p along n (a's when aStepped, else b's) taken across gravity g only: n
// with its part along g taken out, a level push that a straight path keeps without gaining height.
void levelSteppedSide(detail::PairImpulse& p, bool aStepped, Vec2 n, Vec2 g) {
  const Vec2 across = n - g * (dot(n, g) / dot(g, g));
  if (aStepped) {
    p.directionA = across;
    p.effectiveA = p.inverseA * dot(across, n);
  } else {
    p.directionB = across;
    p.effectiveB = p.inverseB * dot(across, n);
  }
}

// Where only the straight paths of a stepped body and a point held on its face (holdOnFaces) approach
// (resolve() says why), the impulse that stops that approach, with no bounce, and how it acts; nothing
// for other pairs, or when neither way below keeps the energy at the step's end from rising.
//  - Held: the stepped body holds, as a kinematic one would, and the point alone stops its approach
//    along its face (holdOnFaces against what does not move). The stepped body's path stays as it is,
//    so its island need not be solved again. Refused where the point would speed up (caught from
//    behind).
//  - Level: the stepped body takes its share across gravity only, as the contacts of its island that
//    hold it up would take the rest (a stepped body is held, or it would fall free). Its potential energy
//    at the step's end is then untouched, and the pair's kinetic energy does not rise when the stepped
//    body's velocity has no part along gravity (a disk its island holds on a floor).
// The energy at the step's end: the point's kinetic energy, and the stepped body's along its straight
// path for the rest of the step, tau, potential included.
struct SteppedResponse {
  FaceHold hold;
  bool steppedHolds = false;  // Held: the stepped body takes nothing
};
std::optional<SteppedResponse> steppedPathResponse(const detail::WorldState& w, const BodySlot& a, uint32_t fixtureA,
                                                   const BodySlot& b, uint32_t fixtureB, Vec2 n, double t,
                                                   double vn, double stepEnd) {
  if (a.stepped == b.stepped || !(vn == 0) || a.asleep || b.asleep || !(stepEnd >= t)) return std::nullopt;
  const Vec2 g = w.def.gravity;
  if (g == Vec2{}) return std::nullopt;
  const Vec2 va = w.velocityAt(a, t), vb = w.velocityAt(b, t);
  const double straight = dot(va - vb, n);
  if (!(straight < 0)) return std::nullopt;
  const double tau = stepEnd - t;
  auto rises = [&](const detail::PairImpulse& p) {
    if (!(p.inverseSum() > 0)) return true;
    const double j = -straight / p.inverseSum();
    auto gain = [&](const BodySlot& s, Vec2 v, Vec2 change) {
      if (change == Vec2{}) return 0.0;
      const double kinetic = s.mass * (dot(v, change) + 0.5 * dot(change, change));
      return s.stepped ? kinetic - s.mass * dot(g, change) * tau : kinetic;
    };
    const double total = gain(a, va, p.directionA * (j * p.inverseA)) + gain(b, vb, p.directionB * (-j * p.inverseB));
    return !(total <= 0);
  };
  const Geometry& ga = w.fixtures[fixtureA].geometry;
  const Geometry& gb = w.fixtures[fixtureB].geometry;
  SteppedResponse held{holdOnFaces(a, a.stepped ? 0.0 : a.inverseMass, ga, b, b.stepped ? 0.0 : b.inverseMass, gb, n,
                                   /*againstStatic=*/true),
                       true};
  if ((a.stepped ? held.hold.heldB : held.hold.heldA) && !rises(held.hold.impulse)) return held;
  SteppedResponse level{holdOnFaces(a, a.inverseMass, ga, b, b.inverseMass, gb, n)};
  if (!(a.stepped ? level.hold.heldB : level.hold.heldA)) return std::nullopt;
  detail::PairImpulse& p = level.hold.impulse;
  levelSteppedSide(p, a.stepped, n, g);
  if (rises(p)) return std::nullopt;
  return level;
}

// The impulse resolve() gives a pair in the form `p`, on copies of their velocities: Newton's bounce from
// vn, then what keeps the straight paths from still approaching (keepSeparating).
double impulseOf(const detail::PairImpulse& p, Vec2& va, Vec2& vb, Vec2 n, double vn, double e) {
  double j = p.bounce(va, vb, vn, e);
  p.keepSeparating(va, vb, n, j);
  return j;
}

// A free body's hit that lifts a stepped body, which moves on a straight line with the step's gravity
// taken at its start: a lift mid-step is never taken back, and the pair can end the step above the energy
// it had. The stepped body takes its share across gravity only (as steppedPathResponse's level case
// does), where that adds no kinetic energy to the pair, when the free body is a point, or when
// keepSeparating tops the impulse up past -2 vn / (1/ma + 1/mb), the bound below which an impulse cannot
// gain (resolve() says why); the free body takes the rest as Newton's law has it.
// - A point sliding on a floor into the foot of a disk made through it lifted the stepped disk, which
//   kept rising for the rest of the step (fuzz/regressions/world_api/energy-hybrid-point-lifts-a-stepped-
//   disk-made-through-a-floor, and -point-meets-a-heavy-disk-sliding-through-a-floor, -point-slides-
//   into-the-foot-of-a-sunk-disk). Not for every free body: a disk landing on a pile meets its stepped
//   bodies from above, and the level response there made the predictive pile of 1,000 take 1.66x the
//   time (bench/README.md, Piles).
// - Where the parabola reads no approach (vn 0) and the straight paths do, keepSeparating gives all of the
//   impulse: a point rising into the foot of a disk sunk in a floor, and a small disk under a large one
//   coming down on it in a box, bounced between it and the floor at one instant, lifted the stepped disk
//   so (fuzz/regressions/world_api/energy-predictive-point-rises-into-a-sunk-disk, energy-hybrid-small-
//   disks-and-a-large-one-in-a-polyline-box).
std::optional<FaceHold> levelLift(const detail::WorldState& w, const BodySlot& a, uint32_t fixtureA, const BodySlot& b,
                                  uint32_t fixtureB, Vec2 n, double t, double vn, double e, double stepEnd,
                                  const FaceHold& hold) {
  const Vec2 g = w.def.gravity;
  if (a.stepped == b.stepped || a.asleep || b.asleep || !(stepEnd >= t) || g == Vec2{}) return std::nullopt;
  if (a.type != BodyType::Dynamic || b.type != BodyType::Dynamic) return std::nullopt;
  // The stepped body's direction, as the impulse moves it (a takes +j, b takes -j).
  const Vec2 moves = a.stepped ? hold.impulse.directionA : -hold.impulse.directionB;
  if (!(dot(moves, g) < 0) || !((a.stepped ? hold.impulse.inverseA : hold.impulse.inverseB) > 0)) return std::nullopt;
  const Vec2 va = w.velocityAt(a, t), vb = w.velocityAt(b, t);
  if (!detail::isPoint(w.fixtures[a.stepped ? fixtureB : fixtureA].geometry)) {
    Vec2 ua = va, ub = vb;
    const double j = impulseOf(hold.impulse, ua, ub, n, vn, e);
    // Past the bound by more than the round-off of the velocities keepSeparating reads.
    const double roundOff = detail::kApproachRoundOff * (length(va) + length(vb));
    if (!(j * hold.impulse.inverseSum() > -2 * vn + roundOff)) return std::nullopt;
  }
  FaceHold level = hold;
  detail::PairImpulse& p = level.impulse;
  levelSteppedSide(p, a.stepped, n, g);
  if (!(p.inverseSum() > 0)) return std::nullopt;
  Vec2 ua = va, ub = vb;
  if (!(impulseOf(p, ua, ub, n, vn, e) > 0)) return std::nullopt;
  const double gain = a.mass * (dot(ua, ua) - dot(va, va)) + b.mass * (dot(ub, ub) - dot(vb, vb));
  if (!(gain <= 0)) return std::nullopt;
  return level;
}

}  // namespace

void detail::resolve(WorldState& w, const PredictedContact& c, std::vector<uint32_t>& woken, bool zenoGuard,
                     double stepEnd) {
  const uint32_t ia = w.fixtures[c.a].body, ib = w.fixtures[c.b].body;
  BodySlot& a = w.bodies[ia];
  BodySlot& b = w.bodies[ib];
  w.advance(a, c.time);
  w.advance(b, c.time);
  placePointOnFace(w, a, c);
  const Vec2 n = c.normal;  // from b toward a
  // A stepped body moves on a straight line with the whole step's gravity taken at its start
  // (island.cpp), so its velocity all step is the one it ends the step with; a free body meeting it
  // mid-step meets a body that has taken g (stepEnd - t) ahead of the parabola it stands in for. With
  // the stepped one on that parabola, the normal velocity is vp, and an impulse j along n changes the
  // pair's energy at the step's end by j vp + j^2 / (2 mu): never a gain while 0 <= j <= -2 mu vp.
  // Newton's impulse from the straight velocities, -(1 + e) mu vs, overstepped that when the stepped body
  // came down onto the free one (vs faster than vp): the free disk under it slid off faster than it came
  // (fuzz/regressions/world_api/energy-predictive-free-disk-meets-a-stepped-one). From the slower of
  // the two approaches, it never does. The path stays the straight one: the last loop below keeps that
  // from still approaching.
  // A body stepped since the step's start is read a third way, on the parabola it began the step on (its
  // velocity then plus g t), before its island's first solve: that solve may have handed it a speed that
  // the island pays for and a free body does not. A disk sunk through a floor, a heavy disk pressing it
  // down, was squeezed out sideways at 17 times the heavy one's fall; a point it met took that speed as its
  // approach and left with energy the island's own check never saw
  // (fuzz/regressions/world_api/energy-hybrid-point-meets-a-disk-sunk-through-a-floor). The slowest of
  // the three readings is taken (impactNormalVelocity).
  // A contact predicted as "pressing" (touching, not moving apart, pushed together by gravity) may read
  // as slightly separating after round-off: treat it as touching.
  auto approach = [&] { return std::min(impactNormalVelocity(w, ia, ib, n, c.time, stepEnd), 0.0); };
  double vn = approach();

  // A sleeping body holds like a static one against soft hits; a harder hit, or a kinematic body,
  // wakes it (and whatever it holds up) first. Not past the squeeze count of both in the step: a light
  // body asleep in a corner, struck by a far heavier point falling onto it, was woken, driven into the
  // corner, put to sleep there and struck again, 3e-16 s a round, while the point kept its speed to six
  // digits, until the step's 20,000 events ran out
  // (fuzz/regressions/world_api/budget-hybrid-light-disk-on-a-floor-under-a-falling-point). What holds
  // it holds the point then, which rests on it or bounces off at restingSpeed.
  const double restingSpeed = w.def.restingSpeed;
  const auto wakes = [&](const BodySlot& sleeper, const BodySlot& other) {
    if (other.type == BodyType::Kinematic) return true;
    const bool caught = sleeper.stepCollisions > w.kSqueezeCollisions && other.stepCollisions > w.kSqueezeCollisions;
    return -vn > restingSpeed && !caught;
  };
  if (a.asleep && wakes(a, b)) wakeUp(w, ia, c.time, woken);
  if (b.asleep && wakes(b, a)) wakeUp(w, ib, c.time, woken);
  // The predictive mode's guard against a Zeno sequence, after the wakes (a body woken here and already
  // caught in one sleeps again at once); the hybrid step resolves such clusters at once instead (jam.cpp).
  // A body put to sleep here stops where it is: the approach is the other body's alone from then on.
  // Taken from before the stop, it handed the other body the sleeper's speed as well, and a disk wedged
  // against a resting one sent it off faster than it came in
  // (fuzz/regressions/world_api/energy-predictive-zeno-sleeper-kicks-its-neighbour).
  if (zenoGuard) {
    sleepIfZeno(w, ia, c.time, n, ib);
    sleepIfZeno(w, ib, c.time, -n, ia);
    vn = approach();
  }
  // Where the stepped body's straight path approaches the free body but the parabola it stands in for
  // does not (vn is 0), an impulse along n gains: j vp + j^2 / (2 mu) > 0 for vp >= 0. Sliding on a
  // floor under a stepped disk that an island held on that floor, a point lifted the disk, which then
  // rose the rest of the step with no gravity to take it back
  // (fuzz/regressions/world_api/energy-predictive-point-sliding-under-a-stepped-disk); a stepped disk
  // sliding along the floor into such a point from behind was lifted likewise
  // (fuzz/regressions/world_api/energy-predictive-stepped-disk-catches-a-sliding-point). There the pair
  // stops its straight approach, with no bounce, in a way that does not gain (steppedPathResponse).
  const std::optional<SteppedResponse> stepped = steppedPathResponse(w, a, c.a, b, c.b, n, c.time, vn, stepEnd);
  const bool steppedHolds = stepped && stepped->steppedHolds;
  const double inverseA = a.asleep || (steppedHolds && a.stepped) ? 0.0 : a.inverseMass;
  const double inverseB = b.asleep || (steppedHolds && b.stepped) ? 0.0 : b.inverseMass;
  const double inverseSum = inverseA + inverseB;
  if (stepped) vn = dot(w.velocityAt(a, c.time) - w.velocityAt(b, c.time), n);
  if (!(inverseSum > 0)) {
    // Put to sleep on this contact: a point rests on the face it arrived at, and remembers its side
    // (Support) as a resolved contact would. Still remembering the face it bounced off before, in the
    // apex of a V where it came to rest on the other face's line, a point that the game sent off that
    // line into the V was taken as arriving from outside and sent out through the face.
    if (zenoGuard) rememberFace(w, c);
    return;
  }

  // Newton's restitution law along the normal: the separation speed after is e times the approach
  // speed, with e the larger of the two fixtures' restitutions. j = (separation - vn) / (1/ma + 1/mb);
  // static, kinematic and sleeping bodies have 1/m = 0.
  const double now = w.time + c.time;
  // The collapse guard without gravity (collapse_guard.h); under gravity the stepped islands and jams
  // hold such clusters instead.
  bool collapsing = false;
  if (w.def.gravity.x == 0 && w.def.gravity.y == 0) {
    const int limit = detail::collapseCollisions(w.def.maxEventsPerStep);
    const bool aCollapsing = a.type == BodyType::Dynamic && a.countStepCollision() > limit;
    const bool bCollapsing = b.type == BodyType::Dynamic && b.countStepCollision() > limit;
    collapsing = aCollapsing || bCollapsing;
  }
  const bool rapid =
      collapsing || now - a.lastContactTime < w.def.collapseTime || now - b.lastContactTime < w.def.collapseTime;
  const double e = stepped ? 0.0
                   : rapid  ? 1.0
                            : std::max(w.fixtures[c.a].restitution, w.fixtures[c.b].restitution);
  double separation = -e * vn;
  FaceHold hold = stepped ? stepped->hold
                          : holdOnFaces(a, inverseA, w.fixtures[c.a].geometry, b, inverseB,
                                        w.fixtures[c.b].geometry, n);
  if (!stepped) {
    if (const std::optional<FaceHold> level = levelLift(w, a, c.a, b, c.b, n, c.time, vn, e, stepEnd, hold))
      hold = *level;
  }
  double j = hold.impulse.bounce(a.velocity, b.velocity, vn, e);

  // Resting (resting.cpp): only when gravity presses the two together, so that a slow bounce would
  // turn into a Zeno sequence.
  const bool pressing = detail::pressedTogether(a.acceleration - b.acceleration, n);
  BodySlot* slider = nullptr;  // a body that starts sliding on this contact keeps that slide
  if (restingSpeed > 0 && pressing && separation < restingSpeed) {
    // The body that rests is the one that can move, against one that cannot.
    const bool aRests = inverseA > 0 && inverseB == 0;
    const bool bRests = inverseB > 0 && inverseA == 0;
    const uint32_t rester = aRests ? ia : ib;
    const uint32_t holderFixture = aRests ? c.b : c.a;
    BodySlot& r = w.bodies[rester];
    // Not a body that this step's start parts from another (separation.cpp): asleep, it would stay on it.
    const bool mayRest = (aRests || bRests) && length(r.velocity) < restingSpeed &&
                         !std::binary_search(w.beingParted.begin(), w.beingParted.end(), rester);
    if (mayRest && supportsAt(w, rester, c.time, w.supporters, aRests ? n : -n, w.fixtures[holderFixture].body)) {
      putToSleep(w, rester, w.supporters);
    } else if (mayRest && leansOnSlowNeighbour(w, rester, c.time, w.supporters)) {
      // Held with a slow awake disk: it sleeps on that disk as a point in a cusp does, and wakes at the
      // next step's start unless the disk is asleep by then (wakeSleepersOfMovingBodies); the disk, held
      // now, sleeps at its next contact with it or with its own holders.
      sleepOnAwakeBodies(w, rester, w.supporters);
    } else if ((aRests || bRests) && w.bodies[w.fixtures[holderFixture].body].type == BodyType::Static &&
               isFlatFeature(w, holderFixture, c.feature) && aRests) {
      startSliding(w, rester, holderFixture, c.feature, n);
      slider = &r;
      j = -vn / inverseSum;
    } else if ((aRests || bRests) && inCusp(w, r, aRests ? c.a : c.b, holderFixture, aRests ? n : -n, c.time)) {
      // Bounced off at restingSpeed, a point that slid along a floor into the foot of a disk asleep on
      // it went into the floor, slid back into the disk at once, and so on at one instant until the
      // step's budget of a million events ran out. It keeps what meets both contacts, nothing here:
      // pressed into the cusp, it rests in it, and wakes with what holds it. So too a point falling
      // down a wall into the cusp of a disk asleep against it: bounced off the disk into the wall and
      // back, 1.3e-13 s apart, it went 4e-13 deeper each time, until the step's budget of 20,000 events
      // ran out (fuzz/regressions/world_api/budget-hybrid-point-falls-into-a-disk-asleep-on-a-wall).
      const Vec2 toward = aRests ? n : -n;  // from the holder toward the point
      const Vec2 before = r.velocity;
      r.velocity = detail::nearestVelocityMeeting(r.velocity, r.support.normal, toward, 0.0);
      // The bounce above is already applied: the impulse is its and this change's together. Only what
      // takes the point farther from the holder is this contact's; what takes it back toward the holder
      // is the face's, which stops the bounce (reported as this contact's, it made the event's impulse
      // negative: fuzz/regressions/world_api/events-hybrid-point-at-a-disk-touching-a-wall).
      j += std::max(0.0, dot(r.velocity - before, toward)) / (aRests ? inverseA : inverseB);
      if (length(r.velocity) < restingSpeed) {
        w.supporters.clear();
        const uint32_t holder = w.fixtures[holderFixture].body;
        if (w.bodies[holder].type == BodyType::Dynamic) w.supporters.push_back(holder);
        putToSleep(w, rester, w.supporters);
      } else if (r.sliding) {
        slider = &r;  // it slides on along its face, away from the cusp
      }
    } else if (!stepped) {
      // Bounce off at restingSpeed at least: bounded bounce rate instead of a Zeno sequence.
      const double extra = (restingSpeed - separation) / hold.impulse.inverseSum();
      hold.impulse.apply(a.velocity, b.velocity, extra);
      j += extra;
      separation = restingSpeed;
    }
  }

  hold.impulse.keepSeparating(a.velocity, b.velocity, n, j);

  const detail::LastContact last{std::min(c.a, c.b), std::max(c.a, c.b), c.feature, c.time};
  for (BodySlot* s : {&a, &b}) {
    if (s->type != BodyType::Dynamic) continue;
    ++s->collisionCount;
    // A body that starts to slide here has the face as its support, which its predictions already
    // leave out; what it was resolved against earlier at this same instant stays its last contact when
    // that cannot move either. A point sliding into a corner of two Segments is on the wall's line when
    // it lands on the floor: the wall, forgotten, would read as just arrived from outside and push it
    // out. A body that moves is another matter: the slide has just changed this body's velocity, so the
    // earlier pair may approach again. Kept as resolved, a disk landing on one that rests in a corner
    // was never resolved against it again and sank through it (predictive), or into it step after step
    // (hybrid).
    // A disk has its overlap to tell its side of that earlier face, and the slide may turn it back into
    // it: in an acute corner of two Segments a disk resolved against one wall, then landing on the
    // other and sliding down it into the first, was taken as leaving the first and slid out through it.
    const bool keepsEarlier = s == slider && s->last.time == c.time && lastPartnerHolds(w, s == &a ? ia : ib) &&
                              detail::isPoint(w.fixtures[s == &a ? c.a : c.b].geometry);
    if (!keepsEarlier) s->setLast(last);
    s->lastContactTime = now;
    // Any other contact ends a slide: the body either leaves the face or is pushed into it, and then
    // the face's own contact (touching and approaching: now) resolves that, resting rules included.
    const bool held = (s == &a && hold.heldA) || (s == &b && hold.heldB);
    if (s->sliding && s != slider && !held) stopSliding(w, *s);
    keepSlidingPointOnFace(w, *s, s == &a ? c.a : c.b);
  }
  rememberFace(w, c);

  w.contactEvents.push_back(contactEventOf(w, c.a, c.b, c.time, c.point, n, j));
}

}  // namespace rattle
