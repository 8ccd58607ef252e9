// The rules of the world's state that the World API and every mode share: which fixtures may collide
// or sense each other (their bodies and filters), and a body's mass from its fixtures.
#include <algorithm>
#include <limits>

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
  // Creation and setDensity keep it at most World::kMaxMass; below the smallest normal double its
  // inverse would overflow.
  mass = std::clamp(mass, std::numeric_limits<double>::min(), World::kMaxMass);
  body.mass = mass;
  body.inverseMass = 1 / mass;
}

}  // namespace rattle
