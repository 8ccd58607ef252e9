// The replay reader: untrusted bytes in, a Replay or a clear error out.
//
// Replays are shared between users, so the reader trusts nothing: every count is checked against the
// bytes left before anything is allocated for it (the parsed replay takes at most about 32 bytes of
// memory per byte of file, plus a constant), every chunk's CRC-32 is checked, every field is range-
// checked, and the first problem is reported with its byte offset, the field and why. It never throws,
// never reads outside the bytes given, never recurses. This is the function the fuzzer calls.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "format/replay.h"

namespace rts::replay {

/// Why a replay could not be read.
struct ReadError {
  size_t offset = 0;    ///< byte offset in the file where the problem is
  std::string field;    ///< what was being read, e.g. "tick 17 command 2 type"
  std::string message;  ///< why, e.g. "unknown command type 9 (1 move, 2 stop, 3 toggle gate, 4 reload world)"
  /// "byte 1234: tick 17 command 2 type: unknown command type 9 (...)"
  std::string describe() const;
};

struct ReadResult {
  std::optional<Replay> replay;  ///< set when the bytes are a valid replay
  ReadError error;               ///< set otherwise
  bool ok() const { return replay.has_value(); }
};

/// Parses a whole replay file held in memory. Never throws; never allocates more than about 32 times
/// `size` (plus a constant). Also checks the embedded map's hash, but does not parse the map's JSON
/// (the map reader, rts::parseMap, does that when the game is built).
ReadResult readReplay(const uint8_t* data, size_t size) noexcept;
ReadResult readReplay(std::string_view bytes) noexcept;

/// Reads the file (refusing files over kMaxFileBytes) and parses it. Errors opening or reading the file
/// come back as a ReadError at offset 0 with field "file".
ReadResult readReplayFile(const std::string& path) noexcept;

}  // namespace rts::replay
