// Squeezes: a dynamic body caught between bodies that do not yield.
//
// A kinematic body closing on a dynamic one against a static body (a piston, a gate shutting on a unit),
// or two kinematic bodies closing on it, leave it less and less room: exact events then bounce it between
// the two ever faster (the gap closes at a finite rate, the bounces come at a rate that grows without
// bound), and a step would spend its whole event budget there. Nothing can hold both constraints, so one
// gives: once the body has collided more than kSqueezeCollisions times in a step with things that do not
// yield, its next contact with a kinematic body is a squeeze. The body stops along that contact's normal
// (keeping its motion along the surface), and that kinematic fixture passes over it, the pair exempt
// from collisions until their geometries no longer overlap. Its contacts with static bodies stay, so it
// is never pushed through one. A body wedged between static bodies alone (put in a gap narrower than
// itself) bounces between them at one instant; past the same count it stops moving into the one it
// meets. StepStats::squeezes counts both.
#include "contact/squeeze.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <span>
#include <tuple>

#include "collision/closest_point.h"
#include "contact/impulse.h"
#include "contact/islands.h"
#include "contact/resting.h"
#include "contact/tolerances.h"
#include "world/world_impl.h"

namespace rattle {

using detail::BodySlot;

namespace {
// Two unit normals whose cross product is smaller than this are one face's to round-off.
constexpr double kWedgeAngle = 1e-9;

// "One instant" to two bodies at time t: times closer than either takes to move its coordinates'
// round-off there, which their positions cannot tell apart (0 when neither moves).
double oneInstant(const detail::WorldState& w, const BodySlot& a, const BodySlot& b, double t) {
  const double speed = length(w.velocityAt(a, t)) + length(w.velocityAt(b, t));
  return speed > 0 ? detail::pointRoundOff(w.positionAt(a, t), w.positionAt(b, t)) / speed : 0;
}

// A point and a stepped body it keeps meeting are in a cusp with the face the point remembers when the
// body's normal at the point is within this of the face's, reversed (cos 2.6 degrees), and the point is
// no farther from the face than such a normal leaves it from a body that touches the face, as a
// fraction of the body's radius (1 - cos), plus its coordinates' round-off.
constexpr double kCuspCosine = 0.999;

// A point's signed distance from the face it remembers (which it must), and its coordinates' round-off
// there.
struct FaceGap {
  double distance;
  double roundOff;
};
FaceGap rememberedFaceGap(const detail::WorldState& w, const BodySlot& point, double now) {
  const Vec2 at = w.positionAt(point, now);
  return {detail::distanceFromRememberedFace(w, point, now),
          detail::pointRoundOff(at, w.bodyOf(point.support.fixture).position)};
}

// How far from the face a point in the cusp of that face and a stepped body touching it can be
// (kCuspCosine).
double cuspReach(const detail::WorldState& w, uint32_t holderFixture, double roundOff) {
  return (1 - kCuspCosine) * detail::circleRadius(w.fixtures[holderFixture].geometry) + roundOff;
}

// Whether a point that keeps meeting a stepped body (normal n toward the point) is caught between it and
// the static face it remembers: on that face to its coordinates' round-off, or within the reach the time
// of impact allows a point on a face (pointOnRememberedFace, which the rules that call this read too: a
// point 9.2e-13 from a wall, twice the first, on it to one reading and off it to the other, held up by the
// wall and a feather disk at rest, was neither caught nor let slide, and met the disk every 1.2e-8 s until
// the step's budget ran out: fuzz/regressions/world_api/budget-hybrid-point-on-a-wall-held-up-by-a-
// feather-disk), in a corner of the face and the body whatever the angle between their normals; or, where
// the two normals are opposed, in the cusp the body leaves against the face (kCuspCosine).
bool caughtAgainstFace(const detail::WorldState& w, const BodySlot& point, uint32_t holderFixture, Vec2 n,
                       double now) {
  if (!detail::remembersLiveFace(w, point) || w.bodyOf(point.support.fixture).type != BodyType::Static) return false;
  const FaceGap gap = rememberedFaceGap(w, point, now);
  if (!(gap.distance >= -gap.roundOff)) return false;
  if (gap.distance <= gap.roundOff || detail::pointOnRememberedFace(w, point, now)) return true;
  if (!(dot(point.support.normal, n) < -kCuspCosine)) return false;
  return gap.distance <= cuspReach(w, holderFixture, gap.roundOff);
}

// A stepped body lighter than this fraction of a point's mass gives back a fraction this small of the
// point's approach at each meeting: to the point it is round-off, and as hard as a static body.
constexpr double kFeatherRatio = 1e-9;

// Whether a point is clear of the face it remembers (which it must): farther from it than the cusp a
// stepped body touching the face leaves (caughtAgainstFace), so that a bounce off that body at
// restingSpeed meets the face, if at all, as an ordinary contact later, and cannot take the point
// across it at once.
bool clearOfRememberedFace(const detail::WorldState& w, const BodySlot& point, uint32_t holderFixture, double now) {
  const FaceGap gap = rememberedFaceGap(w, point, now);
  return gap.distance > cuspReach(w, holderFixture, gap.roundOff);
}

// Whether contacts with normals f and n (toward the body) hold it up against gravity g: -g lies in their
// cone, -g = a f + b n with a, b >= 0 (Cramer's rule on the 2x2 system).
bool heldUpBy(Vec2 g, Vec2 f, Vec2 n) {
  const double det = cross(f, n);
  if (det == 0 || (g.x == 0 && g.y == 0)) return false;
  const double a = cross(-g, n) / det, b = cross(f, -g) / det;
  return a >= 0 && b >= 0;
}

// Whether a body moving at v holds a point it touches (its normal `toward` the point) as one at rest
// would: slower than restingSpeed, as a body that may sleep, and not closing on the point.
bool slowAndNotClosing(const detail::WorldState& w, Vec2 v, Vec2 toward) {
  return length(v) < w.def.restingSpeed && !(dot(v, toward) > 0);
}

// Whether contacts with normals f and n (toward the body), opposed as in a cusp (kCuspCosine), make a
// channel that lies level to within that same angle: one of them within it of straight up. Such a channel
// holds a point in it as a level floor would; the cone test (heldUpBy) asks for up strictly between the
// two, which a channel on a disk's top 2.4e-6 of a radian off its apex is not.
bool levelChannel(Vec2 g, Vec2 f, Vec2 n) {
  const double weight = length(g);
  if (!(weight > 0) || !(dot(f, n) < -kCuspCosine)) return false;
  const Vec2 up = -g * (1.0 / weight);
  return dot(f, up) >= kCuspCosine || dot(n, up) >= kCuspCosine;
}

// Whether a point that a stepped body's contact (normal n toward the point) holds is held up against
// gravity by that contact and a static face the point lies on: the corner of a box's wall and a disk that
// fills the box, when the face the point remembers is the box's ceiling. A polygon's face has its outside;
// a Segment's or a Polyline's is taken on the side that stops the body's push (a box of Segments, where
// such a point slid along the ceiling into the wall, off it, and back, 1e-13 s apart, until the step's
// budget ran out: fuzz/regressions/world_api/budget-hybrid-points-at-a-segment-box-ceiling-corner).
bool heldUpAtStaticFace(const detail::WorldState& w, uint32_t point, Vec2 n, double now) {
  for (const detail::CandidatePair& pair : w.pairsOfBody[point]) {
    if (w.bodyOf(pair.other).type != BodyType::Static) continue;
    Vec2 normal[2];
    int faces = detail::polygonFacesUnderPoint(w, w.bodies[point], pair.other, now, normal);
    if (faces == 0) faces = detail::lineFacesUnderPoint(w, w.bodies[point], pair.other, now, n, normal);
    for (int k = 0; k < faces; ++k) {
      if (heldUpBy(w.def.gravity, normal[k], n)) return true;
    }
  }
  return false;
}

// A point on the face it remembers that a stepped body's contact (normal n toward the point) stops, with
// gravity pressing it into the body and the two not holding it up: it slides along the face off the body,
// leaving it at restingSpeed (the bounce a point away from its face gets below, kept on the face), as it
// would slide down the body's rim. Stopped along the normal instead, it met the body again as soon as
// gravity brought the approach back: a point under a box's ceiling 2.8e-6 from the wall, on the rim of a
// feather disk that the walls hold, met it every 3.4e-14 s until the step's budget ran out
// (fuzz/regressions/world_api/budget-hybrid-points-at-a-box-ceiling-corner, once a polygon's corners were
// met only from their own side). Not where the face and the body's normal are nearly opposed (the cusp
// caughtAgainstFace handles), where the slide would be fast: at most ten times restingSpeed.
Vec2 slideOffAlongFace(const detail::WorldState& w, const BodySlot& p, uint32_t point, const BodySlot& o, Vec2 n,
                       double target, double now) {
  const double leave = target + w.def.restingSpeed;
  if (!(w.def.restingSpeed > 0) || !(leave > 0) || !(dot(p.velocity, n) < leave)) return p.velocity;
  if (!detail::pressedTogether(p.acceleration - o.acceleration, n)) return p.velocity;
  if (heldUpBy(w.def.gravity, p.support.normal, n) || heldUpAtStaticFace(w, point, n, now)) return p.velocity;
  const Vec2 along{-p.support.normal.y, p.support.normal.x};
  const double rate = dot(along, n);  // how fast a slide along the face leaves the body
  if (!(std::fabs(rate) >= 0.1)) return p.velocity;
  const Vec2 off = rate > 0 ? along : -along;
  return off * std::max(dot(p.velocity, off), leave / std::fabs(rate));
}

// Whether a body moving at v holds a point moving at vp that it touches (its normal `toward` the point)
// as one at rest would to within the round-off of their relative velocity (kAbsorbRoundOff, as an
// approach is read at a contact): slower than restingSpeed, and closing on the point no faster than that.
bool closesByRoundOff(const detail::WorldState& w, Vec2 vp, Vec2 v, Vec2 toward) {
  return length(v) < w.def.restingSpeed && dot(v, toward) <= detail::kAbsorbRoundOff * (length(vp) + length(v));
}

// The other side of a cusp that a point meeting a stepped body (normal n toward the point) is caught in,
// where that side is a body's rim rather than a static face (caughtAgainstFace): a dynamic disk among the
// point's candidates, other than the stepped body, that holds the point as one at rest would
// (closesByRoundOff), its normal at the point opposed to n (kCuspCosine), the point on its rim to within
// the cusp's reach.
struct CuspSide {
  uint32_t body;
  Vec2 normal;  // toward the point
};
std::optional<CuspSide> cuspWithBody(const detail::WorldState& w, uint32_t point, uint32_t holderFixture, Vec2 n,
                                     double now) {
  if (point >= w.pairsOfBody.size()) return std::nullopt;
  const BodySlot& p = w.bodies[point];
  const Vec2 at = w.positionAt(p, now);
  const uint32_t holder = w.fixtures[holderFixture].body;
  for (const detail::CandidatePair& pair : w.pairsOfBody[point]) {
    const detail::FixtureSlot& own = w.fixtures[pair.own];
    const detail::FixtureSlot& other = w.fixtures[pair.other];
    const BodySlot& q = w.bodies[other.body];
    if (own.sensor || other.sensor || other.body == holder || q.type != BodyType::Dynamic) continue;
    const Vec2 centre = w.positionAt(q, now) + detail::circleCentre(other.geometry);
    const Vec2 r = at - centre;
    const double distance = length(r);
    if (!(distance > 0)) continue;
    const Vec2 f = r * (1.0 / distance);
    if (!(dot(f, n) < -kCuspCosine)) continue;
    if (!q.asleep && !closesByRoundOff(w, w.velocityAt(p, now), w.velocityAt(q, now), f)) continue;
    const double radius = detail::circleRadius(other.geometry);
    const double holderRadius = detail::circleRadius(w.fixtures[holderFixture].geometry);
    const double reach = (1 - kCuspCosine) * std::min(radius, holderRadius) + detail::pointRoundOff(at, centre);
    if (std::fabs(distance - radius) <= reach) return CuspSide{other.body, f};
  }
  return std::nullopt;
}

// A point caught against the face it remembers by a stepped body that moves along that face too fast to
// hold it as one at rest would (stopPointAtSteppedBody's holderHolds), not closing on it, where the face
// and the body hold it up against gravity (heldUpBy): the wedge between a box's wall and a disk that an
// island moves down along it. Gravity's part along the body's normal presses the point into it, the
// bounce off the body at restingSpeed takes it into the face, and the face sends it back: a point 1.6e-5
// of a radian above such a disk's equator met it every 1.6e-8 s until the step's 20,000 events ran out
// (fuzz/regressions/world_api/budget-hybrid-point-in-the-wedge-of-a-wall-and-a-disk-moving-down-it). A
// point joins no island, so nothing else carries it down with the body, and it cannot sleep there (the
// body moves). It takes the velocity nearest its own that meets both contacts (target along the body's
// normal n, toward the point) and no acceleration for the rest of the step: the body's island is held on
// straight paths too, so the wedge moves on a straight line and the point in it stays there. The step's
// end gives gravity back (restoreCarriedPoints). Not where that velocity rises against gravity: the point
// falls more slowly than it would, which gives nothing back only while it does not climb.
bool carryPointInWedge(detail::WorldState& w, uint32_t point, uint32_t holderFixture, Vec2 n, double target,
                       double now) {
  BodySlot& p = w.bodies[point];
  const Vec2 g = w.def.gravity;
  if (!(w.def.restingSpeed > 0) || !(target <= 0) || !heldUpBy(g, p.support.normal, n) ||
      !caughtAgainstFace(w, p, holderFixture, n, now))
    return false;
  const Vec2 velocity = detail::nearestVelocityMeeting(p.velocity, p.support.normal, n, target);
  if (dot(velocity, g) < 0) return false;
  w.keep(p);
  p.velocity = velocity;
  p.acceleration = {};
  w.carriedPoints.push_back(point);
  return true;
}

}  // namespace

void detail::restoreCarriedPoints(WorldState& w, double end) {
  for (uint32_t i : w.carriedPoints) {
    BodySlot& b = w.bodies[i];
    // Asleep, stepped or sliding since, its acceleration is already what that state asks for.
    if (!b.alive || b.type != BodyType::Dynamic || b.asleep || b.stepped || b.sliding || !(b.acceleration == Vec2{}))
      continue;
    w.advance(b, end);
    b.acceleration = w.def.gravity;
  }
  w.carriedPoints.clear();
}

bool detail::jamsAsDriven(const WorldState& w, uint32_t body) {
  if (w.bodies[body].driven) return true;
  return std::any_of(w.wedged.begin(), w.wedged.end(), [&](const WorldState::Wedged& e) { return e.body == body; });
}

bool detail::squeezeExempt(const WorldState& w, uint32_t fa, uint32_t fb) {
  const uint64_t key = islandKey(fa, fb);
  const WorldState::SqueezeIndex& index = w.squeezeIndex;
  const size_t from = index.valid ? index.covered : 0;
  if (index.valid && std::binary_search(index.sorted.begin(), index.sorted.end(), key)) return true;
  for (size_t k = from; k < w.squeezes.size(); ++k) {
    if (w.squeezes[k].key == key) return true;
  }
  return false;
}

namespace {
// Sorts every squeeze's key into the index again.
void rebuildSqueezeIndex(detail::WorldState& w) {
  detail::WorldState::SqueezeIndex& index = w.squeezeIndex;
  index.valid = false;  // until it is whole: a failed allocation leaves every entry read one by one
  index.sorted.clear();
  for (const detail::WorldState::Squeeze& s : w.squeezes) index.sorted.push_back(s.key);
  std::sort(index.sorted.begin(), index.sorted.end());
  index.covered = w.squeezes.size();
  index.valid = true;
}
}  // namespace

void detail::refreshSqueezes(WorldState& w) {
  // The counts start again each step (the predictive mode's step after a plain one does not reset them).
  for (uint32_t body : w.squeezeCounted) w.bodies[body].stepCollisions = 0;
  w.squeezeCounted.clear();
  w.wedged.clear();
  w.bouncedOffStatic.clear();
  if (w.squeezes.empty()) {
    rebuildSqueezeIndex(w);
    return;
  }
  std::erase_if(w.squeezes, [&](const WorldState::Squeeze& s) {
    const uint32_t fa = static_cast<uint32_t>(s.key >> 32), fb = static_cast<uint32_t>(s.key);
    const detail::FixtureSlot& a = w.fixtures[fa];
    const detail::FixtureSlot& b = w.fixtures[fb];
    if (!a.alive || !b.alive || a.generation != s.generationA || b.generation != s.generationB) return true;
    if (overlaps(a.geometry, w.bodies[a.body].position, b.geometry, w.bodies[b.body].position)) return false;
    // Parted: the pair collides again, and the predictive mode must predict it again.
    w.touched(a.body);
    w.touched(b.body);
    return true;
  });
  rebuildSqueezeIndex(w);
}

bool detail::squeezeAt(WorldState& w, const detail::PredictedContact& c) {
  const uint32_t ia = w.fixtures[c.a].body, ib = w.fixtures[c.b].body;
  BodySlot& a = w.bodies[ia];
  const BodySlot& b = w.bodies[ib];
  if (a.type == BodyType::Dynamic && b.type == BodyType::Dynamic) return passesThrough(w, c);
  // `a` is the dynamic body of a contact (PredictedContact); only a contact with what does not yield
  // counts, and only a kinematic body can give way.
  if (a.type != BodyType::Dynamic) return false;
  const int count = a.countStepCollision();
  if (count == 1) w.squeezeCounted.push_back(ia);
  if (count <= w.kSqueezeCollisions) return false;
  if (b.type == BodyType::Static) {
    // Wedged between static bodies (a body larger than the gap it was put in): it bounces from one to the
    // other at one instant without end. Only such bounces, at the instant of its last collision, count
    // here; a fast body crossing a small box does not. It stops moving into this one.
    const auto bounced = std::find_if(w.bouncedOffStatic.begin(), w.bouncedOffStatic.end(),
                                      [&](const WorldState::Wedged& e) { return e.body == ia; });
    // At one instant to the body's coordinates (oneInstant): a point bounced between two faces on one
    // line (the seam of a wall's top and the face above it) met them 4e-15 s apart, each bounce a little
    // later, until the step's budget ran out (fuzz/regressions/world_api/budget-predictive-point-in-
    // a-seam-of-two-faces).
    const double instant = oneInstant(w, a, b, c.time);
    if (std::fabs(c.time - a.last.time) > instant) {
      // A bounce, but remembered: a body bounced off a wall into a face that its overlap already
      // touches meets that face at the same instant (a disk made over a corner, then slid down along
      // a wall beside it: the corner's normal tilts up, so each stop against the corner left it moving
      // back into the wall, and wall and corner took turns 1e-15 s apart until the step's budget ran
      // out; test Squeeze.ADiskMadeOverACornerBesideAWallStops).
      if (bounced != w.bouncedOffStatic.end()) {
        *bounced = {ia, c.time, c.normal};
      } else {
        w.bouncedOffStatic.push_back({ia, c.time, c.normal});
      }
      return false;
    }
    // Not moving into it, only pressed into it by gravity (a point at rest in a box's corner): there is
    // no bounce to stop, and stopping nothing found the same contact again at the same instant without
    // end (fuzz/regressions/world_api/budget-predictive-points-in-a-corner). resolve()'s resting rules
    // hold a pressed body: it sleeps or slides.
    if (!(dot(w.velocityAt(a, c.time), c.normal) < 0)) return false;
    w.advance(a, c.time);
    placePointOnFace(w, a, c);
    // Stopped against two faces at one instant whose normals differ, it can move along neither: the
    // bounces between them are alternating projections onto their two tangents, which meet only at rest,
    // and converge there no faster than the cosine of the angle between the faces per pair. A disk
    // around a small polygon, put there by setPosition, took 20,000 of them between two of its corners
    // (fuzz/regressions/world_api/budget-hybrid-disk-around-a-static-polygon). Between parallel faces (a
    // slot) it slides on.
    const auto found =
        std::find_if(w.wedged.begin(), w.wedged.end(), [&](const WorldState::Wedged& e) { return e.body == ia; });
    const auto metAtThisInstant = [&](const auto it, const auto end) {
      return it != end && std::fabs(it->time - c.time) <= instant &&
             std::fabs(cross(it->normal, c.normal)) > kWedgeAngle;
    };
    const bool stoppedNow = metAtThisInstant(found, w.wedged.end());
    const bool cornered = stoppedNow || metAtThisInstant(bounced, w.bouncedOffStatic.end());
    // The record of this stop, for the next contact at this instant.
    const auto rememberStop = [&] {
      if (found != w.wedged.end()) {
        *found = {ia, c.time, c.normal};
      } else {
        w.wedged.push_back({ia, c.time, c.normal});
      }
    };
    if (cornered) {
      const Vec2 otherFace = stoppedNow ? found->normal : bounced->normal;
      a.velocity = Vec2{};
      // Stopped in a corner whose two faces hold it up against gravity (a point in the apex of a
      // needle), it rests there: left stopped, it slid on along the face gravity pressed it into, past
      // the apex, where neither face reaches, and fell out of the tip.
      if (w.def.restingSpeed > 0 && heldUpBy(w.def.gravity, otherFace, c.normal)) {
        ++a.collisionCount;
        a.setLast(detail::LastContact{std::min(c.a, c.b), std::max(c.a, c.b), c.feature, c.time});
        rememberStop();
        w.supporters.clear();
        putToSleep(w, ia, w.supporters);
        ++w.stats.squeezes;
        return true;
      }
    } else {
      a.velocity -= c.normal * dot(a.velocity, c.normal);
    }
    rememberStop();
    ++a.collisionCount;
    a.setLast(detail::LastContact{std::min(c.a, c.b), std::max(c.a, c.b), c.feature, c.time});
    // Pressed into a flat face by gravity, it slides on it, as resolve()'s resting rules would have it:
    // stopped on the face with gravity still pulling it in, it was taken as leaving the face it had just
    // been resolved against and fell through the floor of a box
    // (fuzz/regressions/world_api/escape-predictive-disk-squeezed-on-a-floor).
    // Any other face ends a slide, as in resolve(): a disk sliding down one face of a 23-degree apex,
    // stopped moving into the other, went on along that other face into the first, which its slide left
    // out of its predictions, and passed through it.
    if (dot(a.acceleration, c.normal) < 0 && isFlatFeature(w, c.b, c.feature)) {
      startSliding(w, ia, c.b, c.feature, c.normal);
    } else if (a.sliding && !(a.support.fixture == c.b && a.support.feature == c.feature)) {
      stopSliding(w, a);
    }
    keepSlidingPointOnFace(w, a, c.a);
    ++w.stats.squeezes;
    return true;
  }
  // Its last contact was with this kinematic body too, and not at this instant (a disk bouncing on a
  // platform that lifts it under gravity, some 400 times in a step of 1 s, then meeting the platform's
  // wall): the faces of one body do not close on it, and nothing else does. Taken as squeezed, the
  // platform (a box of one Polyline) passed over it and it fell out of the lifted box (tests:
  // Squeeze.ADiskInALiftedBoxStaysIn).
  if (a.last.time >= 0) {
    const uint32_t lastOther = w.lastPartnerFixture(ia);
    if (w.fixtures[lastOther].body == ib && std::fabs(c.time - a.last.time) > oneInstant(w, a, b, c.time)) return false;
  }
  w.advance(a, c.time);
  a.velocity -= c.normal * dot(a.velocity, c.normal);
  ++a.collisionCount;
  a.last = detail::LastContact{};
  a.stepLocalsSet = true;
  exemptFromCollisions(w, c.a, c.b);
  return true;
}

void detail::stopPointAtSteppedBody(WorldState& w, const detail::PredictedContact& c, double dt) {
  // A point joins no island (jam.cpp: an island's contacts cannot tell a point's side of a face). A
  // stepped body it hits takes the hit as a free body would, and the solve of its island after it
  // (settleAround) takes back what the island's holders do not let it keep, while the point keeps what
  // the body took. A point of mass 1 on a disk of radius 0.025 that the two faces of a narrow V held kept
  // all but a twenty-thousandth of its approach each time and met the disk again 2e-6 s later, until the
  // step's budget of a million events ran out. Past the squeeze count the stepped body is taken as one
  // that does not yield: the point's velocity along the normal becomes the body's (or zero, when the body
  // comes toward it), which only ever slows the point.
  for (const bool pointIsA : {true, false}) {
    const uint32_t pointFixture = pointIsA ? c.a : c.b, holderFixture = pointIsA ? c.b : c.a;
    const uint32_t ip = w.fixtures[pointFixture].body;
    const uint32_t io = w.fixtures[holderFixture].body;
    BodySlot& p = w.bodies[ip];
    const BodySlot& o = w.bodies[io];
    if (!o.stepped || p.type != BodyType::Dynamic || p.asleep || p.stepCollisions <= w.kSqueezeCollisions) continue;
    if (!detail::isPoint(w.fixtures[pointFixture].geometry)) continue;
    const Vec2 n = pointIsA ? c.normal : -c.normal;  // from the stepped body toward the point
    w.advance(p, c.time);
    const double vp = dot(p.velocity, n);
    const Vec2 holderVelocity = w.velocityAt(o, c.time);
    const double vo = dot(holderVelocity, n);
    const double target = std::min(vo, 0.0);
    // At rest: still, or moving by what a solve leaves as round-off, far below any bounce (a feather disk
    // that the walls hold, at 3e-269 units/s, kept a point in the box's ceiling corner from the rules
    // below, and the two met 9,700 times at one instant until the step's budget ran out:
    // fuzz/regressions/world_api/budget-hybrid-point-at-a-feather-disk-still-to-round-off). Or slower
    // than restingSpeed, as a body that may sleep, and not closing on the point: a point falling into the
    // V of a wall and a disk resting against it, the disk's island drifting down at 2e-5 units/s, bounced
    // across the V, 1e-14 wide, every 1.5e-12 s until the step's budget ran out
    // (budget-hybrid-point-rattling-in-the-cusp-of-a-drifting-disk-and-a-wall). A point asleep on a body
    // that moves wakes at the next step's start (wakeSleepersOfMovingBodies).
    const bool holderAtRest = length(holderVelocity) <= detail::kAbsorbRoundOff * w.def.restingSpeed ||
                              slowAndNotClosing(w, holderVelocity, n);
    // Or leaving the point, not closing on it, so slowly that a point asleep there hovers above it by the
    // step's end no more than an island's solve may leave two bodies overlapping (kJamResidual of its
    // radius): a point that fell into the V of a wall and a disk sliding down it at three times
    // restingSpeed bounced across the V, 1e-13 wide, every 5e-12 s until the step's budget ran out
    // (budget-hybrid-point-in-the-v-of-a-wall-and-a-disk-sliding-down-it). The velocity that meets both
    // contacts there is the V's own, the body's along the face.
    const double hover = length(holderVelocity) * (dt - c.time);
    const bool holderLeavesSlowly =
        !(dot(holderVelocity, n) > 0) &&
        hover <= Islands::kJamResidual * detail::circleRadius(w.fixtures[holderFixture].geometry);
    const bool holderHolds = holderAtRest || holderLeavesSlowly;
    const double carried = holderAtRest ? 0.0 : length(holderVelocity);
    if (!holderHolds && carryPointInWedge(w, ip, holderFixture, n, target, c.time)) {
      // Carried (carryPointInWedge): it keeps no acceleration the step's next meetings could read.
    } else if (holderHolds && caughtAgainstFace(w, p, holderFixture, n, c.time)) {
      // Caught where the stepped body, at rest, touches the face the point remembers, the two normals
      // opposed: each contact's impulse (the island's bounce at restingSpeed, the face's) drives it into
      // the other, and the bounces come ever faster as it goes deeper. Under an overhang, a point that
      // gravity pressed into a disk resting against the wall went on bouncing at one instant until the
      // step's budget of a million events ran out. It takes what meets both contacts (nothing, nearly,
      // when their normals are opposed), and where the two hold it up, it sleeps there until the body
      // moves. So too in a wider corner of the face and the body: a point on a box's wall, under a light
      // disk the walls hold, slid down the disk at 3e-9 units/s, into the wall, its position frozen by
      // round-off, and met the disk every 3.4e-14 s until the step's budget of 20,000 events ran out
      // (fuzz/regressions/world_api/budget-hybrid-point-below-the-corner-of-a-small-box).
      // What holds it up may be a face it does not remember: a point that rose into a box's ceiling
      // corner inside a feather disk, the ceiling remembered, was held by the wall and the disk's rim, and
      // slid along the rim into the wall at 5e-9 units/s, meeting the disk every 3.4e-14 s until the
      // budget ran out (budget-hybrid-points-at-a-box-ceiling-corner). A static face needs no memory of
      // the side the point is on (heldUpAtStaticFace). A level channel holds it up too (levelChannel): a
      // point on the top of a disk at rest, 2.4e-6 of a radian off its apex, under a ceiling 6e-12 above,
      // bounced off the disk into the ceiling and was stopped, and met the disk again every 6.5e-9 s,
      // until the step's budget ran out (budget-hybrid-point-between-a-disk-top-and-a-ceiling).
      // In the cusp of a body that moves, only where a point asleep there would hover within kJamResidual
      // (above): stopped there at each meeting instead of put to sleep, a point above a disk sliding down a
      // wall met it again and again as it fell after it (tens of thousands of events a step where the
      // normal's part alone takes a few thousand). Asleep, it keeps no velocity, and the body's own (which
      // is what meets both contacts) counts as slow.
      p.velocity = detail::nearestVelocityMeeting(p.velocity, p.support.normal, n, target);
      if (length(p.velocity) < w.def.restingSpeed + carried &&
          (heldUpBy(w.def.gravity, p.support.normal, n) || levelChannel(w.def.gravity, p.support.normal, n) ||
           heldUpAtStaticFace(w, ip, n, c.time))) {
        sleepOnAwakeBodies(w, ip, std::span<const uint32_t>(&io, 1));
        continue;
      }
      p.velocity = slideOffAlongFace(w, p, ip, o, n, target, c.time);
    } else if (const std::optional<CuspSide> side = holderHolds || closesByRoundOff(w, p.velocity, holderVelocity, n)
                                                        ? cuspWithBody(w, ip, holderFixture, n, c.time)
                                                        : std::nullopt;
               side &&
               (heldUpBy(w.def.gravity, side->normal, n) || levelChannel(w.def.gravity, side->normal, n)) &&
               length(detail::nearestVelocityMeeting(p.velocity, side->normal, n, target)) <
                   w.def.restingSpeed + carried) {
      // So too in the cusp where the stepped body touches another disk at rest, each contact's bounce
      // driving the point into the other: a point that fell at 2.7 units/s into the waist of two disks
      // touching on a floor (one stepped, closing on it at 7e-15 units/s, round-off to the point's speed;
      // one free and still) met them in turn every 3.6e-13 s until the step's budget of 20,000 events
      // ran out (fuzz/regressions/world_api/budget-predictive-point-falls-into-the-waist-of-two-disks).
      // It sleeps there, held by the two, and falls again at the next step's start unless each of them is
      // asleep then or still in its island (wakeSleepersOfMovingBodies).
      const uint32_t holders[] = {io, side->body};
      sleepOnAwakeBodies(w, ip, holders);
      continue;
    } else {
      const bool onFace = remembersLiveFace(w, p) && pointOnRememberedFace(w, p, c.time);
      const double leave = target + w.def.restingSpeed;
      // Pressed into the body by gravity and leaving it slower than restingSpeed (below).
      const bool pressedSlow =
          w.def.restingSpeed > 0 && detail::pressedTogether(p.acceleration - o.acceleration, n) && vp < leave;
      const bool knowsFace =
          remembersLiveFace(w, p) && std::isfinite(detail::distanceFromRememberedFace(w, p, c.time));
      const bool feather = o.mass <= kFeatherRatio * p.mass;
      const bool clear = knowsFace && clearOfRememberedFace(w, p, holderFixture, c.time);
      // Pressed into the body by gravity and leaving it slower than restingSpeed, it bounces off at
      // restingSpeed, as resolve() has a body bounce off what cannot move: stopped along the normal, or
      // left separating by round-off, it met the body again as soon as gravity brought back an approach. A
      // point of mass 1 falling along the rim of a disk three thousand billion times lighter, which its
      // island held still, met it every 5e-16 s until the step's budget of 20,000 events ran out
      // (fuzz/regressions/world_api/budget-hybrid-point-along-a-light-disk-held-still); one sliding over
      // such a disk's top at 0.74 units/s, its position frozen by round-off, every 3.6e-16 s
      // (budget-hybrid-point-sliding-over-a-feather-disk-at-rest). A point that remembers a static face
      // (a flat one: a corner's side is not known) bounces only off a body too light to give anything back
      // (kFeatherRatio): a disk of some weight is left out, as the point of tests:
      // BodiesInCorners.APointAsleepOnAnAwakeDiskFallsWhenTheDiskMoves, bounced off its disk (47 times
      // lighter than the point) on the way, no longer reached the cusp the test needs. Away from that
      // face (clear of it) the bounce is along the normal: one 0.32 from it, following a disk 3e12 times
      // lighter that moved down ahead of it, met it every 2.5e-15 s until the budget ran out
      // (budget-hybrid-point-following-a-light-disk-away-from-a-face). Near the face, that bounce may take
      // it into the face (budget-hybrid-point-below-the-corner-of-a-small-box spent its budget so), so
      // the velocity nearest its own that leaves the body at restingSpeed and does not enter the face
      // (zero meets both where the body moves away faster than restingSpeed). Points on a wall above a
      // feather disk that moved down along it followed it, met every 3e-16 s: two on one spot, met in
      // turn, until the budget ran out (budget-hybrid-two-points-on-one-spot-under-a-feather-disk). Where
      // the body does not move away so fast, zero meets neither, and the nearest velocity that does is
      // found where the face and the body's normal leave room for a modest one (nearestVelocityLeaving;
      // in a cusp the cases above and the slide below hold the point): a point 4.6e-13 from a wall,
      // sliding over a feather disk at rest into the corner the two make, its position frozen by
      // round-off, met the disk every 4.5e-16 s (budget-hybrid-point-near-a-wall-on-a-feather-disk-at-rest).
      bool acted = false;
      std::optional<Vec2> nearFace;
      if (pressedSlow && knowsFace && feather && !clear) {
        nearFace = leave <= 0 ? detail::nearestVelocityMeeting(p.velocity, p.support.normal, n, leave)
                              : detail::nearestVelocityLeaving(p.velocity, p.support.normal, n, leave);
      }
      if (nearFace) {
        acted = true;
        p.velocity = *nearFace;
      } else if (pressedSlow && (!knowsFace || (feather && clear))) {
        acted = true;
        p.velocity += n * (leave - vp);
      } else if (vp < 0 && vp < vo) {
        acted = true;
        p.velocity += n * (target - vp);
        // On a face it remembers (sliding along a floor into the cusp under a disk that rests on it), the
        // normal above is the face's to within round-off, and the point's speed along the face gave the
        // part removed: taken out, the point went into the floor. So the face's constraint is met as well:
        // the velocity nearest this one that meets both, which never speeds the point up.
        if (onFace) p.velocity = detail::nearestVelocityMeeting(p.velocity, p.support.normal, n, target);
      }
      // The contact's own response may leave it just separating from the body, on its face, and gravity
      // brings the approach back at once: it slides off all the same (the point on a box's ceiling above
      // met a feather disk every 3.4e-14 s so).
      if (onFace) {
        const Vec2 slide = slideOffAlongFace(w, p, ip, o, n, target, c.time);
        acted = acted || !(slide == p.velocity);
        p.velocity = slide;
      }
      if (!acted) continue;
    }
    ++p.collisionCount;
    p.stepLocalsSet = true;
  }
}

bool detail::exemptIfMadeOverlapping(WorldState& w, uint32_t fa, uint32_t fb, double now) {
  const BodySlot& a = w.bodyOf(fa);
  const BodySlot& b = w.bodyOf(fb);
  if (a.type != BodyType::Dynamic || b.type != BodyType::Dynamic) return false;
  const CircleOverlap o =
      circleOverlap(w.fixtures[fa].geometry, w.positionAt(a, now), w.fixtures[fb].geometry, w.positionAt(b, now));
  if (!madeOverlapping(o)) return false;
  // The sweep's plain pairs reach here without a look at the exempt ones (passesThrough drops theirs).
  if (!squeezeExempt(w, fa, fb)) exemptFromCollisions(w, fa, fb);
  return true;
}

void detail::exemptFromCollisions(WorldState& w, uint32_t fa, uint32_t fb) {
  w.squeezes.push_back(
      {islandKey(fa, fb), w.fixtures[std::min(fa, fb)].generation, w.fixtures[std::max(fa, fb)].generation});
  ++w.stats.squeezes;
  WorldState::SqueezeIndex& index = w.squeezeIndex;
  if (!index.valid || w.squeezes.size() - index.covered <= WorldState::kSqueezeIndexTail) return;
  index.valid = false;  // until the merge is done
  const size_t middle = index.sorted.size();
  for (size_t k = index.covered; k < w.squeezes.size(); ++k) index.sorted.push_back(w.squeezes[k].key);
  std::sort(index.sorted.begin() + static_cast<std::ptrdiff_t>(middle), index.sorted.end());
  std::inplace_merge(index.sorted.begin(), index.sorted.begin() + static_cast<std::ptrdiff_t>(middle),
                     index.sorted.end());
  index.covered = w.squeezes.size();
  index.valid = true;
}

bool detail::passesThrough(WorldState& w, const detail::PredictedContact& c) {
  const uint32_t ia = w.fixtures[c.a].body, ib = w.fixtures[c.b].body;
  const Vec2 pa = w.positionAt(w.bodies[ia], c.time), pb = w.positionAt(w.bodies[ib], c.time);
  // "At this instant", below, to what the two positions resolve: times closer than either body takes to
  // move its coordinates' round-off are one instant to them. A disk driven at 50 units/s into a speck
  // held at a block's face met it every 3.5e-19 s, each meeting a round-off later, where the same
  // instant would have let it pass the speck (fuzz/regressions/world_api/budget-predictive-speck-held-
  // at-a-block-a-round-off-apart).
  double instant = -1;  // worked out when first asked: most contacts never ask
  auto atThisInstant = [&](double t) {
    if (instant < 0) instant = oneInstant(w, w.bodies[ia], w.bodies[ib], c.time);
    return std::fabs(c.time - t) <= instant;
  };
  // One of the two was stopped against a static face at this instant (above), and the other keeps
  // driving it there.
  auto wedgedNow = [&](const WorldState::Wedged& e) { return (e.body == ia || e.body == ib) && atThisInstant(e.time); };
  const bool held = std::any_of(w.wedged.begin(), w.wedged.end(), wedgedNow);
  // Or this pair was the last contact of one of them earlier in this step (at this very instant, or
  // before), and something drove them back together: at one instant, or ever sooner, as gravity presses
  // points made inside a disk wedged in a small box back into it, 1e-14 s apart
  // (fuzz/regressions/world_api/budget-hybrid-points-and-a-light-disk-in-a-small-box).
  auto metInThisStep = [&](const BodySlot& s) { return s.last.time >= 0 && s.last.is(c.a, c.b, s.last.time); };
  // Or one of them has collided past the squeeze count in this step: a point made inside a disk that
  // the walls hold, and pressed against a wall, went from the disk to the wall and back, 1e-13 s apart
  // (fuzz/regressions/world_api/budget-hybrid-point-between-a-wall-and-the-disk-it-is-in).
  auto busy = [&](const BodySlot& s) { return s.stepCollisions > w.kSqueezeCollisions; };
  // Or, the rules below ask, this pair was its last contact at this instant.
  auto metNowBy = [&](const BodySlot& s) { return metInThisStep(s) && atThisInstant(s.last.time); };
  const CircleOverlap o = circleOverlap(w.fixtures[c.a].geometry, pa, w.fixtures[c.b].geometry, pb);
  // Or they were made overlapping (exemptIfMadeOverlapping).
  const bool made = madeOverlapping(o);
  if (!held && !metInThisStep(w.bodies[ia]) && !metInThisStep(w.bodies[ib]) && !busy(w.bodies[ia]) &&
      !busy(w.bodies[ib]) && !made)
    return false;
  if (squeezeExempt(w, c.a, c.b)) return true;  // a second prediction of the pair, made before the first came
  // A point past the squeeze count meets again, at the instant of its last contact with it, the body it last
  // met: something sent the body straight back (a third body it was bounced into), and it is caught between
  // the two, as between a kinematic body and a static one. (This instant as above: the meetings of such a
  // loop came 1e-17 s apart as well, two or three round-offs of the time, and asked for the very instant the
  // loop ran to the budget: fuzz/regressions/world_api/budget-hybrid-two-points-on-a-light-disk-ulps-apart.)
  // A point joins no island, so no solve sees both contacts at once, and each bounces the body into the
  // other. Two points of mass 1 closing on a disk 3e12 times lighter that filled the gap between them,
  // resting on a floor, bounced it from one to the other about 9,700 times each at one instant, until the
  // step's budget of 20,000 events ran out
  // (fuzz/regressions/world_api/budget-hybrid-two-points-on-a-light-disk-at-one-instant); the two touch
  // there, too shallow for the depth below. The point passes through the caught body, as a kinematic body
  // passes over a squeezed one, until they no longer overlap. Not a point near a static face it remembers:
  // caught in the cusp of that face and a stepped disk, it is held there (stopPointAtSteppedBody), where
  // passing through the disk let it fall through (tests:
  // BodiesInCorners.APointAsleepOnAnAwakeDiskFallsWhenTheDiskMoves). Away from that face (beyond the cusp,
  // clearOfRememberedFace) it is caught as any point: one grazing a stepped feather disk that slid down a
  // wall, the two moving apart along their normal exactly as fast as they closed, met it 9,500 times at
  // one instant until the budget ran out (fuzz/regressions/world_api/budget-hybrid-point-grazing-a-
  // feather-disk-sliding-down-a-wall). A body met so by a feather (kFeatherRatio of its mass or less) is
  // caught as such a point is: a disk of mass 1e-150 that its island drove into a free disk bounced off
  // it, was sent back by the island's solve, and met it every 1.8e-16 s, the free disk unmoved, until the
  // budget ran out (budget-hybrid-disk-meets-a-feather-its-island-drives-into-it).
  auto metAgainNow = [&](const BodySlot& point, uint32_t pointFixture) {
    const uint32_t otherFixture = pointFixture == c.a ? c.b : c.a;
    const bool caughtKind = detail::isPoint(w.fixtures[pointFixture].geometry) ||
                            w.bodyOf(otherFixture).mass <= kFeatherRatio * point.mass;
    return busy(point) && caughtKind && metNowBy(point) &&
           (!remembersLiveFace(w, point) || clearOfRememberedFace(w, point, otherFixture, c.time));
  };
  if (metAgainNow(w.bodies[ia], c.a) || metAgainNow(w.bodies[ib], c.b)) {
    exemptFromCollisions(w, c.a, c.b);
    return true;
  }
  // And the two overlap deeply: made so (a fixture created, a body set, over the other), not brought
  // together by this step's events, which leave them touching. A point inside a disk of radius 2.8, the
  // disk held by the floor and the wall the point was pressed into, drove it into the wall 27,000 times
  // at one instant, a little of its momentum each time
  // (fuzz/regressions/world_api/budget-predictive-point-inside-a-disk-at-a-wall). A disk 5e10 times
  // lighter than the points it was made around, two of them closing on it from both sides, took a
  // 5e10th of their approach per collision, all at one instant
  // (fuzz/regressions/world_api/budget-hybrid-light-disk-made-around-points). Such a pair passes
  // through each other, as a kinematic body passes over a squeezed one, until they no longer overlap.
  // A point held, and met again at this instant: pressed into a static face and the other driving it
  // there at once, however shallow the overlap (a point in a corner of a box, inside a feather disk
  // wedged in it: fuzz/regressions/world_api/budget-hybrid-made-pairs-under-gravity-in-a-box). A disk
  // whose diameter is within the residual of the other's radius is such a point: held at a face it is
  // never deeper in the other than the depth rule asks (a disk of radius 1e-12 between a static block
  // and one of 0.05 driven into it: fuzz/regressions/world_api/budget-predictive-speck-held-at-a-block).
  // Not two disks of a size: a column a game drives into a wall has its disks held and met again at one
  // instant, and passing through each other there they packed 7% of a radius deep (tests: DrivenCrowd).
  const bool pointLike = 2 * std::min(o.ra, o.rb) <= Islands::kJamResidual * std::max(o.ra, o.rb);
  const bool metNow = metNowBy(w.bodies[ia]) || metNowBy(w.bodies[ib]);
  const bool heldAndMetNow = held && pointLike && metNow;
  // Or a point and the other each held at a face of their own at this instant: a point sliding along a
  // floor under a disk that the ceiling holds, inside it by less than the depth rule asks (the disk made
  // across the box), where the contact's normal leans off the vertical, so each meeting turns a little
  // of the point's slide into a push into floor and ceiling, which take it. The meetings converge
  // (about 8% less each) but the point's slide is slow to stop: 6,666 of them at one instant, until the
  // queue's budget ran out (fuzz/regressions/world_api/budget-predictive-point-under-a-disk-wedged-in-a-
  // box-of-segments). Neither can move along the normal: it passes through, as above.
  auto heldNow = [&](uint32_t body) {
    return std::any_of(w.wedged.begin(), w.wedged.end(),
                       [&](const WorldState::Wedged& e) { return e.body == body && atThisInstant(e.time); });
  };
  const bool bothHeldNow = pointLike && heldNow(ia) && heldNow(ib);
  // Or a point past the squeeze count, held at a static face at this instant, that a stepped body (an
  // island's member, whose contacts its solve holds and whose last contact it forgets) meets from the
  // other side, the two normals opposed as in a cusp (kCuspCosine): caught in the pinch of the body and
  // the face. A disk wider than its box slid down between the walls, and a point on a wall under its rim,
  // taking a fiftieth of each push along the wall, met it and the wall in turn 9,700 times at one instant
  // until the step's budget ran out (fuzz/regressions/world_api/budget-predictive-point-in-the-cusp-of-a-
  // falling-disk-and-a-wall); a point falling down a wall onto the touch of a small disk resting against
  // it met the two in turn so as well (budget-hybrid-point-falls-into-the-touch-of-a-disk-and-a-wall).
  auto drivenIntoItsFace = [&](uint32_t point, uint32_t pointFixture, uint32_t other) {
    if (!detail::isPoint(w.fixtures[pointFixture].geometry) || !busy(w.bodies[point]) || !w.bodies[other].stepped)
      return false;
    const Vec2 n = pointFixture == c.a ? c.normal : -c.normal;  // from the stepped body toward the point
    return std::any_of(w.wedged.begin(), w.wedged.end(), [&](const WorldState::Wedged& e) {
      return e.body == point && atThisInstant(e.time) && dot(e.normal, n) < -kCuspCosine;
    });
  };
  // Or such a point whose last contact in this step was the static face it remembers, met from the other
  // side by a body that moves toward it, the two normals opposed as above: the pinch where the body's rim
  // crosses the face, or a channel between the two. A point in that pinch, a disk rising along a wall it
  // is deep in, was carried up by a little at each meeting, a meeting of the disk and of the wall every
  // 1e-11 s, 9,800 of each until the step's budget ran out (fuzz/regressions/world_api/budget-predictive-
  // point-in-the-pinch-of-a-rising-disk-and-a-wall); one in a channel 4.9e-11 wide between a wall and a
  // disk in an island, which drifted toward it by round-off, bounced across it at restingSpeed, falling a
  // little each time (budget-hybrid-point-in-a-channel-between-a-wall-and-a-disk). Not a body at rest: a
  // point asleep in the cusp of a floor and a disk, there held, fell through the disk (tests:
  // BodiesInCorners.APointAsleepOnAnAwakeDiskFallsWhenTheDiskMoves).
  auto pressedAgainstItsFace = [&](uint32_t point, uint32_t pointFixture, uint32_t other) {
    const BodySlot& p = w.bodies[point];
    if (!detail::isPoint(w.fixtures[pointFixture].geometry) || !busy(p) || p.last.time < 0 ||
        !remembersLiveFace(w, p))
      return false;
    const uint32_t last = w.lastPartnerFixture(point);
    if (last != p.support.fixture || w.bodyOf(last).type != BodyType::Static) return false;
    const Vec2 n = pointFixture == c.a ? c.normal : -c.normal;  // from the other body toward the point
    return dot(p.support.normal, n) < -kCuspCosine && dot(w.velocityAt(w.bodies[other], c.time), n) > 0;
  };
  const bool cuspNow = drivenIntoItsFace(ia, c.a, ib) || drivenIntoItsFace(ib, c.b, ia) ||
                       pressedAgainstItsFace(ia, c.a, ib) || pressedAgainstItsFace(ib, c.b, ia);
  // Or a point past the squeeze count that meets this body at the instant of its last contact, with
  // another dynamic body whose normal at the point is more than a right angle from this one's: caught
  // between the two, it bounces from one to the other at one instant. A point moving into the narrow
  // wedge where two slightly overlapping disks meet (their normals there 3.6 degrees from opposed), the
  // disks held still by others, met them in turn at one instant until the step's 20,000 events ran out
  // (fuzz/regressions/world_api/budget-hybrid-point-in-the-wedge-of-two-disks). Neither the point's last
  // contact nor this one is this pair met again, which the rules above ask for.
  // A point past the squeeze count whose last contact in this step was with a dynamic body other than
  // this pair's: that contact's other fixture, and the point's centre and that fixture's centre now (a
  // dynamic body holds only circles and points: its normal at the point is from its centre).
  struct LastPartner {
    uint32_t fixture;
    Vec2 at, centre;
  };
  auto lastDynamicPartner = [&](uint32_t point, uint32_t pointFixture) -> std::optional<LastPartner> {
    const BodySlot& p = w.bodies[point];
    if (!detail::isPoint(w.fixtures[pointFixture].geometry) || !busy(p) || p.last.time < 0) return std::nullopt;
    const uint32_t last = w.lastPartnerFixture(point);
    const detail::FixtureSlot& lastFixture = w.fixtures[last];
    if (last == c.a || last == c.b || w.bodies[lastFixture.body].type != BodyType::Dynamic) return std::nullopt;
    return LastPartner{last, w.positionAt(p, c.time) + detail::circleCentre(w.fixtures[pointFixture].geometry),
                       w.positionAt(w.bodies[lastFixture.body], c.time) + detail::circleCentre(lastFixture.geometry)};
  };
  auto pinched = [&](uint32_t point, uint32_t pointFixture) {
    const BodySlot& p = w.bodies[point];
    if (p.last.time < 0 || !atThisInstant(p.last.time)) return false;
    const std::optional<LastPartner> last = lastDynamicPartner(point, pointFixture);
    const Vec2 n = pointFixture == c.a ? c.normal : -c.normal;  // from this body toward the point
    return last && dot(last->at - last->centre, n) < 0;
  };
  const bool pinchNow = pinched(ia, c.a) || pinched(ib, c.b);
  // Or such a point, past the squeeze count, whose last contact was with another dynamic body that it
  // still touches (within the cusp's reach), both bodies asleep or slower than restingSpeed and not
  // closing on it (as stopPointAtSteppedBody takes a holder at rest), the two contacts holding it up: it
  // rests in the pinch. A point fell into the V of two disks touching side by side on a floor, just
  // above their touch, and bounced from one to the other at restingSpeed every 2.2e-12 s until the
  // step's 20,000 events ran out (fuzz/regressions/world_api/budget-predictive-point-in-the-pinch-of-two-
  // disks-on-a-floor); another did so between a sleeping disk and one in an island moving at 4e-13 units/s
  // (budget-hybrid-point-in-the-pinch-of-a-sleeping-disk-and-a-stepped-one). Passed through, it would fall
  // through what holds it up; it sleeps there instead, woken at the next step's start unless both are
  // asleep or stepped and still (wakeSleepersOfMovingBodies).
  auto restsInPinch = [&](uint32_t point, uint32_t pointFixture, uint32_t other) {
    if (!(w.def.restingSpeed > 0)) return false;
    const std::optional<LastPartner> last = lastDynamicPartner(point, pointFixture);
    if (!last) return false;
    const double distance = length(last->at - last->centre);
    const double gap = distance - detail::circleRadius(w.fixtures[last->fixture].geometry);
    const double roundOff = detail::pointRoundOff(last->at, last->centre);
    if (!(distance > 0) || !(std::fabs(gap) <= cuspReach(w, last->fixture, roundOff))) return false;
    const Vec2 f = (last->at - last->centre) * (1.0 / distance);  // from the last body toward the point
    const Vec2 n = pointFixture == c.a ? c.normal : -c.normal;     // from this body toward the point
    auto holds = [&](const BodySlot& b, Vec2 toward) {
      return b.asleep || slowAndNotClosing(w, w.velocityAt(b, c.time), toward);
    };
    return holds(w.bodyOf(last->fixture), f) && holds(w.bodies[other], n) && heldUpBy(w.def.gravity, f, n);
  };
  for (const auto& [point, pointFixture, other] : {std::tuple{ia, c.a, ib}, std::tuple{ib, c.b, ia}}) {
    if (!restsInPinch(point, pointFixture, other)) continue;
    w.advance(w.bodies[point], c.time);
    const std::array<uint32_t, 2> holders{w.fixtures[w.lastPartnerFixture(point)].body, other};
    sleepOnAwakeBodies(w, point, holders);
    ++w.stats.squeezes;
    return true;
  }
  const bool deep = o.depth > Islands::kJamResidual * std::max(o.ra, o.rb);
  // The wedged one stops moving into the face it was stopped against: the push it took from the other
  // at this instant would carry it through (a point lies on the face, with nothing to tell its side).
  auto stopWedgedAtFaces = [&] {
    for (const WorldState::Wedged& e : w.wedged) {
      if (!wedgedNow(e)) continue;
      BodySlot& held = w.bodies[e.body];
      w.advance(held, c.time);
      const double vn = dot(held.velocity, e.normal);
      if (vn < 0) held.velocity -= e.normal * vn;
      ++held.collisionCount;
      held.last = detail::LastContact{};
      held.stepLocalsSet = true;
    }
  };
  if (held && metNow && !heldAndMetNow && !deep) {
    // One of two disks of a size is held at a face and met again at this instant by the other, which
    // drives it there: each meeting gives the held one a part of the driver's approach, which the face
    // then takes, so the driver loses that part per meeting, about the two masses' ratio. Where the
    // held one is far lighter that is no progress: a speck of 1e-12 of the driver's mass, held at a
    // block's face by a speck of the same size driven at 50 units/s, met it at one instant until the
    // step's budget of 20,000 events ran out (fuzz/regressions/world_api/budget-predictive-feather-
    // speck-held-at-a-block). The meetings converge to the driver stopped against the held
    // one (restitution aside, which only ever adds meetings): so it stops there now, its approach along
    // the normal taken to the held one's once that one stops moving into its face, or to none when the
    // held one comes toward it. It only slows. A pair that does not approach so (a row moving along a
    // floor together, pressed by round-off) is resolved as any other.
    if (std::count_if(w.wedged.begin(), w.wedged.end(), wedgedNow) != 1) return false;  // both held: no driver
    const auto wedgedAt = std::find_if(w.wedged.begin(), w.wedged.end(), wedgedNow);
    const uint32_t heldBody = wedgedAt->body, driverBody = heldBody == ia ? ib : ia;
    Vec2 heldVelocity = w.velocityAt(w.bodies[heldBody], c.time);
    const double intoFace = dot(heldVelocity, wedgedAt->normal);
    if (intoFace < 0) heldVelocity -= wedgedAt->normal * intoFace;
    const Vec2 n = driverBody == ia ? c.normal : -c.normal;  // from the held one toward the driver
    const Vec2 driverVelocity = w.velocityAt(w.bodies[driverBody], c.time);
    const double target = std::min(dot(heldVelocity, n), 0.0);
    const double vn = dot(driverVelocity, n);
    // Beyond round-off only: set to the target, the approach is left at round-off of the two velocities,
    // and a rule that stops it again there meets the pair again at this instant without end (a disk
    // driven down onto one sliding along a floor, 20,000 times).
    const double roundOff = kApproachRoundOff * (length(driverVelocity) + length(heldVelocity));
    if (!(target - vn > roundOff)) return false;
    stopWedgedAtFaces();
    BodySlot& driver = w.bodies[driverBody];
    w.advance(driver, c.time);
    driver.velocity += n * (target - vn);
    ++driver.collisionCount;
    driver.setLast(detail::LastContact{std::min(c.a, c.b), std::max(c.a, c.b), c.feature, c.time});
    ++w.stats.squeezes;
    return true;
  }
  if (!heldAndMetNow && !bothHeldNow && !cuspNow && !pinchNow && !deep) return false;
  if (!held) {
    exemptFromCollisions(w, c.a, c.b);
    return true;
  }
  stopWedgedAtFaces();
  exemptFromCollisions(w, c.a, c.b);
  return true;
}

}  // namespace rattle
