// Memory exhaustion at the World API: every operator new of this binary can be made to fail after a
// count, and each call is tried with the failure at each of its allocations in turn. A binary of its own,
// so that the failing allocator never sits under the other tests.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>
#include <string>

#include "rattle/rattle.h"

namespace {

// Allocations left before one fails; below 0, none fails.
std::atomic<long> gAllocationsLeft{-1};

void* allocate(std::size_t size, std::size_t alignment) {
  if (gAllocationsLeft.load(std::memory_order_relaxed) >= 0 && gAllocationsLeft.fetch_sub(1) == 0) {
    gAllocationsLeft.store(-1);
    throw std::bad_alloc();
  }
  if (size == 0) size = 1;
  void* p = alignment <= alignof(std::max_align_t)
                ? std::malloc(size)
                : std::aligned_alloc(alignment, (size + alignment - 1) / alignment * alignment);
  if (!p) throw std::bad_alloc();
  return p;
}

}  // namespace

void* operator new(std::size_t size) { return allocate(size, alignof(std::max_align_t)); }
void* operator new[](std::size_t size) { return allocate(size, alignof(std::max_align_t)); }
void* operator new(std::size_t size, std::align_val_t a) { return allocate(size, static_cast<std::size_t>(a)); }
void* operator new[](std::size_t size, std::align_val_t a) { return allocate(size, static_cast<std::size_t>(a)); }
void* operator new(std::size_t size, const std::nothrow_t&) noexcept {
  try {
    return allocate(size, alignof(std::max_align_t));
  } catch (...) {
    return nullptr;
  }
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }

namespace {

using namespace rattle;

// A closed box with a few disks and a sensor, in the given mode.
World makeWorld(StepMode mode) {
  World w({.mode = mode});
  const BodyId box = w.createBody({.type = BodyType::Static});
  w.createFixture(box, {.geometry = Polyline{{{0, 0}, {10, 0}, {10, 10}, {0, 10}, {0, 0}}}});
  for (int i = 0; i < 8; ++i) {
    const BodyId d = w.createBody({.type = BodyType::Dynamic, .position = {1.0 + i, 5}, .velocity = {1.0 - i * 0.3, 0.5}});
    w.createFixture(d, {.geometry = Circle{{0, 0}, 0.4}, .restitution = 0.5});
  }
  const BodyId eye = w.createBody({.type = BodyType::Static, .position = {5, 5}});
  w.createFixture(eye, {.geometry = Circle{{0, 0}, 2}, .sensor = true});
  w.step(1.0 / 60);
  return w;
}

// What a caller sees of a world: its hash (every body's motion, the time), its counts and its fixtures.
struct Seen {
  uint64_t hash;
  int bodies;
  std::string fixtures;
  bool operator==(const Seen&) const = default;
};

Seen seen(const World& w) {
  std::string fixtures;
  for (const FixtureId f : w.overlapBox({{-100, -100}, {100, 100}})) fixtures += std::to_string(f.index) + " ";
  return {w.stateHash(), w.bodyCount(), fixtures};
}

// Runs one API call, `call`, on a world made by makeWorld and `prepare`, with its k-th allocation failing,
// for k = 0, 1, ... until it runs through without one: each failure must be a rattle::Error that leaves
// the world as it was, and the world must still work (the call again, which must now succeed, then a
// step). Returns the number of allocations the call made.
template <class Prepare, class Call>
int failEachAllocation(StepMode mode, Prepare&& prepare, Call&& call) {
  for (long k = 0; k <= 10000; ++k) {
    World w = makeWorld(mode);
    prepare(w);
    const Seen before = seen(w);
    gAllocationsLeft.store(k);
    bool failed = false;
    try {
      call(w);
    } catch (const Error& e) {
      failed = true;
      gAllocationsLeft.store(-1);
      EXPECT_NE(std::string(e.what()).find("out of memory"), std::string::npos) << e.what();
      EXPECT_TRUE(seen(w) == before) << "allocation " << k << ": the world changed";
    } catch (const std::bad_alloc&) {
      gAllocationsLeft.store(-1);
      ADD_FAILURE() << "allocation " << k << ": std::bad_alloc, not rattle::Error";
      failed = true;
    }
    const bool noneLeftToFail = gAllocationsLeft.load() >= 0;
    gAllocationsLeft.store(-1);
    call(w);
    w.step(1.0 / 60);
    if (!failed && noneLeftToFail) return static_cast<int>(k);
  }
  ADD_FAILURE() << "more than 10000 allocations";
  return -1;
}

}  // namespace

// A body, then a circle on it, with the world's arrays at each size from 10 to 50 bodies (so that some
// calls grow them), and a polyline and a polygon sensor on a static body.
TEST(OutOfMemory, CreatingBodiesAndFixturesFailsCleanlyAtEveryAllocation) {
  for (StepMode mode : {StepMode::Hybrid, StepMode::Discrete, StepMode::Predictive}) {
    int allocations = 0;
    for (int extra = 0; extra < 40; ++extra) {
      auto prepare = [extra](World& w) {
        for (int i = 0; i < extra; ++i) {
          const BodyId b = w.createBody({.type = BodyType::Dynamic, .position = {0.5 + 0.2 * i, 1}});
          w.createFixture(b, {.geometry = Circle{{0, 0}, 0.05}});
        }
      };
      allocations += failEachAllocation(mode, prepare, [](World& w) {
        w.createBody({.type = BodyType::Dynamic, .position = {9, 9}});
      });
      BodyId last;
      allocations += failEachAllocation(
          mode,
          [&](World& w) {
            prepare(w);
            last = w.createBody({.type = BodyType::Dynamic, .position = {9, 9}});
          },
          [&](World& w) { w.createFixture(last, {.geometry = Circle{{0, 0}, 0.05}}); });
    }
    // Built before the allocations fail: the definition's own vector is the caller's.
    const FixtureDef polyline{.geometry = Polyline{{{2, 2}, {3, 2}, {3, 3}, {4, 3}, {4, 4}, {5, 4}}}};
    const FixtureDef polygon{.geometry = Polygon{{{6, 6}, {7, 6}, {7, 7}}}, .sensor = true};
    BodyId wall;
    auto prepareWall = [&](World& w) { wall = w.createBody({.type = BodyType::Static}); };
    allocations += failEachAllocation(mode, prepareWall, [&](World& w) {
      w.createFixture(wall, polyline);
    });
    allocations += failEachAllocation(mode, prepareWall, [&](World& w) {
      w.createFixture(wall, polygon);
    });
    EXPECT_GT(allocations, 0);  // some call had an allocation to fail
  }
}

