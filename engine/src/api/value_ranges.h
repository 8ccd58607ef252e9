// Private: the ranges the World API holds values to, shared by its calls (world.cpp) and by World::load
// (world_save.cpp), which takes the same values from bytes.
#pragma once

#include <cmath>

#include "rattle/world.h"

namespace rattle::detail {

/// Within the documented range of coordinates (World::kMaxCoordinate): differences and products of
/// coordinates, which the broad phase and the times of impact form, then stay finite.
inline bool inRange(Vec2 v) {
  return std::fabs(v.x) <= World::kMaxCoordinate && std::fabs(v.y) <= World::kMaxCoordinate;
}
inline bool inRange(const Box& b) { return inRange(b.min) && inRange(b.max); }

/// A velocity (or an acceleration) whose square is finite too, which every time of impact works with: a
/// speed below 2^512, about 1.34e154. What a save may hold: the API takes speeds below World::kMaxSpeed
/// only, but a bounce off a fast kinematic body can end a little faster.
inline bool finiteSquare(Vec2 v) { return isFinite(v) && std::isfinite(dot(v, v)); }

}  // namespace rattle::detail
