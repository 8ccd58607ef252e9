// FixtureList (engine/src/world/fixture_list.h), a body's fixture indices held in place up to four, checked
// against std::vector, which it replaced, as the reference: the same contents in the same order after
// every operation, across the move from in place to a block of its own, through copies and moves.
#include "world/fixture_list.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <utility>
#include <vector>

namespace {

using rattle::detail::FixtureList;

std::vector<uint32_t> contents(const FixtureList& list) { return {list.begin(), list.end()}; }

void expectSame(const FixtureList& list, const std::vector<uint32_t>& reference) {
  ASSERT_EQ(list.size(), reference.size());
  EXPECT_EQ(list.empty(), reference.empty());
  EXPECT_EQ(contents(list), reference);
  for (size_t k = 0; k < reference.size(); ++k) EXPECT_EQ(list[k], reference[k]);
  if (!reference.empty()) {
    EXPECT_EQ(list.front(), reference.front());
  }
}

TEST(FixtureList, PushEraseAndClearMatchAVector) {
  // Random operations, sizes swinging through 0..12 (in place up to 4, then on the heap and back down).
  std::mt19937 random(7);
  FixtureList list;
  std::vector<uint32_t> reference;
  for (int op = 0; op < 20000; ++op) {
    const uint32_t what = random() % 10;
    if (what < 5 && reference.size() < 12) {
      const uint32_t index = random() % 1000;
      list.push_back(index);
      reference.push_back(index);
    } else if (what < 9 && !reference.empty()) {
      // As World::destroyFixture does: find the index, erase it where it stands.
      const uint32_t index = reference[random() % reference.size()];
      list.erase(std::find(list.begin(), list.end(), index));
      reference.erase(std::find(reference.begin(), reference.end(), index));
    } else if (what == 9 && random() % 8 == 0) {
      list.clear();
      reference.clear();
    }
    expectSame(list, reference);
    if (HasFatalFailure()) return;
  }
}

TEST(FixtureList, EraseOfTheEndIsIgnored) {
  FixtureList list;
  for (uint32_t k = 0; k < 6; ++k) list.push_back(10 * k);
  list.erase(list.end());  // std::find's answer for an index that is not there
  expectSame(list, {0, 10, 20, 30, 40, 50});
}

TEST(FixtureList, CopiesAndMovesKeepTheContentsAndAreIndependent) {
  for (const size_t n : {size_t{0}, size_t{1}, size_t{4}, size_t{5}, size_t{9}}) {
    std::vector<uint32_t> reference;
    FixtureList original;
    for (uint32_t k = 0; k < n; ++k) {
      original.push_back(3 * k + 1);
      reference.push_back(3 * k + 1);
    }
    FixtureList copy(original);
    expectSame(copy, reference);
    copy.push_back(99);  // the copy has storage of its own
    expectSame(original, reference);

    FixtureList assigned;
    for (uint32_t k = 0; k < 7; ++k) assigned.push_back(500 + k);  // on the heap before the assignment
    assigned = original;
    expectSame(assigned, reference);
    assigned = static_cast<const FixtureList&>(assigned);  // self-assignment
    expectSame(assigned, reference);

    FixtureList moved(std::move(copy));
    std::vector<uint32_t> withExtra = reference;
    withExtra.push_back(99);
    expectSame(moved, withExtra);
    EXPECT_TRUE(copy.empty());  // NOLINT(bugprone-use-after-move): a moved-from list is empty and usable
    copy.push_back(5);
    expectSame(copy, {5});

    FixtureList moveAssigned;
    moveAssigned.push_back(8);
    moveAssigned = std::move(moved);
    expectSame(moveAssigned, withExtra);

    // In a vector of bodies that grows: every element is moved to the new block.
    std::vector<FixtureList> many(3, original);
    for (int k = 0; k < 40; ++k) many.push_back(original);
    for (const FixtureList& l : many) expectSame(l, reference);
  }
}

TEST(FixtureList, HoldsAsManyAsAStaticBodyNeeds) {
  FixtureList list;
  std::vector<uint32_t> reference;
  for (uint32_t k = 0; k < 5000; ++k) {
    list.push_back(k * 7u);
    reference.push_back(k * 7u);
  }
  expectSame(list, reference);
}

}  // namespace
