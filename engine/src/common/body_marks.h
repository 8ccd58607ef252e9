// Private: values a step gives a few bodies, by body index, that go back to T{} at the next clear().
// For what a mode or the islands keep of a body in one step (the jams that settled it, the round-off
// approaches it absorbed): in a step that marks none, get() reads nothing but the list's size, and
// clear() costs what was marked, not the world.
#pragma once

#include <cstdint>
#include <vector>

#include "common/large_array.h"

namespace rattle::detail {

template <class T>
class BodyMarks {
 public:
  /// The body's value: T{} unless set since the last clear().
  T get(uint32_t body) const { return marked_.empty() || body >= values_.size() ? T{} : values_[body]; }
  void set(uint32_t body, const T& value) {
    if (values_.size() <= body) values_.resize(body + size_t{1});
    if (values_[body] == T{}) marked_.push_back(body);
    values_[body] = value;
  }
  void clear() {
    for (uint32_t body : marked_) values_[body] = T{};
    marked_.clear();
  }

 private:
  LargeArray<T> values_;
  std::vector<uint32_t> marked_;  // the bodies whose value is not T{} (a body set back to T{} may stay)
};

}  // namespace rattle::detail
