// Private: memory exhaustion at the World API, as rattle::Error.
#pragma once

#include <algorithm>
#include <cstddef>
#include <new>
#include <stdexcept>
#include <string>

#include "rattle/types.h"

namespace rattle::detail {

/// Room for one more element, made before anything changes, so that the push that follows cannot fail
/// half way through a call.
template <class Vector>
void roomForOneMore(Vector& v) {
  if (v.size() == v.capacity()) v.reserve(std::max<std::size_t>(16, 2 * v.capacity()));
}

/// Room for `count` more elements, growing geometrically (calls that each add a few stay linear).
template <class Vector>
void roomFor(Vector& v, std::size_t count) {
  if (v.capacity() - v.size() < count) v.reserve(std::max(2 * v.capacity(), v.size() + count));
}

/// Runs a call that checks its input and makes room for what it adds before it changes anything, so
/// that memory exhaustion leaves the world unchanged: std::bad_alloc (and a length beyond what a
/// container can hold) becomes rattle::Error naming the call.
template <class Call>
decltype(auto) unlessOutOfMemory(const char* name, Call&& call) {
  try {
    return call();
  } catch (const std::bad_alloc&) {
    throw Error(std::string(name) + ": out of memory (the world is unchanged)");
  } catch (const std::length_error&) {
    throw Error(std::string(name) + ": out of memory (the world is unchanged)");
  }
}

}  // namespace rattle::detail
