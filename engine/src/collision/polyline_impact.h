// Private: a circle's time of impact with faces the caller knows more of than the geometry says
// (time_of_impact.cpp): a Polyline's faces read as the caller knows them, and a Segment's neighbours.
#pragma once

#include <optional>

#include "rattle/time_of_impact.h"

namespace rattle::detail {

/// Faces of a Polyline that a caller knows more of than the time of impact can read
/// (contact/response.cpp: a point's side of them), each read another way.
struct KnownFaces {
  enum class Reading {
    AsItIs,    ///< not known: read as timeOfImpact reads it
    Resolved,  ///< taken as resolved at this instant too: a contact with it now is read as leaving it
    LeftOut,   ///< left out entirely
  };
  static constexpr int kMost = 4;
  int face[kMost] = {};
  Reading reading[kMost] = {};
  int count = 0;

  Reading readingOf(int f) const {
    for (int k = 0; k < count; ++k) {
      if (face[k] == f) return reading[k];
    }
    return Reading::AsItIs;
  }
  /// Face f read as `r` from now on; false when there is no room for one more face.
  bool read(int f, Reading r) {
    for (int k = 0; k < count; ++k) {
      if (face[k] == f) {
        reading[k] = r;
        return true;
      }
    }
    if (count == kMost) return false;
    face[count] = f;
    reading[count++] = r;
    return true;
  }
};

/// The faces beside face `face` of a Polyline: the one before its start and the one after its end, -1
/// where there is none. A closed Polyline (its last point its first) joins its last face to its first.
struct PolylineNeighbours {
  int before, after;
};
inline PolylineNeighbours polylineNeighbours(const Polyline& p, int face) {
  const int n = static_cast<int>(p.points.size());
  const bool closed = n > 3 && p.points.front() == p.points.back();
  return {face > 0 ? face - 1 : (closed ? n - 2 : -1), face + 2 < n ? face + 1 : (closed ? 0 : -1)};
}

/// timeOfImpact of circle or point `a` at `positionA` with Polyline `b` at `positionB`, as the dispatch
/// table answers it, with the faces in `known` read as it says.
std::optional<Impact> timeOfImpactPolylineWith(const Geometry& a, Vec2 positionA, const Polyline& b, Vec2 positionB,
                                               const Motion& relativeMotion, double maxTime, int resolvedFeature,
                                               const KnownFaces& known);

/// The far ends of the Segments that share a Segment's start and its end, where exactly one other
/// Segment of the same body does (world/segment_neighbours.cpp keeps them): to a point, the two meet at
/// a joint as a Polyline's faces do, and an acute one is the apex of a wedge the point may be in.
struct SegmentNeighbours {
  Vec2 beforeStart, afterEnd;
  bool hasBefore = false, hasAfter = false;
  bool any() const { return hasBefore || hasAfter; }
};

/// timeOfImpact of circle or point `a` at `positionA` with Segment `b` at `positionB`, as the dispatch
/// table answers it, but with the joints to `neighbours` (in b's coordinates) read as a Polyline's.
std::optional<Impact> timeOfImpactSegmentWith(const Geometry& a, Vec2 positionA, const Segment& b, Vec2 positionB,
                                              const Motion& relativeMotion, double maxTime, int resolvedFeature,
                                              const SegmentNeighbours& neighbours);

}  // namespace rattle::detail
