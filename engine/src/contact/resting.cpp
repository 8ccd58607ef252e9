// Resting under gravity: sleeping, sliding, waking.
//
// A ball bouncing on a floor with restitution below 1 makes infinitely many bounces in finite time (a
// Zeno sequence), and a body pressed against something that does not fall with it can otherwise only be
// held by an endless stream of zero-speed collisions. Event-driven codes end this in one of a few ways
// (docs/numerics.md: Luding & McNamara's TC model, a velocity threshold, DynamO's sleeping particles). rattle
// uses a threshold, WorldDef::restingSpeed, and three outcomes for a contact that would bounce slower
// than it against something that does not fall with the body:
//  - sleep: the body is slow and held (the up direction lies within the cone of the normals of the
//    static fixtures and sleeping bodies it touches): it stops and stays until woken;
//  - slide: the body still moves and the contact is a flat face of a static fixture: it keeps its
//    tangential velocity and slides with gravity's tangential part until it leaves the face;
//  - otherwise it bounces off at restingSpeed, which bounds the bounce rate at g / (2 restingSpeed).
#include "contact/resting.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>

#include "collision/closest_point.h"
#include "collision/polyline_impact.h"
#include "collision/polynomial.h"
#include "common/out_of_memory.h"
#include "contact/response.h"
#include "world/world_impl.h"

namespace rattle {

using detail::BodySlot;

namespace {

// The end points of a flat feature (see Impact::feature), in the fixture's coordinates.
bool flatFeature(const Geometry& g, int feature, Vec2& a, Vec2& b) {
  if (const auto* s = std::get_if<Segment>(&g)) {
    a = s->a;
    b = s->b;
    return feature == 0;
  }
  if (const auto* s = std::get_if<Polyline>(&g)) {
    if (feature < 0 || feature + 1 >= static_cast<int>(s->points.size())) return false;
    a = s->points[feature];
    b = s->points[feature + 1];
    return true;
  }
  if (const auto* s = std::get_if<Polygon>(&g)) {
    const int n = static_cast<int>(s->points.size());
    if (feature < 0 || feature >= n) return false;
    a = s->points[feature];
    b = s->points[(feature + 1) % n];
    return true;
  }
  return false;
}

// The far end of the face that shares the start (atEnd false) or the end of flat feature `feature` of
// fixture `f` (a Polyline, a Polygon, or a Segment that has a neighbour there), in the fixture's
// coordinates: the neighbour a point sliding off that end meets.
std::optional<Vec2> neighbourFarEnd(const detail::WorldState& w, uint32_t f, int feature, bool atEnd) {
  const Geometry& g = w.fixtures[f].geometry;
  if (std::holds_alternative<Segment>(g)) {
    const detail::SegmentNeighbours& n = w.segmentNeighbours[f];
    if (atEnd) return n.hasAfter ? std::optional<Vec2>(n.afterEnd) : std::nullopt;
    return n.hasBefore ? std::optional<Vec2>(n.beforeStart) : std::nullopt;
  }
  if (const auto* s = std::get_if<Polyline>(&g)) {
    const auto [before, after] = detail::polylineNeighbours(*s, feature);
    if (atEnd) return after < 0 ? std::nullopt : std::optional<Vec2>(s->points[after + 1]);
    return before < 0 ? std::nullopt : std::optional<Vec2>(s->points[before]);
  }
  if (const auto* s = std::get_if<Polygon>(&g)) {
    const int n = static_cast<int>(s->points.size());
    return s->points[atEnd ? (feature + 2) % n : (feature + n - 1) % n];
  }
  return std::nullopt;
}

// Whether a point at `p` lies on the face: across it within the round-off of the coordinates, as the
// time of impact takes a point to be on a line; along it, as far past its ends as the time of impact
// reaches past a joint (a neighbour's round-off over the sine of the approach, down to 1/64:
// Edge::jointSlackStart). A point resolved in the bottom of a V lay 1.02 round-offs beyond the next
// face's end: taken as off it, it was taken as just arriving there, from below. `frame`: the position of
// the face's body, whose round-off the time of impact adds for a body away from the origin (inFrameOf,
// time_of_impact.cpp); without it a point in a corner of a box 1,000 units out that the time of impact
// took as on the wall's line was taken here as off it, and was sent out through the wall.
bool pointOnFace(Vec2 p, Vec2 a0, Vec2 d, Vec2 frame) {
  const double len = length(d);
  if (!(len > 0)) return false;
  const Vec2 u = d * (1.0 / len), n{-u.y, u.x};
  const double frameSlack = frame.x != 0 || frame.y != 0 ? detail::pointRoundOff(p, frame) : 0.0;
  const double slack = detail::pointRoundOff(p, a0, d) + frameSlack, reach = 65 * slack;
  const double across = dot(n, p - a0), along = dot(u, p - a0);
  return std::fabs(across) <= slack && along >= -reach && along <= len + reach;
}

// The centre of the body's first fixture at `now`: where a point is, for the rules below.
Vec2 firstCentreAt(const detail::WorldState& w, const BodySlot& b, double now) {
  return w.positionAt(b, now) + detail::circleCentre(w.fixtures[b.fixtures.front()].geometry);
}

// Where the body of a face is at `now`: a kinematic body moves within the step, and a point's side of
// its face is read against the face where it is then (a static body's position, as it is).
Vec2 faceBodyAt(const detail::WorldState& w, uint32_t fixture, double now) {
  const BodySlot& body = w.bodyOf(fixture);
  return body.type == BodyType::Kinematic ? w.positionAt(body, now) : body.position;
}

}  // namespace

bool detail::remembersLiveFace(const WorldState& w, const BodySlot& b) {
  if (b.support.generation == 0) return false;  // none: its fixture index means nothing
  const detail::FixtureSlot& face = w.fixtures[b.support.fixture];
  return face.generation == b.support.generation && face.alive;
}

bool detail::pointOnRememberedFace(const WorldState& w, const BodySlot& b, double now) {
  Vec2 f0, f1;
  if (!remembersLiveFace(w, b) || !flatFeature(w.fixtures[b.support.fixture].geometry, b.support.feature, f0, f1)) {
    return false;
  }
  const Vec2 at = faceBodyAt(w, b.support.fixture, now);
  return pointOnFace(firstCentreAt(w, b, now), at + f0, f1 - f0, at);
}

double detail::distanceFromRememberedFace(const WorldState& w, const BodySlot& b, double now) {
  Vec2 f0, f1;
  if (!remembersLiveFace(w, b) || !flatFeature(w.fixtures[b.support.fixture].geometry, b.support.feature, f0, f1)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  const Vec2 at = faceBodyAt(w, b.support.fixture, now);
  return dot(firstCentreAt(w, b, now) - (at + f0), b.support.normal);
}

bool detail::pointKnowsSideOfFace(const WorldState& w, const BodySlot& b, uint32_t fixture, int feature, double now,
                                  Vec2& side) {
  // The remembered face F: its side is remembered. Another face G, of this fixture or another, that
  // meets F at F's end, where the point lies (it is on both lines, in their corner): when G's far end
  // lies on the point's side of F, the corner is a wedge on that side and the point is in it, on the
  // side of G where F's far end lies (the rule leavesCorner uses). Otherwise G lies beyond F's line and
  // the point, which does not cross F, knows nothing of it; nor of a face whose line it is not on.
  Vec2 f0, f1, g0, g1;
  if (!remembersLiveFace(w, b)) return false;
  if (!flatFeature(w.fixtures[b.support.fixture].geometry, b.support.feature, f0, f1)) return false;
  if (!flatFeature(w.fixtures[fixture].geometry, feature, g0, g1)) return false;
  const Vec2 p = firstCentreAt(w, b, now);
  const Vec2 fAt = faceBodyAt(w, b.support.fixture, now);
  const Vec2 gAt = faceBodyAt(w, fixture, now);
  f0 += fAt, f1 += fAt, g0 += gAt, g1 += gAt;
  if (!pointOnFace(p, f0, f1 - f0, fAt)) return false;
  if (fixture == b.support.fixture && feature == b.support.feature) {
    side = b.support.normal;
    return true;
  }
  if (!pointOnFace(p, g0, g1 - g0, gAt)) return false;
  const Vec2 fFar = length(f0 - p) > length(f1 - p) ? f0 : f1;
  const Vec2 gFar = length(g0 - p) > length(g1 - p) ? g0 : g1;
  const Vec2 d = g1 - g0;
  const double len = length(d);
  if (!(len > 0)) return false;
  const Vec2 normal = Vec2{-d.y, d.x} * (1.0 / len);
  const double fSide = dot(normal, fFar - p);
  // F's far end on G's line (two faces on one line): the point is on F's remembered side of both.
  if (std::fabs(fSide) <= 64 * detail::pointRoundOff(p, fFar, d)) {
    side = dot(normal, b.support.normal) >= 0 ? normal : -normal;
    return true;
  }
  // A corner is at F's end: where G crosses F's middle (two boxes that overlap), F's far end tells
  // nothing of the point's side of G. (Taken as telling it, a point sliding on a box's floor, bounced
  // at another box's wall that crosses that floor, was taken to be below the floor and fell through it.)
  const Vec2 fNear = fFar == f0 ? f1 : f0;
  if (!(length(fNear - p) <= 65 * detail::pointRoundOff(p, fNear, f1 - f0))) return false;
  if (!(dot(b.support.normal, gFar - p) > 0)) return false;
  side = fSide > 0 ? normal : -normal;
  return true;
}

namespace {
// The faces of a chain of corners (closed: the last joins the first) that a point lies on, within the
// round-off the time of impact allows, at most two (at a corner): `normalOf` takes each such face's unit
// normal on its right-hand side (the edge turned a quarter clockwise) and gives the one to report, or
// nothing to pass the face over.
template <typename NormalOf>
int chainFacesUnderPoint(const detail::WorldState& w, const BodySlot& b, uint32_t fixture, double now,
                         std::span<const Vec2> corners, bool closed, NormalOf normalOf, Vec2 (&normal)[2]) {
  const Vec2 p = firstCentreAt(w, b, now);
  const Vec2 at = faceBodyAt(w, fixture, now);
  const size_t n = corners.size();
  const size_t faces = closed ? n : (n > 0 ? n - 1 : 0);
  int found = 0;
  for (size_t k = 0; k < faces && found < 2; ++k) {
    const Vec2 a0 = at + corners[k], d = corners[(k + 1) % n] - corners[k];
    if (!pointOnFace(p, a0, d, at)) continue;
    if (const std::optional<Vec2> chosen = normalOf(Vec2{d.y, -d.x} * (1.0 / length(d)))) normal[found++] = *chosen;
  }
  return found;
}
}  // namespace

int detail::polygonFacesUnderPoint(const WorldState& w, const BodySlot& b, uint32_t fixture, double now,
                                   Vec2 (&outward)[2]) {
  const auto* polygon = std::get_if<Polygon>(&w.fixtures[fixture].geometry);
  if (!polygon) return 0;
  // Wound counter-clockwise (the world's form): a face's right-hand side is its outside.
  return chainFacesUnderPoint(
      w, b, fixture, now, polygon->points, true, [](Vec2 right) { return std::optional<Vec2>(right); }, outward);
}

int detail::lineFacesUnderPoint(const WorldState& w, const BodySlot& b, uint32_t fixture, double now, Vec2 against,
                                Vec2 (&normal)[2]) {
  const Geometry& g = w.fixtures[fixture].geometry;
  std::span<const Vec2> corners;
  Vec2 ends[2];
  if (const auto* s = std::get_if<Segment>(&g)) {
    ends[0] = s->a;
    ends[1] = s->b;
    corners = ends;
  } else if (const auto* l = std::get_if<Polyline>(&g)) {
    corners = l->points;
  }
  auto facingAgainst = [against](Vec2 right) -> std::optional<Vec2> {
    const double facing = dot(right, against);
    if (facing == 0) return std::nullopt;
    return facing < 0 ? right : -right;
  };
  return chainFacesUnderPoint(w, b, fixture, now, corners, false, facingAgainst, normal);
}

bool detail::isFlatFeature(const WorldState& w, uint32_t fixture, int feature) {
  Vec2 a, b;
  return flatFeature(w.fixtures[fixture].geometry, feature, a, b);
}

bool detail::leavesCorner(const WorldState& w, const BodySlot& b, uint32_t fixture, int feature, double now) {
  // A point that reached the end of the face it slides on was resolved against the face it met there
  // (fixture, feature) and then began to slide at the same instant: it sits on both lines, in the corner
  // between them, on the side of the second face where the first one lies (it came along the first).
  // The slide took out only the first face's normal part of its velocity; in a corner of 90 degrees or
  // more that leaves it moving away from the second face, in an acute one it may turn it back in.
  // A polygon's corners are convex and met from outside, where the far end of one face lies on the
  // inner side of the other: the rule above would take a point moving into the polygon as leaving it.
  // A polygon's outward normal says which side is out: the point leaves the face if it moves that way
  // (fuzz/regressions/world_api/escape-hybrid-point-along-the-seam-under-a-wall: a point in a wall's
  // corner, just resolved against its bottom face, passed through its side face).
  //
  // A point at rest there moves the way its acceleration takes it. Taken as leaving every face it lies on,
  // a point at rest in the bottom of a V of a Polyline, pressed into one face by gravity, left that face
  // out of its predictions and fell through it.
  Vec2 s0, s1, f0, f1;
  if (!flatFeature(w.fixtures[fixture].geometry, feature, f0, f1)) return true;
  const BodySlot& holder = w.bodies[w.fixtures[fixture].body];
  Vec2 relative = w.velocityAt(b, now) - holder.velocity;
  if (relative == Vec2{}) relative = b.acceleration - holder.acceleration;
  if (std::holds_alternative<Polygon>(w.fixtures[fixture].geometry)) {
    const Vec2 d = f1 - f0;
    const Vec2 outward{d.y, -d.x};  // counter-clockwise points (geometry.h)
    if (dot(relative, outward) >= 0) return true;
    // At a corner the point lies on the other face's line too, and moving out through that face faster
    // than into this one it leaves the polygon there, beside this face's end: this face's line lies
    // beyond the other's. Taken as arriving at this face, a point that bounced off a wall polygon's side
    // face in its corner on a floor polygon (a box on a kinematic body), lifted off the floor by
    // gravity's part across it, met the wall's bottom face from below at once and was sent through the
    // floor. A motion out through the other face slower than into this one is not enough: a point
    // sliding on the floor into the wall, 1e-6 of its speed into the floor by round-off, passed into
    // the wall (PointsInBoxesOfWalls.NoPointLeavesATurnedBoxOfFourPolygons).
    const double into = -dot(relative, outward * (1.0 / length(outward)));
    Vec2 faces[2];
    const int on = polygonFacesUnderPoint(w, b, fixture, now, faces);
    for (int k = 0; k < on; ++k) {
      if (dot(relative, faces[k]) > into) return true;
    }
    return false;
  }
  if (!flatFeature(w.fixtures[b.support.fixture].geometry, b.support.feature, s0, s1)) return true;
  const Vec2 supportAt = faceBodyAt(w, b.support.fixture, now);
  const Vec2 p = firstCentreAt(w, b, now);
  const Vec2 near = supportAt + s0, far = supportAt + s1;
  const Vec2 away = length(near - p) > length(far - p) ? near : far;  // the support's other end
  const Vec2 d = f1 - f0;
  const Vec2 normal{-d.y, d.x};
  const double side = dot(normal, away - p);
  // The two faces on one line (two boxes made in the same place): the far end lies on the other face's
  // line too, and its side is round-off. The point is on the side of both that it remembers, and leaves
  // the other face when it leaves the remembered one. Judged by the round-off, a point that bounced off
  // one box's wall was taken as arriving at the other's from outside, sent out through both, and fell
  // past the boxes' corner (fuzz/regressions/world_api/escape-predictive-point-between-two-boxes-made-as-one).
  const double len = length(d);
  if (len > 0 && std::fabs(side) <= 64 * detail::pointRoundOff(p, away, d) * len) {
    return dot(relative, b.support.normal) >= 0;
  }
  return side == 0 || dot(relative, normal) * side >= 0;
}

int detail::featureLeftByPoint(const WorldState& w, const BodySlot& b, uint32_t fixture, double now,
                               bool leavesRemembered) {
  // A point at rest in a corner of a box lies on two lines at once, where round-off left it, and Support
  // remembers its side of only the face it touched last. Another face whose line it is on cannot tell its
  // side either: a contact with it at this instant (from outside, the time of impact would take it, for
  // a point moving into the box) overwrote the side it remembered, and from a few ulps below the floor's
  // line it fell out through the corner (fuzz/regressions/world_api/escape-predictive-point-woken-in-a-
  // corner). The remembered face's far end lies on the inner side of each such face (the point came along
  // it, as leavesCorner takes it), so a point leaving the remembered face, or just resolved against it,
  // that moves to that side of every other face it is on leaves them all: kEveryFeature. Otherwise the
  // remembered face alone. The corner may be between two fixtures (two Segments meeting in a V): asked
  // about a fixture other than the remembered one, every face of it counts, and the answer when it
  // leaves none is kNoFeature, and when it leaves one face alone, that face: a point in the corner of
  // a box's floor and its wall, a separate Polygon whose bottom face lies on the floor's line, leaves
  // that bottom face as it moves along the floor, and taken as leaving every face of the wall it passed
  // through the wall's side, 2e-13 ahead of it, without a prediction (fuzz/regressions/world_api/
  // escape-hybrid-two-points-meet-in-a-corner-of-two-walls).
  // A point in a corner of a Polyline that rests on one face and is sent off across it leaves the other
  // face there but not this one: taken as arriving at the other from outside, it bounced out through it.
  const bool remembered = fixture == b.support.fixture;
  const int otherwise = remembered && leavesRemembered ? b.support.feature : kNoFeature;
  const Geometry& g = w.fixtures[fixture].geometry;
  const Vec2 at = faceBodyAt(w, fixture, now);
  const Vec2 p = firstCentreAt(w, b, now);
  int left = otherwise;
  Vec2 e0, e1;
  for (int f = 0; flatFeature(g, f, e0, e1); ++f) {
    if (remembered && f == b.support.feature) continue;
    if (!pointOnFace(p, at + e0, e1 - e0, at)) continue;
    if (!leavesCorner(w, b, fixture, f, now)) return otherwise;
    left = left == kNoFeature ? f : kEveryFeature;
  }
  return left;
}

namespace {

// What the static fixtures and sleeping bodies a body touches give it to rest on: their unit normals
// toward it at the points it touches, and the sleeping bodies among them (supporters).
struct Holds {
  Vec2 normals[16];
  int count = 0;
  void add(Vec2 n) {
    if (count < 16) normals[count++] = n;
  }
};

// Touching: within round-off, or within the height of a bounce at restingSpeed (v^2 / 2g, doubled),
// since a body bouncing between two supports at that speed touches them one at a time.
double touchReach(const detail::WorldState& w, double radius) {
  return 1e-7 * std::max(radius, 1e-9) + w.def.restingSpeed * w.def.restingSpeed / length(w.def.gravity);
}

// The dynamic holders (sleepers) go to `supporters` when it is given.
void holdsOfFixedBodies(const detail::WorldState& w, uint32_t bodyIndex, double now, Vec2 up, Holds& holds,
                        std::vector<uint32_t>* supporters) {
  const BodySlot& body = w.bodies[bodyIndex];
  for (const auto& pair : w.pairsOfBody[bodyIndex]) {
    const detail::FixtureSlot& own = w.fixtures[pair.own];
    const detail::FixtureSlot& other = w.fixtures[pair.other];
    if (own.sensor || other.sensor) continue;
    const BodySlot& holder = w.bodies[other.body];
    if (holder.type != BodyType::Static && !holder.asleep) continue;
    const Vec2 centre = w.positionAt(body, now) + detail::circleCentre(own.geometry);
    const double radius = detail::circleRadius(own.geometry);
    // Every piece it touches: in the corner of one Polyline the floor holds it up and the wall beside
    // it, and the closest point alone (the wall's, at a tie) left a disk at rest there awake for ever.
    detail::forEachClosestPoint(other.geometry, holder.position, centre, [&](const detail::Closest& closest) {
      if (!closest.collidable) return;
      const Vec2 r = centre - closest.point;
      const double distance = length(r);
      if (!(distance > 0) || distance - radius > touchReach(w, radius)) return;
      const Vec2 n = r * (1.0 / distance);
      // Beside (a wall) still helps to hold it, together with something below (the cone test); so does
      // a round piece above and beside it, a sleeper or a static circle: a disk pressed into a sleeper's
      // slope by a sleeper above it is wedged, and bounced off the slope at restingSpeed it rattled
      // between the two for ever (rattle-soak's predictive pile of 300). A flat static face above it
      // holds nothing here: under an overhanging wall the disk slides down its slope into the corner,
      // where it rests exactly.
      const bool flat = holder.type == BodyType::Static && !std::holds_alternative<Circle>(other.geometry) &&
                        !std::holds_alternative<Point>(other.geometry);
      if (flat && dot(n, up) < -1e-12) return;
      holds.add(n);
      if (supporters && holder.type == BodyType::Dynamic &&
          std::find(supporters->begin(), supporters->end(), other.body) == supporters->end()) {
        supporters->push_back(other.body);
      }
    });
  }
}

// Held when up lies within the cone of the normals: one normal straight up (a level floor), or two on
// either side of up (a cradle of two disks, a wedge).
bool upWithinCone(const Holds& holds, Vec2 up) {
  const Vec2* normals = holds.normals;
  for (int i = 0; i < holds.count; ++i) {
    if (dot(normals[i], up) >= 1 - 1e-12) return true;
    for (int j = 0; j < holds.count; ++j) {
      if (cross(normals[i], up) >= 0 && cross(up, normals[j]) >= 0 && cross(normals[i], normals[j]) > 0) return true;
    }
  }
  return false;
}

}  // namespace

bool detail::supportsAt(const WorldState& w, uint32_t bodyIndex, double now, std::vector<uint32_t>& supporters,
                        Vec2 contactNormal, uint32_t holderIndex) {
  const BodySlot& body = w.bodies[bodyIndex];
  const Vec2 up = -w.def.gravity * (1.0 / length(w.def.gravity));
  supporters.clear();
  Holds holds;
  holdsOfFixedBodies(w, bodyIndex, now, up, holds, &supporters);
  // A point touches at distance 0, where the pieces it touches give no direction: the contact at hand
  // and the face it slides on do. Without them a point that slid into the bottom of a V of two faces
  // could never rest there: it slid down one face into the other, and down that one back into the
  // first, ever faster, until the step's budget ran out, step after step.
  if (detail::isPoint(w.fixtures[body.fixtures.front()].geometry)) {
    // Static holders only: a point inside a disk (squeezed into it, passing through) touches nothing
    // there that holds it.
    // A face above it counts too: in an acute corner under an overhang the floor and the overhang hold
    // a point together (up lies within the cone of their normals), and the cone test below asks for
    // both.
    auto add = [&](Vec2 n, uint32_t holder) {
      if (w.bodies[holder].type == BodyType::Static) holds.add(n);
    };
    if (contactNormal.x != 0 || contactNormal.y != 0) add(contactNormal, holderIndex);
    // The face it remembers (Support) while it still lies on it: sliding there, or in a corner where it
    // bounces from one face to the other at one instant without end (a Zeno sequence the predictive
    // guard ends, sleepIfZeno), where the contact at hand gives one face and the memory the other.
    const detail::Support& face = body.support;
    if (remembersLiveFace(w, body)) {
      Vec2 e0, e1;
      const Vec2 at = faceBodyAt(w, face.fixture, now);
      if (body.sliding || (flatFeature(w.fixtures[face.fixture].geometry, face.feature, e0, e1) &&
                           pointOnFace(firstCentreAt(w, body, now), at + e0, e1 - e0, at))) {
        add(face.normal, w.fixtures[face.fixture].body);
      }
    }
  }
  return upWithinCone(holds, up);
}

bool detail::leansOnSlowNeighbour(const WorldState& w, uint32_t bodyIndex, double now,
                                  std::vector<uint32_t>& supporters) {
  // Two free disks each on one sleeper's slope and leaning on each other, an arch of two, are held by
  // each other, and neither alone: bounced off its sleeper at restingSpeed each time, each rattled for
  // ever against the other and kept a pile of 300 awake (a minute of rattle-soak's pile). The forces
  // that hold them exist when up lies within the cone of each one's normals, the other's included.
  const BodySlot& body = w.bodies[bodyIndex];
  if (body.stepped || detail::isPoint(w.fixtures[body.fixtures.front()].geometry)) return false;
  const Vec2 up = -w.def.gravity * (1.0 / length(w.def.gravity));
  supporters.clear();
  Holds own;
  holdsOfFixedBodies(w, bodyIndex, now, up, own, &supporters);
  if (own.count == 0) return false;
  for (const auto& pair : w.pairsOfBody[bodyIndex]) {
    const detail::FixtureSlot& mine = w.fixtures[pair.own];
    const detail::FixtureSlot& theirs = w.fixtures[pair.other];
    const BodySlot& other = w.bodies[theirs.body];
    if (mine.sensor || theirs.sensor || other.type != BodyType::Dynamic || other.asleep || other.stepped) continue;
    if (detail::isPoint(theirs.geometry) || !(length(w.velocityAt(other, now)) < w.def.restingSpeed)) continue;
    if (std::binary_search(w.beingParted.begin(), w.beingParted.end(), theirs.body)) continue;
    const Vec2 r = w.positionAt(body, now) + detail::circleCentre(mine.geometry) -
                   (w.positionAt(other, now) + detail::circleCentre(theirs.geometry));
    const double distance = length(r);
    const double radius = std::min(detail::circleRadius(mine.geometry), detail::circleRadius(theirs.geometry));
    const double gap = distance - detail::circleRadius(mine.geometry) - detail::circleRadius(theirs.geometry);
    if (!(distance > 0) || gap > touchReach(w, radius)) continue;
    const Vec2 n = r * (1.0 / distance);  // toward this body
    Holds withOther = own;
    withOther.add(n);
    if (!upWithinCone(withOther, up)) continue;
    Holds theirsHeld;
    holdsOfFixedBodies(w, theirs.body, now, up, theirsHeld, nullptr);
    theirsHeld.add(-n);
    if (!upWithinCone(theirsHeld, up)) continue;
    supporters.push_back(theirs.body);
    return true;
  }
  return false;
}

void detail::sleepIfZeno(WorldState& w, uint32_t bodyIndex, double now, Vec2 contactNormal, uint32_t holder) {
  // A body wedged where the independent-collision model needs infinitely many bounces (a narrowing gap
  // between a wall and a resting disk) collides ever faster without coming to rest. Once it has collided
  // kZenoCollisions times in one step while held up by static or sleeping bodies, it sleeps where it is,
  // before the contact at hand, so that contact sees it as resting. (The hybrid step resolves such
  // clusters at once instead: jam.cpp.)
  constexpr int kZenoCollisions = 64;
  BodySlot& s = w.bodies[bodyIndex];
  if (!(w.def.restingSpeed > 0) || (w.def.gravity.x == 0 && w.def.gravity.y == 0)) return;
  if (s.type != BodyType::Dynamic || s.asleep) return;
  if (s.countStepCollision() > kZenoCollisions && supportsAt(w, bodyIndex, now, w.supporters, contactNormal, holder)) {
    putToSleep(w, bodyIndex, w.supporters);
  }
}

void detail::putToSleep(WorldState& w, uint32_t bodyIndex, std::span<const uint32_t> supporters) {
  BodySlot& b = w.bodies[bodyIndex];
  w.keep(b);
  b.asleep = true;
  b.stepped = false;
  b.velocity = {};
  b.acceleration = {};
  b.clearSupport();
  ++b.collisionCount;
  for (uint32_t s : supporters) w.dependents[s].push_back(bodyIndex);
}

void detail::placePointOnFace(WorldState& w, BodySlot& b, const PredictedContact& c) {
  // Beyond the joint of an apex lies the outside, and soon the fixture's box: a point that came to rest
  // there, or bounced off there, a few round-offs past the end of both faces, was no longer a candidate
  // of either, and a throw from the game sent it out of the tip. Across the face (the contact's point
  // is the point's projection on the face's line) it is within the round-off of the time of impact; only
  // along the face, beyond its end, is it farther.
  if (!detail::isPoint(w.fixtures[c.a].geometry) || w.bodyOf(c.b).type != BodyType::Static) return;
  Vec2 f0, f1;
  if (!flatFeature(w.fixtures[c.b].geometry, c.feature, f0, f1)) return;
  const Vec2 origin = w.bodyOf(c.b).position;
  f0 += origin, f1 += origin;
  const Vec2 centre = firstCentreAt(w, b, c.time);
  const double len = length(f1 - f0);
  const double tau = dot(centre - f0, f1 - f0) / len;
  // Beyond the face's end by more than the time of impact's own reach there (its round-off): only a
  // joint's reach puts it there.
  const double slack = detail::pointRoundOff(centre, f0, f1 - f0);
  if (!(tau < -slack || tau > len + slack)) return;
  const Vec2 at = c.point - detail::circleCentre(w.fixtures[c.a].geometry);
  if (length(at - b.position) <= 0x1p-20 * (length(at) + 1)) b.position = at;
}

void detail::sleepOnAwakeBodies(WorldState& w, uint32_t bodyIndex, std::span<const uint32_t> supporters) {
  putToSleep(w, bodyIndex, supporters);
  auto& list = w.sleepersOnAwakeBodies;
  for (uint32_t supporter : supporters) {
    const std::pair<uint32_t, uint32_t> entry{bodyIndex, supporter};
    const auto at = std::lower_bound(list.begin(), list.end(), entry);
    if (at == list.end() || *at != entry) list.insert(at, entry);
  }
}

void detail::wakeSleepersOfMovingBodies(WorldState& w) {
  // A sleeper is held by what it rests on until that wakes (dependents). An awake body holds one only
  // while it stays where it is: a stepped body at rest in its island. Moving, or no longer stepped, it
  // lets the sleeper fall again, at the next step's start (so at most a step late).
  auto& list = w.sleepersOnAwakeBodies;
  if (list.empty()) return;
  std::vector<uint32_t> woken;
  std::erase_if(list, [&](const std::pair<uint32_t, uint32_t>& e) {
    const BodySlot& sleeper = w.bodies[e.first];
    const BodySlot& holder = w.bodies[e.second];
    if (!sleeper.alive || !sleeper.asleep) return true;
    if (holder.alive && holder.asleep) return true;  // an ordinary sleeper's holder now: its wake wakes it
    if (holder.alive && holder.stepped && holder.velocity == Vec2{}) return false;
    wakeUp(w, e.first, 0.0, woken);
    return true;
  });
  for (uint32_t i : woken) w.touched(i);
}

void detail::findSleepersOnAwakeBodies(WorldState& w) {
  w.sleepersOnAwakeBodies.clear();
  for (uint32_t s = 0; s < w.bodies.size(); ++s) {
    if (!w.bodies[s].alive || w.bodies[s].asleep) continue;
    for (uint32_t d : w.dependents[s]) {
      if (w.bodies[d].alive && w.bodies[d].asleep) w.sleepersOnAwakeBodies.emplace_back(d, s);
    }
  }
  std::sort(w.sleepersOnAwakeBodies.begin(), w.sleepersOnAwakeBodies.end());
  w.sleepersOnAwakeBodies.erase(std::unique(w.sleepersOnAwakeBodies.begin(), w.sleepersOnAwakeBodies.end()),
                                w.sleepersOnAwakeBodies.end());
}

void detail::wakeUp(WorldState& w, uint32_t bodyIndex, double now, std::vector<uint32_t>& woken) {
  const size_t from = woken.size();
  collectWake(w, bodyIndex, woken);
  applyWake(w, woken, from, now);
}

void detail::collectWake(const WorldState& w, uint32_t bodyIndex, std::vector<uint32_t>& woken) {
  if (!w.bodies[bodyIndex].alive || !w.bodies[bodyIndex].asleep) return;  // a game's every tick: no allocation
  // Iterative, in a fixed order: a tall pile wakes layer by layer without deep recursion. A body is
  // listed once, at its first visit; `seen` (sorted) holds what `woken` holds.
  std::vector<uint32_t> seen(woken.begin(), woken.end());
  std::sort(seen.begin(), seen.end());
  std::vector<uint32_t> stack{bodyIndex};
  while (!stack.empty()) {
    const uint32_t i = stack.back();
    stack.pop_back();
    const BodySlot& b = w.bodies[i];
    if (!b.alive || !b.asleep) continue;
    const auto at = std::lower_bound(seen.begin(), seen.end(), i);
    if (at != seen.end() && *at == i) continue;
    seen.insert(at, i);
    woken.push_back(i);
    const std::vector<uint32_t>& held = w.dependents[i];
    for (auto it = held.rbegin(); it != held.rend(); ++it) stack.push_back(*it);
  }
}

void detail::applyWake(WorldState& w, const std::vector<uint32_t>& woken, size_t from, double now) {
  for (size_t k = from; k < woken.size(); ++k) {
    const uint32_t i = woken[k];
    BodySlot& b = w.bodies[i];
    w.keep(b);
    // It rested until now: its fall starts at this instant, not at the start of the step.
    b.asleep = false;
    b.localTime = now;
    b.acceleration = w.def.gravity;
    ++b.collisionCount;
    std::vector<uint32_t>& held = w.dependents[i];
    if (w.stepStart.active && !held.empty()) {
      // Kept whole for undoStep (the room made first, so that the move cannot fail half way).
      detail::roomForOneMore(w.stepStart.dependents);
      w.stepStart.dependents.emplace_back(i, std::move(held));
    }
    held.clear();
  }
}

void detail::startSliding(WorldState& w, uint32_t bodyIndex, uint32_t fixture, int feature, Vec2 contactNormal) {
  BodySlot& b = w.bodies[bodyIndex];
  w.keep(b);
  // An edge's normal is unit only to an ulp (a direction times a rounded reciprocal length): projecting
  // with it left a slide on a level floor a downward acceleration of 1e-16 g, and a point (which has no
  // overlap to hold it up) fell into the floor again and again at one instant until it fell through
  // (fuzz/regressions/world_api/escape-point-falling-on-a-floor). Divided by its length, a level or
  // upright face's normal is exact, and so is the slide along it.
  const double norm = length(contactNormal);
  const Vec2 normal{contactNormal.x / norm, contactNormal.y / norm};
  b.setSupport(detail::Support{fixture, w.fixtures[fixture].generation, feature, normal});
  b.velocity -= normal * dot(b.velocity, normal);
  b.acceleration = w.def.gravity - normal * dot(w.def.gravity, normal);
}

void detail::keepSlidingPointOnFace(WorldState& w, BodySlot& b, uint32_t fixture) {
  // A slide keeps a body on its face's line only while its velocity runs along it. An impulse at a
  // corner (the approach to the other face absorbed, or a bounce from it at one instant) leaves a few
  // ulps of the speeds it acted on across the slide's face, and a point, which has no overlap to hold it
  // to the face, drifts off the line by that much for as long as it slides: 1.7e-13 units/s for ten
  // steps took one 3.7e-13 below a floor, past the round-off by which the next face of its corner reaches
  // past the joint, and it passed under the joint; 2e-11 units/s for 0.2 s took another 4e-12 out of its
  // container, where nothing was met again. A disk's gap tells its side, so disks are left as they were.
  if (!b.sliding || !detail::isPoint(w.fixtures[fixture].geometry)) return;
  const double across = dot(b.velocity, b.support.normal);
  if (across == 0) return;
  w.keep(b);
  b.velocity -= b.support.normal * across;
}

void detail::stopSliding(WorldState& w, BodySlot& b) {
  w.keep(b);
  b.clearSupport();
  if (!b.asleep) b.acceleration = w.def.gravity;
}

bool detail::stopPointAtRest(WorldState& w, const PredictedContact& c, double vn) {
  // A contact that closes no more than the round-off of its coordinates within the step is at rest and
  // dismissed for the step, and a body's overlap tells its side again at the next. A point has none:
  // left with the last few ulps of a run of bounces in a corner (5.5e-14 units/s, out through the
  // corner), it was dismissed step after step and drifted on, 5e-13 outside after twenty steps, beyond
  // the round-off of the faces and out of its container's box, where no face was a candidate any more.
  // At rest by that tolerance, it is stopped.
  if (!(vn < 0)) return false;
  BodySlot& a = w.bodyOf(c.a);
  if (a.type != BodyType::Dynamic || a.asleep || w.bodyOf(c.b).type != BodyType::Static) return false;
  if (!detail::isPoint(w.fixtures[c.a].geometry)) return false;
  w.advance(a, c.time);
  a.velocity = Vec2{};
  ++a.collisionCount;
  return true;
}

std::optional<double> detail::slideEndTime(const WorldState& w, const BodySlot& b, double now, double dt) {
  const detail::FixtureSlot& face = w.fixtures[b.support.fixture];
  Vec2 a, e;
  flatFeature(face.geometry, b.support.feature, a, e);
  const Vec2 origin = w.bodies[face.body].position + a;
  const double len = length(e - a);
  const Vec2 u = (e - a) * (1.0 / len);
  const Vec2 centre = firstCentreAt(w, b, now);
  const Vec2 v = w.velocityAt(b, now);
  // tau(h) = u.(c - a) + (u.v) h + (u.g) h^2 / 2 leaves [0, len] at the first downward crossing of
  // tau or of len - tau.
  detail::Polynomial tau;
  tau.degree = 2;
  tau.c = {dot(u, centre - origin), dot(u, v), 0.5 * dot(u, b.acceleration)};
  // A point's face reaches the round-off of its coordinates past its ends, as its time of impact does
  // (time_of_impact.h): one that came to rest in a corner an ulp beyond the floor's end is on the floor,
  // and does not fall off it at once to land on it again.
  const bool point = detail::circleRadius(w.fixtures[b.fixtures.front()].geometry) == 0;
  const double slack = detail::pointRoundOff(centre, origin, e - a);
  // Twice that: where the slide ends, its face's time of impact must no longer reach the point, or the
  // two took turns at one instant, the contact starting the slide again and the slide ending at once.
  // A disk's face reaches only to its ends, but round-off puts the disk back on the face as often as
  // past it where the slide ends exactly there: a disk driven off a ledge under gravity took sixteen
  // such turns and was then held at the ledge's height for the rest of the step, and one made on the
  // seam of a block's two Polygons took them until the event budget ran out (tests: GravityBall.A-
  // SlideEndsAtTheEndOfALedgeAndTheBallFallsFromThere). Its slide ends as far past the end as a point's.
  tau.c[0] += 2 * slack;
  detail::Polynomial rest = tau;
  for (double& c : rest.c) c = -c;
  rest.c[0] += len + 4 * slack;
  // An end where the neighbouring face turns back over this one's side is the apex of an acute wedge
  // (a nearly straight joint, which a slide passes on to the next face, is not): beyond it lies the
  // outside, and the point meets the neighbour at the joint, which its time of impact finds up to the
  // neighbour's round-off over the sine of the apex past the joint (time_of_impact.cpp). The slide ends
  // beyond that, so that the neighbour comes first: ended 2 round-offs past the joint of an apex of half
  // a degree, the point was already outside the neighbour's end, and fell out of the tip.
  if (point) {
    for (const bool atEnd : {false, true}) {
      const auto far = neighbourFarEnd(w, b.support.fixture, b.support.feature, atEnd);
      const Vec2 joint = atEnd ? e : a;
      if (!far || !(dot(*far - joint, b.support.normal) > 0) || !(dot(*far - joint, atEnd ? -u : u) > 0)) continue;
      const Vec2 d = *far - joint;
      const double sine = std::fabs(cross(u, d)) / length(d);
      // The neighbour's time of impact reaches past the joint by this face's round-off over the sine
      // of the point's approach, at least half the apex's (time_of_impact.cpp); a needle's two faces
      // have about the same round-off, and the larger of the two is taken.
      const double roundOff = std::max(detail::pointRoundOff(*far, joint, d), detail::pointRoundOff(a, e, e - a));
      const double reach = 2 * roundOff / std::max(sine, 0x1p-40) + 2 * slack;
      (atEnd ? rest : tau).c[0] += reach;
    }
  }
  auto low = detail::firstDownwardCrossing(tau, 0, dt - now);
  auto high = detail::firstDownwardCrossing(rest, 0, dt - now);
  if (tau.c[0] < 0 || rest.c[0] < 0) return now;  // already past an end
  std::optional<double> h = low;
  if (high && (!h || *high < *h)) h = high;
  if (!h) return std::nullopt;
  return now + *h;
}

}  // namespace rattle
