// Private: number formatting for error messages, so a message shows the exact value that was rejected.
#pragma once

#include <cstdio>
#include <string>

#include "rattle/vec2.h"

namespace rattle::detail {

inline std::string str(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

inline std::string str(Vec2 v) { return "(" + str(v.x) + ", " + str(v.y) + ")"; }

}  // namespace rattle::detail
