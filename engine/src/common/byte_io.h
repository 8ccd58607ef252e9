// Private: little-endian bytes for World::save and World::load (api/world_save.cpp). Doubles travel as
// their IEEE-754 bits, so a save reads back bit for bit on every machine; the reader refuses anything
// past the end with the offset and the field it was reading.
#pragma once

#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include "rattle/types.h"

namespace rattle::detail {

class ByteWriter {
 public:
  void u8(uint8_t v) { bytes_.push_back(v); }
  void u32(uint32_t v) { little(v, 4); }
  void i32(int32_t v) { little(static_cast<uint32_t>(v), 4); }
  void u64(uint64_t v) { little(v, 8); }
  void f64(double v) {
    uint64_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    u64(bits);
  }
  void vec2(Vec2 v) {
    f64(v.x);
    f64(v.y);
  }
  void raw(std::span<const uint8_t> b) { bytes_.insert(bytes_.end(), b.begin(), b.end()); }
  std::vector<uint8_t>& bytes() { return bytes_; }

 private:
  void little(uint64_t v, int n) {
    for (int i = 0; i < n; ++i) bytes_.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  std::vector<uint8_t> bytes_;
};

/// Reads what ByteWriter wrote. Every read names its field (within the entry set by `entry`): past the
/// end, or refused by a check, it throws rattle::Error "<what>: byte <offset>: <entry>.<field> ...".
class ByteReader {
 public:
  ByteReader(std::span<const uint8_t> bytes, std::string what) : bytes_(bytes), what_(std::move(what)) {}

  static constexpr uint32_t kNoIndex = 0xFFFFFFFFu;
  /// The fields read next belong to list[index], or to `list` itself without an index (null: to none).
  void entry(const char* list, uint32_t index = kNoIndex) {
    list_ = list;
    index_ = index;
  }
  uint8_t u8(const char* field) { return static_cast<uint8_t>(little(1, field)); }
  uint32_t u32(const char* field) { return static_cast<uint32_t>(little(4, field)); }
  int32_t i32(const char* field) { return static_cast<int32_t>(u32(field)); }
  /// A byte that must be 0 or 1.
  bool flag(const char* field) {
    const size_t at = offset_;
    const uint8_t v = u8(field);
    if (v > 1) fail(at, field, " = " + std::to_string(v) + ": must be 0 or 1");
    return v == 1;
  }
  uint64_t u64(const char* field) { return little(8, field); }
  double f64(const char* field) {
    const uint64_t bits = u64(field);
    double v;
    std::memcpy(&v, &bits, sizeof v);
    return v;
  }
  Vec2 vec2(const char* field) {
    const double x = f64(field);
    return {x, f64(field)};
  }
  /// A count of entries of at least `entryBytes` each: refused when the bytes left cannot hold them,
  /// so that no list is sized from a count the input does not back.
  uint32_t count(const char* field, size_t entryBytes) {
    const size_t at = offset_;
    const uint32_t n = u32(field);
    if (entryBytes > 0 && n > (bytes_.size() - offset_) / entryBytes) {
      fail(at, field, " = " + std::to_string(n) + ": more entries than the " +
                          std::to_string(bytes_.size() - offset_) + " bytes left can hold");
    }
    return n;
  }
  size_t offset() const { return offset_; }
  size_t left() const { return bytes_.size() - offset_; }
  /// Throws rattle::Error for `field` of the current entry, which starts at byte `at`.
  [[noreturn]] void fail(size_t at, const char* field, const std::string& message) const {
    std::string name = list_ ? std::string(list_) : std::string();
    if (list_ && index_ != kNoIndex) name += "[" + std::to_string(index_) + "]";
    if (field && *field) name += (name.empty() ? "" : ".") + std::string(field);
    throw Error(what_ + ": byte " + std::to_string(at) + ": " + name + message);
  }

 private:
  uint64_t little(int n, const char* field) {
    if (bytes_.size() - offset_ < static_cast<size_t>(n)) {
      fail(offset_, field, ": the bytes end here (" + std::to_string(bytes_.size()) + " in all)");
    }
    uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= uint64_t{bytes_[offset_ + i]} << (8 * i);
    offset_ += n;
    return v;
  }
  std::span<const uint8_t> bytes_;
  std::string what_;
  size_t offset_ = 0;
  const char* list_ = nullptr;
  uint32_t index_ = kNoIndex;
};

/// FNV-1a over the bytes (the save's checksum).
inline uint64_t fnv1a(std::span<const uint8_t> bytes) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (uint8_t b : bytes) {
    h ^= b;
    h *= 0x100000001b3ull;
  }
  return h;
}

}  // namespace rattle::detail
