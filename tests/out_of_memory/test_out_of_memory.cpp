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

// What a call leaves to its caller besides the bodies' motion: who sleeps, the sensors' overlaps and the
// events.
struct AfterStep {
  uint64_t hash;
  std::string asleep;
  std::string overlaps;
  size_t contacts, sensorEvents;
  bool operator==(const AfterStep&) const = default;
};

AfterStep afterStep(const World& w, const std::vector<FixtureId>& sensors) {
  std::string asleep, overlaps;
  for (uint32_t i = 0; i < 200; ++i) {
    for (uint32_t g = 1; g <= 2; ++g) {
      if (w.isValid(BodyId{i, g})) asleep += w.isAsleep(BodyId{i, g}) ? 'z' : '.';
    }
  }
  for (const FixtureId s : sensors) {
    if (!w.isValid(s)) continue;
    for (const FixtureId f : w.sensorOverlaps(s)) overlaps += std::to_string(f.index) + " ";
    overlaps += "| ";
  }
  return {w.stateHash(), asleep, overlaps, w.contactEvents().size(), w.sensorEvents().size()};
}

// A scene for the steps below: the world, made by `build`, and its sensors.
struct Scene {
  World world;
  std::vector<FixtureId> sensors;
};

// Runs `call` (a step, with what a game does before it, or another call) on the scene `build` makes, with
// its k-th allocation failing, for k = 0, 1, ... until it runs through without one. Each failure must be
// a rattle::Error that leaves the bodies, the time, who sleeps and the sensors' overlaps as they were
// (and a failed step reports no events); the call again must then give exactly what it gives on a world
// where nothing failed (`exact`: a predictive step after a failed one makes its grid and queue afresh,
// and predictions made afresh may differ in the last bits from those the queue carried), and the world
// must step on. Returns the number of allocations the call made.
template <class Build, class Call>
int failEachAllocationOf(Build&& build, Call&& call, bool exact = true, bool isStep = true) {
  Scene reference = build();
  call(reference.world);
  const AfterStep expected = afterStep(reference.world, reference.sensors);
  for (long k = 0; k <= 20000; ++k) {
    Scene scene = build();
    World& w = scene.world;
    const Seen before = seen(w);
    const AfterStep beforeStep = afterStep(w, scene.sensors);
    gAllocationsLeft.store(k);
    bool failed = false;
    try {
      call(w);
    } catch (const Error& e) {
      failed = true;
      gAllocationsLeft.store(-1);
      EXPECT_NE(std::string(e.what()).find("out of memory"), std::string::npos) << e.what();
      EXPECT_TRUE(seen(w) == before) << "allocation " << k << ": the world changed";
      const AfterStep after = afterStep(w, scene.sensors);
      EXPECT_EQ(after.asleep, beforeStep.asleep) << "allocation " << k;
      EXPECT_EQ(after.overlaps, beforeStep.overlaps) << "allocation " << k;
      if (isStep) {
        EXPECT_EQ(w.contactEvents().size(), 0u);
      } else {
        EXPECT_EQ(after.contacts, beforeStep.contacts);
        EXPECT_EQ(after.sensorEvents, beforeStep.sensorEvents);
      }
    } catch (const std::bad_alloc&) {
      gAllocationsLeft.store(-1);
      ADD_FAILURE() << "allocation " << k << ": std::bad_alloc, not rattle::Error";
      return -1;
    }
    const bool noneLeftToFail = gAllocationsLeft.load() >= 0;
    gAllocationsLeft.store(-1);
    if (failed) {
      call(w);
      if (exact) {
        EXPECT_TRUE(afterStep(w, scene.sensors) == expected) << "allocation " << k << ": the call again differs";
      }
      for (int i = 0; i < 30; ++i) w.step(1.0 / 60);
      EXPECT_GT(w.bodyCount(), 0);
    }
    if (!failed && noneLeftToFail) return static_cast<int>(k);
  }
  ADD_FAILURE() << "more than 20000 allocations";
  return -1;
}

// A closed box, disks and a sensor.
Scene boxWithSensor(StepMode mode, Vec2 gravity, int disks) {
  Scene s{World({.mode = mode, .gravity = gravity}), {}};
  World& w = s.world;
  const BodyId box = w.createBody({.type = BodyType::Static});
  w.createFixture(box, {.geometry = Polyline{{{0, 0}, {10, 0}, {10, 10}, {0, 10}, {0, 0}}}});
  for (int i = 0; i < disks; ++i) {
    const BodyId d = w.createBody({.type = BodyType::Dynamic,
                                   .position = {1.0 + (i % 8) + 0.1 * (i / 8), 1.0 + 1.1 * (i / 8)},
                                   .velocity = {1.0 - (i % 8) * 0.3, 0.5 - (i % 3)}});
    w.createFixture(d, {.geometry = Circle{{0, 0}, 0.45}, .restitution = 0.5});
  }
  const BodyId eye = w.createBody({.type = BodyType::Static, .position = {5, 3}});
  s.sensors.push_back(w.createFixture(eye, {.geometry = Circle{{0, 0}, 2}, .sensor = true}));
  return s;
}


// Runs one API call, `call`, on a world made by makeWorld and `prepare`, with each of its allocations
// failing in turn (failEachAllocationOf, above). Returns the number of allocations the call made.
template <class Prepare, class Call>
int failEachAllocation(StepMode mode, Prepare&& prepare, Call&& call) {
  return failEachAllocationOf(
      [&] {
        Scene s{makeWorld(mode), {}};
        prepare(s.world);
        return s;
      },
      call, true, false);
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



// A step with each of its allocations failing in turn, in each mode: the first step of a world (every
// container grows), a later one with sensors busy, a pile under gravity hit by a fast disk (islands,
// sleeping bodies woken), and a crowd the game drives into a wall (a jam's solve).
TEST(OutOfMemory, AStepFailsCleanlyAtEveryAllocation) {
  for (StepMode mode : {StepMode::Hybrid, StepMode::Discrete, StepMode::Predictive}) {
    SCOPED_TRACE(static_cast<int>(mode));
    const bool exact = mode != StepMode::Predictive;
    const auto step = [](World& w) { w.step(1.0 / 60); };
    int allocations = failEachAllocationOf([&] { return boxWithSensor(mode, {}, 16); }, step, exact);
    // A first step in which many pairs collide, each collision's event pushed after bodies have moved.
    allocations += failEachAllocationOf(
        [&] {
          Scene s = boxWithSensor(mode, {}, 40);
          for (int i = 1; i <= 40; ++i) {
            s.world.setVelocity({static_cast<uint32_t>(i), 1}, {20.0 * ((i * 7) % 5 - 2), 15.0 * ((i * 3) % 5 - 2)});
          }
          return s;
        },
        step, exact);
    allocations += failEachAllocationOf(
        [&] {
          Scene s = boxWithSensor(mode, {}, 16);
          for (int i = 0; i < 20; ++i) s.world.step(1.0 / 60);
          return s;
        },
        step, exact);
    allocations += failEachAllocationOf(
        [&] {
          Scene s = boxWithSensor(mode, {0, -9.81}, 40);
          for (int i = 0; i < 240; ++i) s.world.step(1.0 / 60);
          const BodyId shot =
              s.world.createBody({.type = BodyType::Dynamic, .position = {5, 4.5}, .velocity = {3, -60}});
          s.world.createFixture(shot, {.geometry = Circle{{0, 0}, 0.3}});
          return s;
        },
        step, exact);
    // A pile still landing: bodies held by stepped islands, sliding and going to sleep within the step.
    for (int steps : {45}) {
      allocations += failEachAllocationOf(
          [&] {
            Scene s = boxWithSensor(mode, {0, -9.81}, 40);
            for (int i = 0; i < steps; ++i) s.world.step(1.0 / 60);
            return s;
          },
          step, exact);
    }
    const auto drive = [](World& w) {
      for (uint32_t i = 1; i <= 40; ++i) w.setVelocity({i, 1}, {-4, 0.3});
    };
    allocations += failEachAllocationOf(
        [&] {
          Scene s = boxWithSensor(mode, {}, 40);
          for (int i = 0; i < 30; ++i) {
            drive(s.world);
            s.world.step(1.0 / 30);
          }
          drive(s.world);
          return s;
        },
        [](World& w) { w.step(1.0 / 30); }, exact);
    EXPECT_GT(allocations, 0);
  }
}

// The calls a game makes between steps, with each of their allocations failing in turn, on a pile that
// has gone to sleep under gravity with a sensor over it: waking it (wake, setVelocity, setPosition of a
// body that holds others up), destroying a body that holds others up, and a sensor's fixture or filter
// that ends its overlaps.
TEST(OutOfMemory, CallsBetweenStepsFailCleanlyAtEveryAllocation) {
  for (StepMode mode : {StepMode::Hybrid, StepMode::Discrete, StepMode::Predictive}) {
    SCOPED_TRACE(static_cast<int>(mode));
    const auto pile = [&] {
      Scene s = boxWithSensor(mode, {0, -9.81}, 40);
      for (int i = 0; i < 600; ++i) s.world.step(1.0 / 60);
      return s;
    };
    if (mode != StepMode::Discrete) {  // (the discrete mode does not put bodies to sleep)
      // Some of the pile must sleep for the wakes below to be tried.
      Scene s = pile();
      EXPECT_NE(afterStep(s.world, s.sensors).asleep.find('z'), std::string::npos);
    }
    const BodyId low{1, 1};  // the first disk, at the bottom of the pile
    // (Handles made here: a call that returns a vector would fail on its own allocation.)
    const FixtureId eye{41, 1}, disk{5, 1};
    int allocations = 0;
    allocations += failEachAllocationOf(pile, [&](World& w) { w.wake(low); }, true, false);
    allocations += failEachAllocationOf(pile, [&](World& w) { w.setVelocity(low, {0, 1}); }, true, false);
    allocations += failEachAllocationOf(pile, [&](World& w) { w.setPosition(low, {5, 9}); }, true, false);
    allocations += failEachAllocationOf(pile, [&](World& w) { w.destroyBody(low); }, true, false);
    allocations += failEachAllocationOf(pile, [&](World& w) { w.destroyFixture(eye); }, true, false);
    allocations += failEachAllocationOf(
        pile, [&](World& w) { w.setFilter(eye, {.categoryBits = 1, .maskBits = 0}); }, true, false);
    allocations += failEachAllocationOf(pile, [&](World& w) { w.setDensity(disk, 3); }, true, false);
    EXPECT_GT(allocations, 0);
  }
}
