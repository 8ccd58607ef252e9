// Private: a body's fixture indices, in the order they were created (the first physical one is the body's
// primary fixture, and every loop over a body's fixtures visits them in this order).
//
// Up to kInline indices live inside the list itself, so inside the BodySlot: a disk, a unit with its sight
// circle, a short wall. Reading them then touches no memory beyond the body's own record, which a step has
// already asked for; a std::vector's separate block was one more wait for memory per body visited, and at
// 10^6 bodies the most frequent single one in the hybrid step's re-predictions (perf annotate: about a
// fifth of the hybrid step's repredict's samples on the load of the vector's first element). More indices
// move to a block of their own, as a vector's would.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace rattle::detail {

class FixtureList {
 public:
  static constexpr uint32_t kInline = 4;

  FixtureList() = default;
  FixtureList(const FixtureList& other) { assignFrom(other); }
  FixtureList(FixtureList&& other) noexcept { takeFrom(other); }
  FixtureList& operator=(const FixtureList& other) {
    if (this != &other) {
      release();
      assignFrom(other);
    }
    return *this;
  }
  FixtureList& operator=(FixtureList&& other) noexcept {
    if (this != &other) {
      release();
      takeFrom(other);
    }
    return *this;
  }
  ~FixtureList() { release(); }

  uint32_t* begin() { return data(); }
  uint32_t* end() { return data() + size_; }
  const uint32_t* begin() const { return data(); }
  const uint32_t* end() const { return data() + size_; }
  size_t size() const { return size_; }
  bool empty() const { return size_ == 0; }
  uint32_t front() const { return data()[0]; }
  uint32_t operator[](size_t k) const { return data()[k]; }

  void push_back(uint32_t index) {
    if (size_ == capacity_) grow();
    data()[size_++] = index;
  }
  /// Room for one more index, so that the next push_back cannot fail.
  void reserveOneMore() {
    if (size_ == capacity_) grow();
  }
  // Removes the entry at `at` (an iterator of this list), keeping the order of the rest.
  void erase(const uint32_t* at) {
    uint32_t* d = data();
    const size_t k = static_cast<size_t>(at - d);
    if (k >= size_) return;
    std::memmove(d + k, d + k + 1, (size_ - k - 1) * sizeof(uint32_t));
    --size_;
  }
  void clear() { size_ = 0; }

 private:
  bool onHeap() const { return capacity_ > kInline; }
  uint32_t* data() { return onHeap() ? heap_ : inline_; }
  const uint32_t* data() const { return onHeap() ? heap_ : inline_; }

  void grow() {
    const uint32_t capacity = capacity_ * 2;
    uint32_t* block = new uint32_t[capacity];
    std::memcpy(block, data(), size_ * sizeof(uint32_t));
    release();
    heap_ = block;
    capacity_ = capacity;
  }
  void release() {
    if (onHeap()) delete[] heap_;
    capacity_ = kInline;
  }
  // Into a list that holds nothing on the heap (after release(), or new).
  void assignFrom(const FixtureList& other) {
    if (other.size_ > kInline) {
      heap_ = new uint32_t[other.size_];
      capacity_ = other.size_;
    }
    std::memcpy(data(), other.data(), other.size_ * sizeof(uint32_t));
    size_ = other.size_;
  }
  void takeFrom(FixtureList& other) {
    size_ = other.size_;
    capacity_ = other.capacity_;
    if (other.onHeap()) {
      heap_ = other.heap_;
    } else {
      std::memcpy(inline_, other.inline_, sizeof(inline_));
    }
    other.size_ = 0;
    other.capacity_ = kInline;
  }

  uint32_t size_ = 0;
  uint32_t capacity_ = kInline;  // > kInline: the indices are in heap_
  union {
    uint32_t inline_[kInline] = {};
    uint32_t* heap_;
  };
};

static_assert(sizeof(FixtureList) == 24, "the same size as the std::vector it replaced in BodySlot");

}  // namespace rattle::detail
