// Reads the format's primitive values from untrusted bytes. Every read is bounds-checked; a failure
// throws FormatError naming the absolute byte offset, the field being read and why.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

namespace rts::replay {

/// A malformed replay: where (byte offset in the file), what (the field) and why. Thrown inside the
/// reader only; readReplay() turns it into a ReadError.
class FormatError : public std::runtime_error {
 public:
  FormatError(size_t offset, std::string field, const std::string& why)
      : std::runtime_error(why), offset_(offset), field_(std::move(field)) {}
  size_t offset() const { return offset_; }
  const std::string& field() const { return field_; }

 private:
  size_t offset_;
  std::string field_;
};

class ByteReader {
 public:
  /// `base`: the file offset of bytes[0], for messages.
  ByteReader(std::string_view bytes, size_t base) : bytes_(bytes), base_(base) {}

  size_t offset() const { return base_ + pos_; }
  size_t remaining() const { return bytes_.size() - pos_; }
  bool atEnd() const { return pos_ == bytes_.size(); }

  [[noreturn]] void fail(const std::string& field, const std::string& why) const { throw FormatError(offset(), field, why); }
  [[noreturn]] void failAt(size_t offset, const std::string& field, const std::string& why) const {
    throw FormatError(offset, field, why);
  }

  uint8_t u8(const std::string& field) { return uint8_t(fixed(field, 1)); }
  uint16_t u16(const std::string& field) { return uint16_t(fixed(field, 2)); }
  uint32_t u32(const std::string& field) { return uint32_t(fixed(field, 4)); }
  uint64_t u64(const std::string& field) { return fixed(field, 8); }
  double f64(const std::string& field);
  /// A finite double.
  double finite(const std::string& field);
  /// A varint in [lo, hi].
  uint64_t varint(const std::string& field, uint64_t lo = 0, uint64_t hi = UINT64_MAX);
  /// A zigzag varint in [lo, hi].
  int64_t zigzag(const std::string& field, int64_t lo, int64_t hi);
  /// A bool stored as one byte, 0 or 1.
  bool flag(const std::string& field);
  /// A string of at most maxBytes bytes (its varint length is checked before anything is allocated).
  std::string str(const std::string& field, size_t maxBytes);
  /// The next n bytes (n <= remaining(), else an error naming `field`).
  std::string_view bytes(const std::string& field, size_t n);
  /// A count of items that take at least `minBytesEach` bytes each: it must fit in what is left, so a
  /// huge count in a small file is an error before anything is allocated for it.
  size_t count(const std::string& field, size_t minBytesEach, size_t hi);
  /// Fails unless every byte has been read.
  void expectEnd(const std::string& what) const;

 private:
  uint64_t fixed(const std::string& field, int n);
  std::string_view bytes_;
  size_t base_;
  size_t pos_ = 0;
};

}  // namespace rts::replay
