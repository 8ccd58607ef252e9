// The broad phase (engine/src/broad_phase/broad_phase.h) against brute force: every pair and every query answer it
// gives must be exactly the pairs an O(n^2) check of the same boxes gives, each once, step after step
// while boxes move, grow, jump, come and go, change kind and filter, and the world outgrows its bands.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <set>
#include <utility>
#include <vector>

#include "broad_phase/broad_phase.h"

namespace rattle {
namespace {

using detail::BroadPhase;

struct Item {
  Box box;
  bool present = false;
  bool moving = false;
  bool sensor = false;
  uint32_t category = ~0u, mask = ~0u;
  uint32_t tag = BroadPhase::kNoTag;
};

using PairSet = std::set<std::pair<uint32_t, uint32_t>>;

std::pair<uint32_t, uint32_t> ordered(uint32_t a, uint32_t b) { return {std::min(a, b), std::max(a, b)}; }

bool filtersMeet(const Item& a, const Item& b) { return (a.category & b.mask) != 0 && (b.category & a.mask) != 0; }

// What findPairs promises: overlapping (closed boxes), one of them moving, neither a sensor, filters meet.
PairSet bruteCollisionPairs(const std::vector<Item>& items) {
  PairSet out;
  for (uint32_t i = 0; i < items.size(); ++i) {
    for (uint32_t j = i + 1; j < items.size(); ++j) {
      const Item &a = items[i], &b = items[j];
      if (!a.present || !b.present || a.sensor || b.sensor) continue;
      if (!(a.moving || b.moving) || !filtersMeet(a, b) || !a.box.overlaps(b.box)) continue;
      out.insert({i, j});
    }
  }
  return out;
}

// What findSensorPairs promises: a sensor and a fixture that is not one, overlapping, one moving,
// filters meet.
PairSet bruteSensorPairs(const std::vector<Item>& items) {
  PairSet out;
  for (uint32_t i = 0; i < items.size(); ++i) {
    for (uint32_t j = i + 1; j < items.size(); ++j) {
      const Item &a = items[i], &b = items[j];
      if (!a.present || !b.present || a.sensor == b.sensor) continue;
      if (!(a.moving || b.moving) || !filtersMeet(a, b) || !a.box.overlaps(b.box)) continue;
      out.insert({i, j});
    }
  }
  return out;
}

class RandomBoxes {
 public:
  explicit RandomBoxes(uint32_t seed) : rng_(seed) {}
  double uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(rng_); }
  uint32_t below(uint32_t n) { return std::uniform_int_distribution<uint32_t>(0, n - 1)(rng_); }

  // A box of one of the kinds a world has: small moving bodies (most), small static obstacles, long
  // horizontal and vertical walls (spanning many bands, or all), zero-size points, and huge boxes.
  Item make(double extent) {
    Item it;
    it.present = true;
    const uint32_t kind = below(20);
    const Vec2 c{uniform(0, extent), uniform(0, extent)};
    Vec2 half{uniform(0.3, 0.7), uniform(0.3, 0.7)};
    if (kind == 0) half = {uniform(0.2, 0.5) * extent, 0};  // a horizontal wall
    if (kind == 1) half = {0, uniform(0.2, 0.5) * extent};  // a vertical wall
    if (kind == 2) half = {0, 0};                            // a point
    if (kind == 3) half = {uniform(2, 8), uniform(2, 8)};   // a large box
    it.box = {c - half, c + half};
    it.moving = kind >= 5 || kind == 3;
    it.sensor = below(10) == 0;
    if (below(4) == 0) {
      it.category = 1u << below(3);
      it.mask = below(2) == 0 ? ~0u : (1u << below(3)) | (1u << below(3));
    }
    return it;
  }

 private:
  std::mt19937 rng_;
};

// A tag for proxy f (every fifth none), and another after a change of it.
uint32_t tagFor(uint32_t f, uint32_t changes = 0) { return f % 5 == 0 ? BroadPhase::kNoTag : 3 * f + changes; }

void add(BroadPhase& bp, uint32_t f, const Item& it) {
  bp.add(f, it.box, it.moving, it.sensor, it.category, it.mask);
  bp.setTag(f, it.tag);
}

PairSet collisionPairs(BroadPhase& bp, int& reportedTwice) {
  PairSet out;
  reportedTwice = 0;
  bp.findPairs([&](uint32_t a, uint32_t b) {
    if (!out.insert(ordered(a, b)).second) ++reportedTwice;
  });
  return out;
}

// One findPairs against brute force: every overlapping pair reported once, with both proxies' tags as
// last set; the pairs told ahead are the first ones reported, each told before it is reported, with the
// same tags. Adds the pairs checked to `checked`, and those told ahead to `toldAhead`.
::testing::AssertionResult pairsMatchBruteForce(BroadPhase& bp, const std::vector<Item>& items, size_t& checked,
                                                size_t* toldAhead = nullptr) {
  int twice = 0, wrongTags = 0;
  PairSet found;
  struct Told {
    uint32_t a, b, tagA, tagB;
    bool operator==(const Told&) const = default;
  };
  std::vector<Told> told, reported;
  std::vector<size_t> toldBefore;  // how many pairs had been told when each was reported
  bp.findPairs(
      [&](uint32_t a, uint32_t b, uint32_t tagA, uint32_t tagB) {
        if (!found.insert(ordered(a, b)).second) ++twice;
        if (tagA != items[a].tag || tagB != items[b].tag) ++wrongTags;
        toldBefore.push_back(told.size());
        reported.push_back({a, b, tagA, tagB});
      },
      [&](uint32_t a, uint32_t b, uint32_t tagA, uint32_t tagB) { told.push_back({a, b, tagA, tagB}); });
  const PairSet expected = bruteCollisionPairs(items);
  if (twice != 0) return ::testing::AssertionFailure() << twice << " pairs reported twice";
  if (wrongTags != 0) return ::testing::AssertionFailure() << wrongTags << " pairs reported with wrong tags";
  if (told.size() > reported.size() || !std::equal(told.begin(), told.end(), reported.begin())) {
    return ::testing::AssertionFailure() << "the pairs told ahead are not the first ones reported";
  }
  for (size_t k = 0; k < told.size(); ++k) {
    if (toldBefore[k] <= k) return ::testing::AssertionFailure() << "pair " << k << " was reported before it was told";
  }
  if (found != expected) {
    return ::testing::AssertionFailure() << found.size() << " pairs found, " << expected.size() << " expected";
  }
  checked += expected.size();
  if (toldAhead != nullptr) *toldAhead += told.size();
  return ::testing::AssertionSuccess();
}

// Checks findPairs, mid-step queries and findSensorPairs against brute force over 40 steps of random
// changes, with the pair cache on or off.
void checkAgainstBruteForceWhileBoxesMoveComeAndGo(bool pairCache) {
  for (uint32_t seed = 1; seed <= 6; ++seed) {
    SCOPED_TRACE(seed);
    RandomBoxes random(seed);
    BroadPhase bp;
    bp.setPairCache(pairCache);
    std::vector<Item> items;
    double extent = 40;
    for (uint32_t f = 0; f < 500; ++f) {
      items.push_back(random.make(extent));
      items.back().tag = tagFor(f);
      add(bp, f, items.back());
    }
    size_t checkedPairs = 0, checkedQueries = 0;
    for (int step = 0; step < 40; ++step) {
      SCOPED_TRACE(step);
      // The world grows now and then (new boxes further out), so the bands are cut again.
      if (step % 10 == 9) extent *= 1.6;
      for (uint32_t f = 0; f < items.size(); ++f) {
        Item& it = items[f];
        if (!it.present) continue;
        const uint32_t what = random.below(100);
        if (what < 3) {
          // Removed; its index is reused below, maybe by the other kind.
          bp.remove(f);
          it.present = false;
        } else if (what < 5) {
          // A jump across the world (the sorted order is far off).
          const Vec2 d{random.uniform(-extent, extent), random.uniform(-extent, extent)};
          it.box = {it.box.min + d, it.box.max + d};
          bp.setBox(f, it.box);
        } else if (what < 6) {
          it.category = 1u << random.below(3);
          bp.setFilter(f, it.category, it.mask);
        } else if (it.moving) {
          const Vec2 d{random.uniform(-0.3, 0.3), random.uniform(-0.3, 0.3)};
          it.box = {it.box.min + d, it.box.max + d};
          bp.setBox(f, it.box);
        }
        if (what == 99) {
          it.moving = !it.moving;
          bp.setMoving(f, it.moving);
        }
        if (what == 98) {
          it.tag = tagFor(f, static_cast<uint32_t>(step) + 1);
          bp.setTag(f, it.tag);
        }
      }
      for (uint32_t f = 0; f < items.size(); ++f) {
        if (!items[f].present && random.below(2) == 0) {
          items[f] = random.make(extent);
          items[f].tag = tagFor(f);
          add(bp, f, items[f]);
        }
      }
      for (int k = 0; k < 10; ++k) {
        items.push_back(random.make(extent));
        items.back().tag = tagFor(static_cast<uint32_t>(items.size() - 1));
        add(bp, static_cast<uint32_t>(items.size() - 1), items.back());
      }

      ASSERT_TRUE(pairsMatchBruteForce(bp, items, checkedPairs));

      // Mid-step: some moving boxes grow (a path that left its swept box), then queries must see the
      // current boxes, grown ones included.
      for (uint32_t f = 0; f < items.size(); ++f) {
        Item& it = items[f];
        if (!it.present || it.sensor || !it.moving || random.below(8) != 0) continue;
        const double grow = random.uniform(0, 6);
        it.box = {it.box.min - Vec2{grow * random.uniform(0, 1), grow * random.uniform(0, 1)},
                  it.box.max + Vec2{grow * random.uniform(0, 1), grow * random.uniform(0, 1)}};
        bp.grow(f, it.box);
      }
      for (int q = 0; q < 40; ++q) {
        const Vec2 c{random.uniform(-0.2 * extent, 1.2 * extent), random.uniform(-0.2 * extent, 1.2 * extent)};
        const Vec2 half{random.uniform(0, 3), random.uniform(0, 3)};
        const Box box{c - half, c + half};
        std::vector<uint32_t> got;
        bp.query(box, [&](uint32_t f) { got.push_back(f); });
        std::vector<uint32_t> want;
        for (uint32_t f = 0; f < items.size(); ++f) {
          if (items[f].present && !items[f].sensor && items[f].box.overlaps(box)) want.push_back(f);
        }
        const size_t reported = got.size();
        std::sort(got.begin(), got.end());
        EXPECT_EQ(std::unique(got.begin(), got.end()), got.end()) << "a proxy reported twice";
        EXPECT_EQ(reported, got.size());
        ASSERT_EQ(got, want);
        checkedQueries += want.size();
      }

      // After the step: the sensors' sweep.
      PairSet sensed;
      int sensedTwice = 0;
      bp.findSensorPairs([&](uint32_t a, uint32_t b) {
        if (!sensed.insert(ordered(a, b)).second) ++sensedTwice;
      });
      EXPECT_EQ(sensedTwice, 0);
      ASSERT_EQ(sensed, bruteSensorPairs(items));
    }
    // The checks were not vacuous.
    EXPECT_GT(checkedPairs, 2000u);
    EXPECT_GT(checkedQueries, 500u);
  }
}

TEST(BroadPhase, PairsAndQueriesMatchBruteForceWhileBoxesMoveComeAndGoAndTheWorldGrows) {
  checkAgainstBruteForceWhileBoxesMoveComeAndGo(false);
}

TEST(BroadPhase, WithThePairCacheTheSamePairsWhileBoxesMoveComeAndGoAndTheWorldGrows) {
  // Every step removes and adds boxes here, so no pairs are kept: each step after a change sweeps plainly
  // (the pair cache's plain path, with its own sort), and must still find every pair.
  checkAgainstBruteForceWhileBoxesMoveComeAndGo(true);
}

TEST(BroadPhase, PairCacheServesStepsOfSmallMovesWithTheSamePairsAndQueriesAsBruteForce) {
  // A gas-like world: 2,000 small moving boxes drifting a little each step (most stay inside their
  // reach), a few fast ones that leave it within a step or two, static walls across the world, sensors,
  // filters, and mid-step growth with queries. Nothing is added or removed, so steps are served from the
  // kept pairs, with the escaped boxes looked up on their own, until too many have escaped.
  for (const double margin : {0.0, BroadPhase::kDefaultMargin, 1.0}) {
    SCOPED_TRACE(margin);
    RandomBoxes random(7);
    BroadPhase bp;
    bp.setPairCache(true);
    bp.setMargin(margin);
    std::vector<Item> items;
    std::vector<Vec2> velocity;
    const double extent = 60;
    for (uint32_t f = 0; f < 2000; ++f) {
      Item it;
      it.present = true;
      it.moving = random.below(10) != 0;
      it.sensor = random.below(20) == 0;
      if (random.below(5) == 0) {
        it.category = 1u << random.below(3);
        it.mask = random.below(2) == 0 ? ~0u : 1u << random.below(3);
      }
      const Vec2 c{random.uniform(0, extent), random.uniform(0, extent)};
      const Vec2 half{random.uniform(0.4, 0.6), random.uniform(0.4, 0.6)};
      it.box = {c - half, c + half};
      it.tag = tagFor(f);
      items.push_back(it);
      // Most drift at about 0.02 a step; one in 50 at 0.5 (a fast body).
      const double speed = random.below(50) == 0 ? 0.5 : random.uniform(0, 0.04);
      const double angle = random.uniform(0, 6.283185307179586);
      velocity.push_back(it.moving ? Vec2{speed * std::cos(angle), speed * std::sin(angle)} : Vec2{});
    }
    for (const double y : {10.0, 30.0, 50.0}) {
      Item wall;
      wall.present = true;
      wall.box = {{-1, y}, {extent + 1, y}};
      items.push_back(wall);
      velocity.push_back({});
    }
    for (uint32_t f = 0; f < items.size(); ++f) add(bp, f, items[f]);
    int fromCache = 0;
    size_t checkedPairs = 0, checkedQueries = 0, checkedAround = 0, toldAhead = 0;
    for (int step = 0; step < 60; ++step) {
      SCOPED_TRACE(step);
      for (uint32_t f = 0; f < items.size(); ++f) {
        if (!items[f].moving) continue;
        items[f].box = items[f].box.translated(velocity[f]);
        bp.setBox(f, items[f].box);
      }
      ASSERT_TRUE(pairsMatchBruteForce(bp, items, checkedPairs, &toldAhead));
      fromCache += bp.lastFromCache() ? 1 : 0;
      for (uint32_t f = 0; f < items.size(); ++f) {
        Item& it = items[f];
        if (it.sensor || !it.moving || random.below(20) != 0) continue;
        const double grow = random.uniform(0, 2);
        it.box = {it.box.min - Vec2{grow * random.uniform(0, 1), grow * random.uniform(0, 1)},
                  it.box.max + Vec2{grow * random.uniform(0, 1), grow * random.uniform(0, 1)}};
        bp.grow(f, it.box);
      }
      // queryAround: a moving proxy's own (grown) box; every other proxy it overlaps whose filter bits
      // meet the proxy's.
      for (int q = 0; q < 40; ++q) {
        const uint32_t f = random.below(2000);
        if (items[f].sensor || !items[f].moving) continue;
        std::vector<uint32_t> got;
        bp.queryAround(f, [&](uint32_t g) {
          if (g != f && filtersMeet(items[f], items[g])) got.push_back(g);
        });
        std::vector<uint32_t> want;
        for (uint32_t g = 0; g < items.size(); ++g) {
          if (g != f && !items[g].sensor && filtersMeet(items[f], items[g]) && items[g].box.overlaps(items[f].box)) {
            want.push_back(g);
          }
        }
        std::sort(got.begin(), got.end());
        ASSERT_EQ(got, want) << "queryAround " << f;
        checkedAround += want.size();
      }
      for (int q = 0; q < 40; ++q) {
        const Vec2 c{random.uniform(0, extent), random.uniform(0, extent)};
        const Vec2 half{random.uniform(0, 2), random.uniform(0, 2)};
        const Box box{c - half, c + half};
        std::vector<uint32_t> got;
        bp.query(box, [&](uint32_t f) { got.push_back(f); });
        std::vector<uint32_t> want;
        for (uint32_t f = 0; f < items.size(); ++f) {
          if (!items[f].sensor && items[f].box.overlaps(box)) want.push_back(f);
        }
        std::sort(got.begin(), got.end());
        ASSERT_EQ(got, want);
        checkedQueries += want.size();
      }
    }
    EXPECT_GT(checkedPairs, 20000u);
    EXPECT_GT(checkedQueries, 1000u);
    EXPECT_GT(checkedAround, 1000u);
    // With a margin many steps were served from the cache (26 of 60 at 0.2: the fast boxes, 1 in 50,
    // escape within a step or two, and past 16 + pairs / 128 escapes the next step sweeps); with none,
    // the drifting boxes leave their reach at once and nearly every step sweeps.
    if (margin > 0) {
      EXPECT_GT(fromCache, 20);
      // The kept pairs' steps told their pairs ahead (the tags checked with them).
      EXPECT_GT(toldAhead, 10000u);
    } else {
      EXPECT_LT(fromCache, 10);
    }
  }
}

TEST(BroadPhase, CrowdedBandOfIdenticalBoxesAndBoxesOnBandEdgesPairOnce) {
  // Many boxes with the same lower x edge (ties in the sort), and boxes whose edges fall exactly on
  // each other (closed boxes touch), in a lattice that fills a band after band.
  BroadPhase bp;
  std::vector<Item> items;
  for (int row = 0; row < 30; ++row) {
    for (int col = 0; col < 30; ++col) {
      Item it;
      it.present = true;
      it.moving = (row + col) % 3 != 0;
      const Vec2 lo{col * 1.0, row * 1.0};
      it.box = {lo, lo + Vec2{1.0, 1.0}};
      items.push_back(it);
      add(bp, static_cast<uint32_t>(items.size() - 1), it);
    }
  }
  for (int step = 0; step < 3; ++step) {
    int twice = 0;
    const PairSet found = collisionPairs(bp, twice);
    EXPECT_EQ(twice, 0);
    const PairSet expected = bruteCollisionPairs(items);
    EXPECT_EQ(found, expected);
    // Each box touches its eight neighbours: most pairs exist.
    EXPECT_GT(expected.size(), 2500u);
  }
}

}  // namespace
}  // namespace rattle
