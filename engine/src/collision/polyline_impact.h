// Private: a circle's time of impact with a Polyline, one face left out (time_of_impact.cpp).
#pragma once

#include <optional>

#include "rattle/time_of_impact.h"

namespace rattle::detail {

/// timeOfImpact of circle or point `a` at `positionA` with Polyline `b` at `positionB`, as the dispatch
/// table answers it, with face `skippedFace` of `b` left out entirely: a caller that knows the answer for
/// that face (a point's side of it, contact/response.cpp) asks about the others.
std::optional<Impact> timeOfImpactPolylineSkipping(const Geometry& a, Vec2 positionA, const Polyline& b, Vec2 positionB,
                                                   const Motion& relativeMotion, double maxTime, int resolvedFeature,
                                                   int skippedFace);

}  // namespace rattle::detail
