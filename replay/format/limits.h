// The format's constants and the bounds a reader enforces (FORMAT.md, "Limits").
#pragma once

#include <cstddef>
#include <cstdint>

namespace rts::replay {

inline constexpr char kMagic[8] = {'R', 'A', 'T', 'T', 'L', 'R', 'E', 'P'};
inline constexpr uint16_t kFormatVersion = 1;

inline constexpr size_t kMaxFileBytes = size_t(1) << 30;      ///< readReplayFile refuses larger files
inline constexpr size_t kMaxChunkBytes = size_t(64) << 20;    ///< one chunk's payload
inline constexpr size_t kMaxMapBytes = size_t(16) << 20;      ///< the embedded map (as kMaxMapFileBytes)
inline constexpr size_t kMaxBuildFacts = 64;
inline constexpr size_t kMaxFactKeyBytes = 64;
inline constexpr size_t kMaxFactValueBytes = 1024;
inline constexpr size_t kMaxNameBytes = 256;                  ///< map name, recordedBy
inline constexpr uint32_t kMaxUnitsPerTeam = 200'000;         ///< as rattle-demo --units
inline constexpr uint32_t kMaxGates = 32;                     ///< as the map reader
inline constexpr uint32_t kMaxDoorways = 100'000;             ///< as the map reader's object limit
inline constexpr uint32_t kMaxRooms = 100'000;
inline constexpr uint32_t kMaxTicks = 100'000'000;
inline constexpr uint32_t kMaxKeyframeEvery = 100'000'000;

}  // namespace rts::replay
