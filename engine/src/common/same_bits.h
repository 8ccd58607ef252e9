// Private: whether two values have the very same bits, where == would call -0 and +0 equal.
#pragma once

#include <cstring>

namespace rattle::detail {

template <class T>
bool sameBits(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

}  // namespace rattle::detail
