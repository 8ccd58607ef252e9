// World queries: ray casts and overlap tests against the fixtures as they stand between steps.
//
// Brute force over the fixture slots, in index order, with a box pre-check before the exact test of
// overlap.cpp. Walking the slots in index order gives overlap results already sorted by fixture index; ray
// hits are sorted by (fraction, fixture index). Both keys are total, so results never depend on anything
// but the world's contents. The broad phase is not used: its boxes of moving bodies are swept boxes of the
// last step, not the boxes of where the bodies are now, and a query must see exactly the present.
//
// Every query validates its arguments first and throws rattle::Error naming the argument and its value.
#include <algorithm>
#include <cmath>
#include <string>

#include "common/format.h"
#include "world/world_impl.h"

namespace rattle {

using detail::FixtureSlot;
using detail::require;
using detail::str;

namespace {

void checkFinite(Vec2 v, const char* query, const char* argument) {
  require(isFinite(v), [&] { return std::string(query) + ": " + argument + " = " + str(v) + ": must be finite"; });
}

void checkRay(Vec2 origin, Vec2 translation, const char* query) {
  checkFinite(origin, query, "origin");
  checkFinite(translation, query, "translation");
  // Both finite but the end point overflows: the ray would run through infinity, where no test is
  // meaningful.
  require(isFinite(origin + translation), [&] {
    return std::string(query) + ": translation = " + str(translation) +
           ": origin + translation overflows from origin = " + str(origin);
  });
}

// A fixture is seen when its category is in the query's mask and the query's category is in its mask
// (the world's collision rule without groups); sensors only when asked for.
bool seen(const FixtureSlot& f, const QueryFilter& q) {
  if (!f.alive) return false;
  if (f.sensor && !q.includeSensors) return false;
  return (f.filter.categoryBits & q.maskBits) != 0 && (q.categoryBits & f.filter.maskBits) != 0;
}

Box boxAround(Vec2 a, Vec2 b) {
  return {{std::min(a.x, b.x), std::min(a.y, b.y)}, {std::max(a.x, b.x), std::max(a.y, b.y)}};
}

// The helpers below take the world's storage as a template parameter: detail::WorldState is private to World,
// so these free functions may use it only without naming it.

// Calls found(index, hit) for every seen fixture the ray hits, in fixture index order.
template <class Impl, class Found>
void forEachRayHit(const Impl& w, Vec2 origin, Vec2 translation, const QueryFilter& filter, Found&& found) {
  for (uint32_t i = 0; i < w.fixtures.size(); ++i) {
    const FixtureSlot& f = w.fixtures[i];
    if (!seen(f, filter)) continue;
    const Vec2 position = w.bodies[f.body].position;
    // The pre-check in the fixture's frame, where rayCast() works too: the ray's box (its origin there is
    // origin - position, exactly as rayCast computes it) against the geometry's local box.
    const Vec2 o = origin - position;
    if (!boxAround(o, o + translation).overlaps(f.localBox)) continue;
    if (auto hit = rayCast(f.geometry, position, origin, translation)) found(i, *hit);
  }
}

template <class Impl>
RayHit rayHitOf(const Impl& w, uint32_t fixture, const RayCastHit& hit) {
  const FixtureSlot& f = w.fixtures[fixture];
  RayHit out;
  out.fixture = FixtureId{fixture, f.generation};
  out.body = BodyId{f.body, w.bodies[f.body].generation};
  out.point = hit.point;
  out.normal = hit.normal;
  out.fraction = hit.fraction;
  return out;
}

// Calls test(geometry, position) for every seen fixture whose world box meets `box`, and collects those
// for which it returns true, in index order.
template <class Impl, class Test>
std::vector<FixtureId> collectOverlaps(const Impl& w, const Box& box, const QueryFilter& filter, Test&& test) {
  std::vector<FixtureId> out;
  for (uint32_t i = 0; i < w.fixtures.size(); ++i) {
    const FixtureSlot& f = w.fixtures[i];
    if (!seen(f, filter)) continue;
    if (!w.worldBox(i).overlaps(box)) continue;
    if (test(f.geometry, w.bodies[f.body].position)) out.push_back(FixtureId{i, f.generation});
  }
  return out;
}

}  // namespace

std::optional<RayHit> World::rayCastFirst(Vec2 origin, Vec2 translation, const QueryFilter& filter) const {
  checkRay(origin, translation, "rayCastFirst");
  std::optional<RayHit> best;
  // Fixtures come in index order, so keeping only strictly nearer hits leaves the lowest index on a tie.
  forEachRayHit(impl(), origin, translation, filter, [&](uint32_t i, const RayCastHit& hit) {
    if (!best || hit.fraction < best->fraction) best = rayHitOf(impl(), i, hit);
  });
  return best;
}

std::vector<RayHit> World::rayCastAll(Vec2 origin, Vec2 translation, const QueryFilter& filter) const {
  checkRay(origin, translation, "rayCastAll");
  std::vector<RayHit> hits;
  forEachRayHit(impl(), origin, translation, filter,
                [&](uint32_t i, const RayCastHit& hit) { hits.push_back(rayHitOf(impl(), i, hit)); });
  std::sort(hits.begin(), hits.end(), [](const RayHit& x, const RayHit& y) {
    if (x.fraction != y.fraction) return x.fraction < y.fraction;
    return x.fixture.index < y.fixture.index;
  });
  return hits;
}

std::vector<FixtureId> World::overlapBox(const Box& box, const QueryFilter& filter) const {
  checkFinite(box.min, "overlapBox", "box.min");
  checkFinite(box.max, "overlapBox", "box.max");
  require(box.min.x <= box.max.x && box.min.y <= box.max.y, [&] {
    return "overlapBox: box.min = " + str(box.min) + ", box.max = " + str(box.max) +
           ": min must be <= max in x and in y";
  });
  return collectOverlaps(impl(), box, filter,
                         [&](const Geometry& g, Vec2 position) { return overlapsBox(g, position, box); });
}

std::vector<FixtureId> World::overlapCircle(Vec2 center, double radius, const QueryFilter& filter) const {
  checkFinite(center, "overlapCircle", "center");
  require(std::isfinite(radius) && radius >= 0,
          [&] { return "overlapCircle: radius = " + str(radius) + ": must be finite and >= 0"; });
  const Geometry circle = Circle{center, radius};
  const Vec2 r{radius, radius};
  return collectOverlaps(impl(), Box{center - r, center + r}, filter,
                         [&](const Geometry& g, Vec2 position) { return overlaps(circle, Vec2{}, g, position); });
}

std::vector<FixtureId> World::overlapPoint(Vec2 point, const QueryFilter& filter) const {
  checkFinite(point, "overlapPoint", "point");
  const Geometry p = Point{point};
  return collectOverlaps(impl(), Box{point, point}, filter,
                         [&](const Geometry& g, Vec2 position) { return overlaps(p, Vec2{}, g, position); });
}

}  // namespace rattle
