// The rules of the world's state that the World API and every mode share: which fixtures may collide
// or sense each other (their bodies and filters), and a body's mass and disk shape from its fixtures.
#include <algorithm>
#include <limits>

#include "common/same_bits.h"
#include "world/world_impl.h"

namespace rattle {

using detail::BodySlot;
using detail::FixtureSlot;

bool detail::canCollide(const WorldState& w, uint32_t fa, uint32_t fb) {
  const FixtureSlot& a = w.fixtures[fa];
  const FixtureSlot& b = w.fixtures[fb];
  if (a.body == b.body || a.sensor || b.sensor) return false;
  if (w.bodies[a.body].type != BodyType::Dynamic && w.bodies[b.body].type != BodyType::Dynamic) return false;
  if (a.filter.group != 0 && a.filter.group == b.filter.group) return false;
  return (a.filter.categoryBits & b.filter.maskBits) != 0 && (b.filter.categoryBits & a.filter.maskBits) != 0;
}

bool detail::canSense(const WorldState& w, uint32_t fa, uint32_t fb) {
  const FixtureSlot& a = w.fixtures[fa];
  const FixtureSlot& b = w.fixtures[fb];
  if (a.body == b.body || a.sensor == b.sensor) return false;
  if (w.bodies[a.body].type == BodyType::Static && w.bodies[b.body].type == BodyType::Static) return false;
  if (a.filter.group != 0 && a.filter.group == b.filter.group) return false;
  return (a.filter.categoryBits & b.filter.maskBits) != 0 && (b.filter.categoryBits & a.filter.maskBits) != 0;
}

double detail::physicalMass(const WorldState& w, const BodySlot& body) {
  double mass = 0;
  for (uint32_t f : body.fixtures) {
    if (!w.fixtures[f].sensor) mass += w.fixtures[f].density * areaOf(w.fixtures[f].geometry);
  }
  return mass;
}

void detail::recomputeMass(WorldState& w, BodySlot& body) {
  if (body.type != BodyType::Dynamic) {
    body.mass = std::numeric_limits<double>::infinity();
    body.inverseMass = 0;
    return;
  }
  double mass = physicalMass(w, body);
  // Like Box2D: a dynamic body with nothing that has area (points only) still needs a finite mass.
  if (!(mass > 0)) mass = 1;
  // Creation and setDensity keep it at most World::kMaxMass. Below World::kMinMass its inverse times a
  // distance or a speed can overflow (fuzz/regressions/world_api/finite-discrete-density-min).
  mass = std::clamp(mass, World::kMinMass, World::kMaxMass);
  body.mass = mass;
  body.inverseMass = 1 / mass;
}

void detail::refreshDiskShape(WorldState& w, uint32_t bodyIndex) {
  BodySlot& b = w.bodies[bodyIndex];
  b.diskShape = false;
  uint32_t physical = 0, f = 0;
  for (uint32_t g : b.fixtures) {
    if (w.fixtures[g].sensor) continue;  // the step's collisions never see it
    ++physical;
    f = g;
  }
  if (physical != 1) return;
  const FixtureSlot& fixture = w.fixtures[f];
  const Circle* circle = std::get_if<Circle>(&fixture.geometry);
  if (circle == nullptr) return;
  const Vec2 zero{0.0, 0.0};
  const Box box{Vec2{-circle->radius, -circle->radius}, Vec2{circle->radius, circle->radius}};
  // Exactly, bit for bit (a radius of 0 gives a box from +0 where -radius is -0): the hybrid step's first
  // pass then adds the same box to the path as it would read from the fixture.
  if (!detail::sameBits(circle->center, zero) || !detail::sameBits(fixture.localBox.min, box.min) ||
      !detail::sameBits(fixture.localBox.max, box.max)) {
    return;
  }
  w.diskShapes[bodyIndex] = {circle->radius, f, fixture.filter.group};
  b.diskShape = true;
}

}  // namespace rattle
