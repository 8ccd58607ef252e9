// Appends the format's primitive values to a byte string (FORMAT.md, "Primitive values").
#pragma once

#include <bit>
#include <cstdint>
#include <string>
#include <string_view>

namespace rts::replay {

class ByteWriter {
 public:
  void u8(uint8_t v) { out_.push_back(char(v)); }
  void u16(uint16_t v) { fixed(v, 2); }
  void u32(uint32_t v) { fixed(v, 4); }
  void u64(uint64_t v) { fixed(v, 8); }
  void f64(double v) { u64(std::bit_cast<uint64_t>(v)); }
  /// Unsigned LEB128: 7 bits a byte, low bits first, high bit set on all but the last byte.
  void varint(uint64_t v) {
    while (v >= 0x80) {
      u8(uint8_t(v) | 0x80);
      v >>= 7;
    }
    u8(uint8_t(v));
  }
  /// Zigzag (0, -1, 1, -2, ... as 0, 1, 2, 3, ...), then varint.
  void zigzag(int64_t v) { varint((uint64_t(v) << 1) ^ uint64_t(v >> 63)); }
  /// varint length, then the bytes.
  void str(std::string_view s) {
    varint(s.size());
    bytes(s);
  }
  void bytes(std::string_view s) { out_.append(s); }

  const std::string& data() const { return out_; }
  std::string& data() { return out_; }
  size_t size() const { return out_.size(); }
  void clear() { out_.clear(); }

 private:
  void fixed(uint64_t v, int n) {
    for (int i = 0; i < n; ++i) out_.push_back(char(uint8_t(v >> (8 * i))));
  }
  std::string out_;
};

}  // namespace rts::replay
