// Exact times of impact for a circle in linear motion against each geometry, and the dispatch table.
//
// All functions work in B's frame (B at rest) and follow the rules in time_of_impact.h. Two kernels do
// the work: a circle against a circle (a quadratic in t) and a circle against one edge line (linear in
// t); segments, polylines and polygons are made of those, taking the earliest impact and, on equal
// times, the lowest feature index, so ties resolve the same way on every run.
#include "rattle/time_of_impact.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "collision/closest_point.h"
#include "collision/plain_disk_impact.h"
#include "collision/polyline_impact.h"
#include "collision/polynomial.h"

namespace rattle {

using detail::Polynomial;

namespace {

bool accelerates(const Motion& m) { return m.acceleration.x != 0 || m.acceleration.y != 0; }

Vec2 travel(const Motion& m, double t) { return m.velocity * t + m.acceleration * (0.5 * t * t); }

// The rules of Bannerman et al. (2014) for a gap function f (f < 0: overlapping) over [0, maxTime]:
//  f(0) > 0: the first downward crossing;
//  f(0) <= 0 and approaching (f'(0) < 0, or f'(0) = 0 with f''(0) < 0): now;
//  f(0) <= 0 and separating: nothing until f' turns negative; if f <= 0 still then, that instant,
//  otherwise the first downward crossing after it.
// `justResolved`: this contact was resolved at this very instant, so it is separating whatever round-off
// says about f(0) and f'(0); only the separating branch applies (a bounce under gravity comes back).
std::optional<double> firstImpactOfGap(const Polynomial& f, double maxTime, bool justResolved) {
  if (!justResolved) {
    if (!(f.c[0] <= 0)) return detail::firstDownwardCrossing(f, 0, maxTime);
    if (f.c[1] < 0 || (f.c[1] == 0 && f.c[2] < 0)) return 0.0;
  }
  const auto turn = detail::firstDownwardCrossing(f.derivative(), 0, maxTime);
  if (!turn) return std::nullopt;
  if (f(*turn) <= 0) return *turn;
  return detail::firstDownwardCrossing(f, *turn, maxTime);
}

// timeToReach under acceleration: f(t) = |r + v t + a t^2/2|^2 - reach^2, a quartic.
[[gnu::noinline]] std::optional<double> timeToReachAccelerating(Vec2 r, const Motion& m, double reach, double maxTime,
                                                               bool justResolved) {
  const Vec2 v = m.velocity;
  const Vec2 a = m.acceleration;
  Polynomial f;
  f.degree = 4;
  f.c = {dot(r, r) - reach * reach, 2 * dot(r, v), dot(v, v) + dot(r, a), dot(v, a), 0.25 * dot(a, a)};
  return firstImpactOfGap(f, maxTime, justResolved);
}

// First time the distance between two centres, r + v t + a t^2/2, closes to `reach` while approaching.
// Inlined into its callers: most pairs that a broad phase hands over never meet, and returned through
// memory the optional's flag byte is written and then read back as part of a wider word, which stalls
// (a failed store-to-load forward) on every call.
[[gnu::always_inline]] inline std::optional<double> timeToReach(Vec2 r, const Motion& m, double reach, double maxTime,
                                                               bool justResolved) {
  const Vec2 v = m.velocity;
  if (accelerates(m)) return timeToReachAccelerating(r, m, reach, maxTime, justResolved);
  // Linear: f(t) = A t^2 + 2 b t + c with A = v.v, b = r.v, c = r.r - reach^2.
  const double c = dot(r, r) - reach * reach;
  const double b = dot(r, v);
  if (c <= 0) {
    // Touching or overlapping (by round-off, or because bodies were placed so): the sign of f'(0) = 2b
    // decides. Approaching collides now; separating or sliding gets no event. A straight path that
    // has just been resolved separates and never comes back.
    if (b < 0 && !justResolved) return 0.0;
    return std::nullopt;
  }
  // Two points just resolved against each other have parted along one line (as plainTimeToReach).
  if (b >= 0 || (reach == 0 && justResolved)) return std::nullopt;
  const double A = dot(v, v);
  const double disc = detail::reachDiscriminant(r, v, b, A, c, reach);
  // disc = 0 is a tangent touch, a double root: not an event. So is a pass whose deepest overlap,
  // -disc / A = min |r + v t|^2 - reach^2, is within round-off of zero (1e-12 reach^2, a depth of
  // 5e-13 reach): it is what a body sliding along a surface by an ulp meets at the surface's corner,
  // and resolving it would kick the body sideways by speed x sqrt(2 depth / reach). Two points (reach
  // 0) meet only at a double root, when their paths are on one line exactly (head-on): that is an event.
  if (!(disc > 1e-12 * A * reach * reach) && !(reach == 0 && disc == 0)) return std::nullopt;
  // The smaller root (-b - sqrt(disc)) / A cancels when c -> 0; its conjugate form has a sum of two
  // positive terms below: t = c / (-b + sqrt(disc)).
  const double t = c / (-b + std::sqrt(disc));
  if (!(t <= maxTime)) return std::nullopt;
  return t;
}

Impact pointImpact(Vec2 center, const Motion& m, Vec2 target, double targetRadius, double t, int feature) {
  Vec2 r = center + travel(m, t) - target;
  double len = length(r);
  // Coincident centres happen only for two points; push back along the motion then. So when round-off
  // put two points a hair past each other at their meeting (a normal along the motion, which is never
  // the normal of an approach).
  const Vec2 velocityThen = m.velocity + m.acceleration * t;
  const bool backwards =
      len > 0 && dot(r, velocityThen) >= 0 && targetRadius == 0 && len <= 0x1p-40 * length(center - target);
  Vec2 n = len > 0 && !backwards ? r * (1.0 / len)
                                 : (length(m.velocity) > 0 ? -m.velocity * (1.0 / length(m.velocity)) : Vec2{1, 0});
  return Impact{t, target + n * targetRadius, n, feature};
}

struct Edge {
  Vec2 a;
  Vec2 u;  // unit direction from a along the edge
  Vec2 n;  // unit normal on the side that collides
  double length;
  // How far off its line round-off leaves a point on a neighbouring face that shares this edge's start
  // or end (a polyline's previous or next segment): such a point reaches this edge's line that far
  // over the sine of its angle of approach past the shared end (faceImpact).
  double jointSlackStart = 0, jointSlackEnd = 0;
  // The far ends of those neighbours, when known (a Polyline's): where one lies on the colliding side,
  // the joint is the apex of a wedge the point is in.
  const Vec2* beforeStart = nullptr;
  const Vec2* afterEnd = nullptr;
  // How far off the line a point is on it: the round-off of the line's two ends and the point's
  // coordinates, the bound the resting rules use for a point on a face (featureLeftByPoint). The line's
  // start alone was too tight: a point that slid down one face of a V into the joint and was resolved
  // there lay off the other face's line by more, on its far side, and went through it.
  double pointSlack(Vec2 centre) const { return detail::pointRoundOff(centre, a, u * length) + frameSlack; }
  // The round-off a point's coordinates carry from the world's frame into this one (a shape of a body
  // far from the origin, whose own coordinates are small): see inFrameOf.
  double frameSlack = 0;
};

Edge edgeOf(Vec2 a, Vec2 b) {
  Vec2 d = b - a;
  double len = length(d);
  Vec2 u = d * (1.0 / len);
  // Outward normal of a counter-clockwise polygon's edge: the edge direction turned clockwise.
  return Edge{a, u, Vec2{u.y, -u.x}, len};
}

// The circle against the face of one edge that `edge.n` points out of. The signed distance of the centre
// from the edge's line is s(t) = s0 + vn t + an t^2/2; the gap s(t) - r is linear or quadratic. The
// impact counts only if the contact point then lies on the edge (0 <= tau <= length): an edge's ends are
// not corners. `front`: the centre starts on this face's side, so the overlap rules apply; otherwise only
// a crossing from outside counts.
// A circle of radius 0 (a point) meets a corner only on an exact line (timeToReach with reach 0), so a
// point sliding exactly along one edge into the next, or along the seam of two polygons that share a
// line, meets the next edge at its end, where round-off puts tau an ulp outside: that ulp is taken as on
// the edge. So too for bare segments that meet end to end (a box of four): a point sliding an ulp below
// the floor's line, where round-off leaves it, crosses the wall's line an ulp beyond the wall's end, and
// left the box through its corner (fuzz/regressions/world_api/escape-point-predictive-dt1-through-the-
// floor-corner). A segment's end still does not collide as a corner: only its face reaches an ulp further.
std::optional<Impact> faceImpact(const Circle& circle, const Motion& m, const Edge& edge, bool front, double maxTime,
                                 int feature, bool justResolved) {
  const Vec2 rel = circle.center - edge.a;
  double s0 = dot(edge.n, rel);
  // A point (radius 0) has no overlap to tell it is still in front: an ulp behind the line (where
  // round-off puts a point that came to rest on a floor, in a frame other than the floor's) is on it.
  if (circle.radius == 0 && s0 < 0 && s0 >= -edge.pointSlack(circle.center)) s0 = 0;
  // Nor was a point well off the line just resolved against this face: kEveryFeature names every face
  // of a Polyline after a corner, and a point that left a corner of one, taken as leaving a face far
  // from it as well, was never predicted to meet that face and passed through it. (Well off: a point
  // just resolved at a joint lies off the line by up to a few times pointSlack, which must not read as
  // arriving from the far side.)
  if (circle.radius == 0 && std::fabs(s0) > 64 * edge.pointSlack(circle.center)) justResolved = false;
  Polynomial gap;
  gap.degree = 2;
  gap.c = {s0 - circle.radius, dot(edge.n, m.velocity), 0.5 * dot(edge.n, m.acceleration)};
  // A circle moving along the face, its normal velocity and acceleration round-off (sliding on a sloped
  // face, or a point along the seam of a wall's bottom face and the floor it stands on), meets it at no
  // time. Read from the round-off, one that slid on a face met it at once (a gap of {0, 0, -2e-16}),
  // was dismissed and was predicted again at that instant until the step's budget of predictions ran
  // out, and the wall at the end of the slide then went unpredicted: a point left a turned box of
  // Polygons, and a disk wedged in an acute corner of a Polyline fell out of it. (segmentImpact's
  // alongLine is the same rule for a point on a Segment's line.)
  const bool alongFace = std::fabs(gap.c[1]) <= detail::kAbsorbRoundOff * length(m.velocity);
  if (alongFace && std::fabs(gap.c[2]) <= 0.5 * detail::kPressRoundOff * length(m.acceleration)) return std::nullopt;
  // A point on the line (within round-off) moving along it is on the side its acceleration takes it to.
  if (circle.radius == 0 && alongFace && std::fabs(s0) <= edge.pointSlack(circle.center)) gap.c[1] = 0;
  std::optional<double> t;
  // A point exactly on the line touches it (a closed edge): the overlap rules apply, as they do to a
  // circle whose gap is exactly 0.
  if (front && (s0 > -circle.radius || s0 == 0)) {
    t = firstImpactOfGap(gap, maxTime, justResolved);
  } else {
    // Centre a full radius behind the line (or on the segment's other side): only coming round to the
    // front and then closing in counts.
    t = detail::firstDownwardCrossing(gap, 0, maxTime);
    // A centre exactly on a segment's line that was just resolved there crosses neither face now.
    if (t && *t == 0 && justResolved) t = detail::firstDownwardCrossing(gap, std::nextafter(0.0, 1.0), maxTime);
  }
  if (!t) return std::nullopt;
  const Vec2 along = rel + travel(m, *t);
  double tau = dot(edge.u, along);
  if (circle.radius == 0) {
    const double slack = detail::pointRoundOff(circle.center, edge.a, along) + edge.frameSlack;
    // A point that slid down one segment of a polyline into a valley lies off that segment's line by
    // its round-off, and meets the next segment's line that far over the sine of the angle between
    // them before or past the joint. Missed there, it passed under the joint and out of the valley, or
    // it slid on past the first segment's end into the same segment at one instant without end. (Not
    // for a point moving nearly along this edge: it slides off the joint's end, and its slide ends
    // within `slack`, resting.cpp.)
    double start = slack, end = slack;
    if (edge.jointSlackStart > 0 || edge.jointSlackEnd > 0) {
      const Vec2 v = m.velocity + m.acceleration * *t;
      const double speed = length(v);
      const double sine = speed > 0 ? std::fabs(cross(edge.u, v)) / speed : 1.0;
      // At the apex of an acute wedge (the neighbour turns back over the colliding side), beyond the
      // joint lies only the outside, within the neighbour's round-off over the sine of the apex of both
      // lines: the face reaches that far, for any point not moving along it (whose slide ends past the
      // joint, resting.cpp). In an apex of half a degree a point slid along one face 119 round-offs past
      // the joint, and out of its container; another, come to rest 5 round-offs past it, was later
      // thrown down out of the tip. (A nearly straight joint has as small a sine, and a point moving
      // along one face passes it: there the reach stays the round-off's.)
      auto apexSine = [&](const Vec2* far, Vec2 joint, Vec2 alongFace) {
        if (!far || !(dot(edge.n, *far - joint) > 0) || !(dot(*far - joint, alongFace) > 0)) return 0.0;
        const Vec2 d = *far - joint;
        const double apex = std::fabs(cross(edge.u, d)) / length(d);
        return sine >= 0.5 * apex ? apex : 0.0;
      };
      const double apexStart = apexSine(edge.beforeStart, edge.a, edge.u);
      const double apexEnd = apexSine(edge.afterEnd, edge.a + edge.u * edge.length, -edge.u);
      if (apexStart > 0) {
        start += edge.jointSlackStart / std::min(sine, apexStart);
      } else if (sine >= 1.0 / 64) {
        start += edge.jointSlackStart / sine;
      }
      if (apexEnd > 0) {
        end += edge.jointSlackEnd / std::min(sine, apexEnd);
      } else if (sine >= 1.0 / 64) {
        end += edge.jointSlackEnd / sine;
      }
    }
    if (tau < 0 && tau >= -start) tau = 0;
    if (tau > edge.length && tau <= edge.length + end) tau = edge.length;
  }
  if (tau < 0 || tau > edge.length) return std::nullopt;
  return Impact{*t, edge.a + edge.u * tau, edge.n, feature};
}

// Which pieces of a wall a circle of radius > 0 cannot reach over [0, maxTime]: its centre moves at most
// |v| T + |a| T^2 / 2, and a piece farther than the radius plus that, by more than round-off, is out of
// reach. A face is met only where the centre lies the radius from the face's line over the segment itself
// (faceImpact takes no slack along the face but a point's), and a corner where it lies the radius from the
// corner, so such a segment's faces and ends have no impact to find; most segments of a wall around a
// scene are that far from most bodies. The margin, 1e-9 of the coordinates at play, is far above the
// rounding of the gap, of tau and of the times of impact; a non-finite travel or coordinate reaches all.
// A corner is out of reach with a segment it ends or begins (an end is no nearer than its segment): the
// segments found out of reach are marked, up to 64; past that each corner is tested on its own.
class OutOfReach {
 public:
  OutOfReach(const Circle& a, const Motion& m, double maxTime, int segments)
      : centre_(a.center),
        radius_(a.radius),
        travel_(length(m.velocity) * maxTime + 0.5 * length(m.acceleration) * maxTime * maxTime),
        scale_(norm1(a.center) + a.radius + travel_),
        marking_(segments <= 64) {}

  // Segment i, from p0 to p1.
  bool segment(int i, Vec2 p0, Vec2 p1) {
    const bool far = beyond(detail::closestOnSegment(p0, p1, centre_, true).point, norm1(p0) + norm1(p1));
    if (far && marking_) marked_ |= uint64_t{1} << i;
    return far;
  }
  // The corner at p that ends segment `before` and begins segment `after` (-1 or the segment count: none).
  bool corner(int before, int after, Vec2 p) const {
    if (!marking_) return beyond(p, 2 * norm1(p));
    return isMarked(before) || isMarked(after);
  }

 private:
  static double norm1(Vec2 p) { return std::fabs(p.x) + std::fabs(p.y); }
  bool beyond(Vec2 nearest, double pieceScale) const {
    const Vec2 off = centre_ - nearest;
    const double out = radius_ + travel_ + 1e-9 * (scale_ + pieceScale);
    return radius_ > 0 && dot(off, off) > out * out;
  }
  bool isMarked(int i) const { return i >= 0 && i < 64 && ((marked_ >> i) & 1) != 0; }

  Vec2 centre_;
  double radius_, travel_, scale_;
  bool marking_;
  uint64_t marked_ = 0;
};

void keepEarlier(std::optional<Impact>& best, const std::optional<Impact>& candidate) {
  if (candidate && (!best || candidate->time < best->time)) best = candidate;
}

// A segment collides on both sides. The overlap rules apply on the side the centre is on; a centre
// exactly on the line has f = s^2 - r^2 with f'(0) = 0 from velocity alone, and is left to the
// crossing test. The other side matters only under acceleration: a body can pass beyond an end and
// curve back onto the underside.
bool isResolved(int feature, int resolvedFeature) {
  return feature == resolvedFeature || resolvedFeature == kEveryFeature;
}

std::optional<Impact> segmentImpact(const Circle& a, const Motion& m, Vec2 p0, Vec2 p1, double maxTime, int feature,
                                    bool justResolved, double frameSlack, double jointSlackStart = 0,
                                    double jointSlackEnd = 0, const Vec2* beforeStart = nullptr,
                                    const Vec2* afterEnd = nullptr) {
  Edge edge = edgeOf(p0, p1);
  edge.frameSlack = frameSlack;
  edge.jointSlackStart = jointSlackStart;
  edge.jointSlackEnd = jointSlackEnd;
  edge.beforeStart = beforeStart;
  edge.afterEnd = afterEnd;
  double s0 = dot(edge.n, a.center - edge.a);
  if (a.radius == 0 && std::fabs(s0) <= edge.pointSlack(a.center)) s0 = 0;
  if (s0 < 0) edge.n = -edge.n;
  // A point on the line (within round-off) has no overlap to tell which side it is on; its history does.
  // Just resolved against this segment, it leaves it: it is on the side it moves to, and the rules find
  // its return (a bounce under gravity). Otherwise it has just arrived: it is on the side it comes from,
  // and collides now. Moving along the line, the side is the one its acceleration presses it into.
  if (s0 == 0 && a.radius == 0) {
    const double vn = dot(edge.n, m.velocity), an = dot(edge.n, m.acceleration);
    // Moving along the line, with a normal velocity and acceleration within the round-off of the
    // motion (a point sliding down a sloped segment: its acceleration is gravity's part along it), it
    // stays on the line and meets neither face. Read as a side, it collided at once, was dismissed and
    // was predicted again at the same instant until the step's budget ran out, and its next segment
    // went unpredicted for the rest of the step.
    // Moving along the line with an acceleration across it (a point placed on a slope under gravity),
    // the side is the one the acceleration presses it into: read from the round-off in its normal
    // velocity, it was as often the far side, and the point fell through the face.
    const bool alongLine = std::fabs(vn) <= detail::kAbsorbRoundOff * length(m.velocity);
    if (alongLine && std::fabs(an) <= detail::kPressRoundOff * length(m.acceleration)) return std::nullopt;
    const double toward = !alongLine ? (justResolved ? vn : -vn) : -an;
    if (toward < 0) edge.n = -edge.n;
    if (toward != 0) return faceImpact(a, m, edge, true, maxTime, feature, justResolved);
  }
  std::optional<Impact> best = faceImpact(a, m, edge, s0 != 0, maxTime, feature, justResolved);
  if (accelerates(m) || s0 == 0) {
    edge.n = -edge.n;
    keepEarlier(best, faceImpact(a, m, edge, false, maxTime, feature, justResolved));
  }
  return best;
}

}  // namespace

std::optional<Impact> timeOfImpactCircleCircle(const Circle& a, const Motion& motion, const Circle& b, double maxTime,
                                               int resolvedFeature) {
  auto t = timeToReach(a.center - b.center, motion, a.radius + b.radius, maxTime, isResolved(0, resolvedFeature));
  if (!t) return std::nullopt;
  return pointImpact(a.center, motion, b.center, b.radius, *t, 0);
}

std::optional<Impact> timeOfImpactCirclePoint(const Circle& a, const Motion& motion, const Point& b, double maxTime,
                                              int resolvedFeature) {
  auto t = timeToReach(a.center - b.position, motion, a.radius, maxTime, isResolved(0, resolvedFeature));
  if (!t) return std::nullopt;
  return pointImpact(a.center, motion, b.position, 0.0, *t, 0);
}

namespace {

// `neighbours` (null: none known) are the Segments met at its ends (detail::timeOfImpactSegmentWith);
// `frameSlack` is Edge::frameSlack.
std::optional<Impact> circleSegmentImpact(const Circle& a, const Motion& motion, const Segment& b, double maxTime,
                                          int resolvedFeature, const detail::SegmentNeighbours* neighbours,
                                          double frameSlack) {
  // Another fixture's face may meet this one at either end (two Segments in a V): for a point, the face
  // reaches past its ends by the round-off of such a neighbour (Edge::jointSlackStart), taken as its own
  // where the neighbour is not known. Missed there, a point bounced at the joint onto the other Segment
  // passed under this one's end. A known neighbour is read as a Polyline's: in a needle of two Segments
  // (an apex of a third of a degree), a point slid along one past the joint, out of its container.
  if (a.radius != 0) return segmentImpact(a, motion, b.a, b.b, maxTime, 0, isResolved(0, resolvedFeature), 0);
  double start = detail::pointRoundOff(b.a, b.b, b.b - b.a), end = start;
  const Vec2* beforeStart = nullptr;
  const Vec2* afterEnd = nullptr;
  if (neighbours != nullptr && neighbours->hasBefore) {
    beforeStart = &neighbours->beforeStart;
    start = detail::pointRoundOff(*beforeStart, b.a, b.a - *beforeStart);
  }
  if (neighbours != nullptr && neighbours->hasAfter) {
    afterEnd = &neighbours->afterEnd;
    end = detail::pointRoundOff(*afterEnd, b.b, b.b - *afterEnd);
  }
  return segmentImpact(a, motion, b.a, b.b, maxTime, 0, isResolved(0, resolvedFeature), frameSlack, start, end,
                       beforeStart, afterEnd);
}

}  // namespace

std::optional<Impact> timeOfImpactCircleSegment(const Circle& a, const Motion& motion, const Segment& b, double maxTime,
                                                int resolvedFeature) {
  return circleSegmentImpact(a, motion, b, maxTime, resolvedFeature, nullptr, 0);
}

namespace {

// `known` (null: none) says which faces are taken as resolved too, or left out
// (detail::timeOfImpactPolylineWith); `frameSlack` is Edge::frameSlack.
std::optional<Impact> circlePolylineImpact(const Circle& a, const Motion& motion, const Polyline& b, double maxTime,
                                           int resolvedFeature, const detail::KnownFaces* known, double frameSlack) {
  const int n = static_cast<int>(b.points.size());
  // A closed Polyline (its last point its first) has a joint there too: to a point it is an inner
  // corner, met through the faces beside it. As two ends, a point that slid into it took a normal from
  // its own motion and was bounced back into the face it came along, out of the closed box.
  const bool closed = n > 3 && b.points.front() == b.points.back();
  OutOfReach reach(a, motion, maxTime, n - 1);
  std::optional<Impact> best;
  for (int i = 0; i + 1 < n; ++i) {
    if (reach.segment(i, b.points[i], b.points[i + 1])) continue;
    // The round-off of the neighbouring segments' lines (Edge::jointSlackStart, jointSlackEnd), for a
    // point.
    double start = 0, end = 0;
    const Vec2* beforeStart = nullptr;
    const Vec2* afterEnd = nullptr;
    if (a.radius == 0) {
      const auto [before, after] = detail::polylineNeighbours(b, i);
      if (before >= 0) {
        const Vec2 p = b.points[before], q = b.points[before + 1];
        start = detail::pointRoundOff(p, q, q - p);
        beforeStart = &b.points[before];
      }
      if (after >= 0) {
        const Vec2 p = b.points[after], q = b.points[after + 1];
        end = detail::pointRoundOff(q, p, q - p);
        afterEnd = &b.points[after + 1];
      }
    }
    bool resolved = isResolved(i, resolvedFeature);
    if (known != nullptr) {
      const detail::KnownFaces::Reading reading = known->readingOf(i);
      if (reading == detail::KnownFaces::Reading::LeftOut) continue;
      if (reading == detail::KnownFaces::Reading::Resolved) resolved = true;
    }
    keepEarlier(best, segmentImpact(a, motion, b.points[i], b.points[i + 1], maxTime, i, resolved, frameSlack, start,
                                    end, beforeStart, afterEnd));
  }
  for (int k = 0; k < n; ++k) {
    // A point meets a joint only along an exact line, and then its normal is no face's: met there
    // before the next face (by round-off), a point sliding into a valley took the joint's normal from
    // its own motion, was taken to leave both faces, and went on through the next one. The two faces
    // reach past the joint by the round-off (Edge::jointSlackStart, jointSlackEnd) and meet it instead.
    if (a.radius == 0 && ((k > 0 && k + 1 < n) || closed)) continue;
    if (reach.corner(k - 1, k, b.points[k])) continue;
    const int feature = n - 1 + k;
    if (auto t = timeToReach(a.center - b.points[k], motion, a.radius, maxTime, isResolved(feature, resolvedFeature)))
      keepEarlier(best, pointImpact(a.center, motion, b.points[k], 0.0, *t, feature));
  }
  return best;
}

}  // namespace

std::optional<Impact> timeOfImpactCirclePolyline(const Circle& a, const Motion& motion, const Polyline& b,
                                                 double maxTime, int resolvedFeature) {
  return circlePolylineImpact(a, motion, b, maxTime, resolvedFeature, nullptr, 0);
}

namespace {
std::optional<Impact> circlePolygonImpact(const Circle& a, const Motion& motion, const Polygon& b, double maxTime,
                                          int resolvedFeature, double frameSlack) {
  const int n = static_cast<int>(b.points.size());
  std::optional<Impact> best;
  // A face's overlap rule (faceImpact's `front`) takes a centre up to a radius behind the face's line as
  // in front of it, for a disk made across the face. A centre outside the polygon, in front of another
  // face, is on that face's side, not this one's: read as in front of both, a disk of radius 5 above a
  // floor polygon 0.5 thick met the bottom face as if from below the instant it bounced off the top
  // one, and the two faces took it back and forth at one instant until the step's budget ran out
  // (fuzz/regressions/world_api/budget-predictive-big-disk-across-a-thin-floor-polygon).
  bool outside = false;
  for (int i = 0; i < n && a.radius > 0 && !outside; ++i) {
    const Vec2 here = b.points[i], next = b.points[(i + 1) % n];
    outside = cross(next - here, a.center - here) < 0;
  }
  OutOfReach reach(a, motion, maxTime, n);
  for (int i = 0; i < n; ++i) {
    const Vec2 here = b.points[i], next = b.points[(i + 1) % n];
    if (reach.segment(i, here, next)) continue;
    Edge edge = edgeOf(here, next);
    edge.frameSlack = frameSlack;
    const bool front = !outside || cross(next - here, a.center - here) <= 0;
    keepEarlier(best, faceImpact(a, motion, edge, front, maxTime, i, isResolved(i, resolvedFeature)));
  }
  // A point meets a corner only on an exact line, and its normal is then no edge's but its own motion's
  // (pointImpact): the edges beside the corner reach past it by round-off and meet the point instead, as
  // a Polyline's inner corner does. A point that slid along a wall polygon's face into its corner on a
  // floor polygon met the corner, stopped there (restitution 0), then met the wall's bottom face from
  // below, on the floor's line, and slid out along the seam between the two polygons
  // (BodiesInCorners.PointsThrownIntoATiltedBoxFarOutStayIn).
  for (int k = 0; k < n && a.radius > 0; ++k) {
    const int feature = n + k;
    if (reach.corner((k + n - 1) % n, k, b.points[k])) continue;  // it ends edge k - 1 and begins edge k
    auto t = timeToReach(a.center - b.points[k], motion, a.radius, maxTime, isResolved(feature, resolvedFeature));
    if (!t) continue;
    // A corner is the contact only where it is the polygon's nearest point to the centre: past the end of
    // the edge before it and short of the start of the one after (the corner's Voronoi region, outside
    // the polygon). A centre inside the polygon reaching a corner's distance is an overlap from within;
    // one in front of an edge, over the edge, is the face's to meet. Met as a corner there, a disk of
    // radius 1e-12 lying 1e-12 from a polygon's corner, over its bottom face, was pushed away from the
    // corner, into a disk pressing it back, at one instant until the step's budget ran out
    // (fuzz/regressions/world_api/budget-predictive-big-disk-across-a-thin-floor-polygon, its second loop).
    const Vec2 c = a.center + travel(motion, *t);
    const Vec2 prev = b.points[(k + n - 1) % n], here = b.points[k], next = b.points[(k + 1) % n];
    if (dot(c - here, here - prev) < 0 || dot(c - here, next - here) > 0) continue;
    keepEarlier(best, pointImpact(a.center, motion, b.points[k], 0.0, *t, feature));
  }
  return best;
}
}  // namespace

std::optional<Impact> timeOfImpactCirclePolygon(const Circle& a, const Motion& motion, const Polygon& b, double maxTime,
                                                int resolvedFeature) {
  return circlePolygonImpact(a, motion, b, maxTime, resolvedFeature, 0);
}

// ---- Dispatch ----------------------------------------------------------------------------------------

namespace {

using PairFunction = std::optional<Impact> (*)(const Geometry& a, Vec2 positionA, const Geometry& b, Vec2 positionB,
                                               const Motion& relativeMotion, double maxTime, int resolvedFeature);

// A circle-like geometry as a circle in world coordinates.
Circle asCircle(const Geometry& g, Vec2 position) {
  if (const auto* c = std::get_if<Circle>(&g)) return Circle{c->center + position, c->radius};
  return Circle{std::get<Point>(g).position + position, 0.0};
}

// Circle (or point) A into B's frame, `solve(circle, frameSlack)` there, the answer back (the dispatch
// table's entries, and those that pass the solve more than the table does). frameSlack, for a point, is the
// round-off its coordinates carry from the world's frame (Edge::frameSlack): in the frame of a body far from
// the origin the shape's coordinates are small, and so is the round-off faceImpact reads from them, but the
// point's carry the world's. A point that came to rest on a box's floor two round-offs of its world
// coordinates below the floor's line (1.4e-14 at 51 units out) slid along it into the corner, passed under
// the end of the wall's face (the wall a polygon standing on the floor's line) and left the box
// (fuzz/regressions/world_api/escape-predictive-point-under-a-polygon-wall-far-out); so too under a Segment's
// end, or a closed Polyline's corner, three round-offs below
// (BodiesInCorners.APointSlidingUlpsBelowAFloorFarOutMeetsTheWall), and points thrown into a tilted box far
// out left it through its corners (BodiesInCorners.PointsThrownIntoATiltedBoxFarOutStayIn). Two round-offs
// are lost in the frame: the point's world coordinates' own, and the shape's placement in the world (its
// body's position). A body at the origin loses neither: its frame is the world's, whose round-off the faces
// read already, and adding it there let a point out of a box of Segments at the origin
// (PointsOnWalls.NoBodyLeavesAContainerWhereAPointLiesOnAWall).
template <class Solve>
std::optional<Impact> inFrameOf(const Geometry& a, Vec2 positionA, Vec2 positionB, Solve solve) {
  Circle circle = asCircle(a, positionA);
  const bool offset = positionB.x != 0 || positionB.y != 0;
  const double frameSlack = circle.radius == 0 && offset ? detail::pointRoundOff(circle.center, positionB) : 0.0;
  circle.center -= positionB;
  auto impact = solve(circle, frameSlack);
  if (impact) impact->point += positionB;
  return impact;
}

// Circle (or point) A against geometry B of type Shape: the circle goes into B's frame, the answer back.
// (A point against a point or a circle meets it only on an exact distance, with no face to reach past.)
template <class Shape, std::optional<Impact> (*Fn)(const Circle&, const Motion&, const Shape&, double, int)>
std::optional<Impact> circleVs(const Geometry& a, Vec2 positionA, const Geometry& b, Vec2 positionB, const Motion& m,
                               double maxTime, int resolvedFeature) {
  return inFrameOf(a, positionA, positionB, [&](const Circle& circle, double) {
    return Fn(circle, m, std::get<Shape>(b), maxTime, resolvedFeature);
  });
}

// The other order: B is the circle. Solve with the roles swapped and the motion reversed, then turn
// the answer back: the normal is negated, and the contact point, found in the frame where A rests,
// moves by A's travel into the frame where B rests.
template <PairFunction Fn>
std::optional<Impact> swapped(const Geometry& a, Vec2 positionA, const Geometry& b, Vec2 positionB, const Motion& m,
                              double maxTime, int resolvedFeature) {
  auto impact = Fn(b, positionB, a, positionA, Motion{-m.velocity, -m.acceleration}, maxTime, resolvedFeature);
  if (impact) {
    impact->normal = -impact->normal;
    impact->point += travel(m, impact->time);
  }
  return impact;
}

std::optional<Impact> noImpact(const Geometry&, Vec2, const Geometry&, Vec2, const Motion&, double, int) {
  return std::nullopt;
}

constexpr PairFunction kCircleCircle = circleVs<Circle, timeOfImpactCircleCircle>;
constexpr PairFunction kCirclePoint = circleVs<Point, timeOfImpactCirclePoint>;
// A Segment, Polyline or Polygon in its body's frame, with the frame's round-off for a point (inFrameOf).
std::optional<Impact> circleSegmentInWorld(const Geometry& a, Vec2 positionA, const Geometry& b, Vec2 positionB,
                                           const Motion& m, double maxTime, int resolvedFeature) {
  return inFrameOf(a, positionA, positionB, [&](const Circle& circle, double frameSlack) {
    return circleSegmentImpact(circle, m, std::get<Segment>(b), maxTime, resolvedFeature, nullptr, frameSlack);
  });
}

std::optional<Impact> circlePolylineInWorld(const Geometry& a, Vec2 positionA, const Geometry& b, Vec2 positionB,
                                            const Motion& m, double maxTime, int resolvedFeature) {
  return inFrameOf(a, positionA, positionB, [&](const Circle& circle, double frameSlack) {
    return circlePolylineImpact(circle, m, std::get<Polyline>(b), maxTime, resolvedFeature, nullptr, frameSlack);
  });
}

std::optional<Impact> circlePolygonInWorld(const Geometry& a, Vec2 positionA, const Geometry& b, Vec2 positionB,
                                           const Motion& m, double maxTime, int resolvedFeature) {
  return inFrameOf(a, positionA, positionB, [&](const Circle& circle, double frameSlack) {
    return circlePolygonImpact(circle, m, std::get<Polygon>(b), maxTime, resolvedFeature, frameSlack);
  });
}

constexpr PairFunction kCircleSegment = circleSegmentInWorld;
constexpr PairFunction kCirclePolyline = circlePolylineInWorld;
constexpr PairFunction kCirclePolygon = circlePolygonInWorld;

// A point on the moving side is a circle of radius 0, so "point vs X" reuses the circle functions
// (asCircle handles both); a point on the resting side uses circle-point.
constexpr PairFunction kTable[kGeometryTypeCount][kGeometryTypeCount] = {
    //             Point                     Circle                     Segment          Polyline          Polygon
    /* Point    */ {kCirclePoint, kCircleCircle, kCircleSegment, kCirclePolyline, kCirclePolygon},
    /* Circle   */ {kCirclePoint, kCircleCircle, kCircleSegment, kCirclePolyline, kCirclePolygon},
    /* Segment  */ {swapped<kCircleSegment>, swapped<kCircleSegment>, noImpact, noImpact, noImpact},
    /* Polyline */ {swapped<kCirclePolyline>, swapped<kCirclePolyline>, noImpact, noImpact, noImpact},
    /* Polygon  */ {swapped<kCirclePolygon>, swapped<kCirclePolygon>, noImpact, noImpact, noImpact},
};

}  // namespace

std::optional<Impact> timeOfImpact(const Geometry& a, Vec2 positionA, const Geometry& b, Vec2 positionB,
                                   const Motion& relativeMotion, double maxTime, int resolvedFeature) {
  return kTable[a.index()][b.index()](a, positionA, b, positionB, relativeMotion, maxTime, resolvedFeature);
}

std::optional<Impact> detail::timeOfImpactPolylineWith(const Geometry& a, Vec2 positionA, const Polyline& b,
                                                       Vec2 positionB, const Motion& relativeMotion, double maxTime,
                                                       int resolvedFeature, const KnownFaces& known) {
  return inFrameOf(a, positionA, positionB, [&](const Circle& circle, double frameSlack) {
    return circlePolylineImpact(circle, relativeMotion, b, maxTime, resolvedFeature, &known, frameSlack);
  });
}

std::optional<Impact> detail::timeOfImpactSegmentWith(const Geometry& a, Vec2 positionA, const Segment& b,
                                                      Vec2 positionB, const Motion& relativeMotion, double maxTime,
                                                      int resolvedFeature, const SegmentNeighbours& neighbours) {
  return inFrameOf(a, positionA, positionB, [&](const Circle& circle, double frameSlack) {
    return circleSegmentImpact(circle, relativeMotion, b, maxTime, resolvedFeature, &neighbours, frameSlack);
  });
}

}  // namespace rattle
