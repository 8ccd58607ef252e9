// Private: a circle's time of impact with a Polyline, one face read as the caller knows it
// (time_of_impact.cpp).
#pragma once

#include <optional>

#include "rattle/time_of_impact.h"

namespace rattle::detail {

/// What a caller knows of one face of a Polyline (contact/response.cpp: a point's side of it).
enum class KnownFace {
  Resolved,  ///< taken as resolved at this instant too: a contact with it now is read as leaving it
  LeftOut,   ///< left out entirely
};

/// timeOfImpact of circle or point `a` at `positionA` with Polyline `b` at `positionB`, as the dispatch
/// table answers it, with face `face` of `b` read as `known` says.
std::optional<Impact> timeOfImpactPolylineWith(const Geometry& a, Vec2 positionA, const Polyline& b, Vec2 positionB,
                                               const Motion& relativeMotion, double maxTime, int resolvedFeature,
                                               int face, KnownFace known);

}  // namespace rattle::detail
