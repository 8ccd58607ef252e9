// Reads a map from Tiled's JSON format (see demo/MAPS.md for the properties a map may use).
//
// Maps are shared between players, so they are untrusted input: every problem is reported as a
// MapError whose message names the object id and the field, and nothing in a file can crash the
// loader or make it allocate much more than the file's size.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

#include "map/map.h"

namespace rts {

class MapError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Largest map file accepted, in bytes.
inline constexpr size_t kMaxMapFileBytes = 16u << 20;

/// Parses a Tiled JSON map held in memory. `sourceName` only labels error messages.
Map parseMap(std::string_view json, const std::string& sourceName);

/// Reads a map file's bytes (at most kMaxMapFileBytes), unparsed: for a replay, which embeds them.
std::string readMapFile(const std::string& path);

/// Reads and parses a map file.
Map loadMap(const std::string& path);

}  // namespace rts
