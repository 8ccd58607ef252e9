// The three hashes of the format: CRC-32 over every chunk, FNV-1a 64 of the embedded map, and the
// 16-bit body digests.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace rts::replay {

/// CRC-32 (IEEE 802.3, reflected, polynomial 0xEDB88320; the one zlib and PNG use). `crc` continues
/// an earlier call; start with 0.
uint32_t crc32(const void* data, size_t size, uint32_t crc = 0);

/// FNV-1a, 64 bits.
uint64_t fnv1a64(std::string_view bytes);

/// A body's digest: FNV-1a 64 of its encoded state, folded to 16 bits by xor of the four 16-bit words.
uint16_t digest16(std::string_view encodedState);

}  // namespace rts::replay
