// The few ways the network code writes values into the lines it prints and sends: one place, so that a
// desync reads the same from a player, a spectator and the desync report.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

#include "net/protocol.h"

namespace rts::net {

/// A state hash as 16 hex digits (as rattle-replay and rattle-trace print hashes).
inline std::string hexHash(uint64_t v) {
  char text[24];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(v));
  return text;
}

/// Seconds with one decimal, for waits and timeouts.
inline std::string secondsText(double s) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f", s);
  return text;
}

/// A Refuse or Bye reason as the protocol allows it: printable ASCII, at most kMaxReasonBytes.
inline std::string reasonText(const std::string& line) {
  std::string out = line.substr(0, kMaxReasonBytes);
  for (char& c : out) {
    if (c < 0x20 || c > 0x7e) c = '?';
  }
  return out;
}

}  // namespace rts::net
