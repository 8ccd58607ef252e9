// Private: checks and number formatting for error messages, so a message shows the exact value rejected.
#pragma once

#include <cstdio>
#include <string>

#include "rattle/types.h"
#include "rattle/vec2.h"

namespace rattle::detail {

inline std::string str(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

inline std::string str(Vec2 v) { return "(" + str(v.x) + ", " + str(v.y) + ")"; }

/// Throws rattle::Error with message() when ok is false. The message is built only then: a create call
/// must not pay for formatting.
template <class Message>
void require(bool ok, Message&& message) {
  if (!ok) throw Error(message());
}

}  // namespace rattle::detail
