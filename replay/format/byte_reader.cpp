#include "format/byte_reader.h"

#include <bit>
#include <cmath>

namespace rts::replay {

uint64_t ByteReader::fixed(const std::string& field, int n) {
  if (remaining() < size_t(n)) {
    fail(field, "truncated: needs " + std::to_string(n) + " bytes, " + std::to_string(remaining()) + " left");
  }
  uint64_t v = 0;
  for (int i = 0; i < n; ++i) v |= uint64_t(uint8_t(bytes_[pos_ + size_t(i)])) << (8 * i);
  pos_ += size_t(n);
  return v;
}

double ByteReader::f64(const std::string& field) { return std::bit_cast<double>(fixed(field, 8)); }

double ByteReader::finite(const std::string& field) {
  const size_t at = offset();
  const double d = f64(field);
  if (!std::isfinite(d)) failAt(at, field, "not a finite number");
  return d;
}

uint64_t ByteReader::varint(const std::string& field, uint64_t lo, uint64_t hi) {
  const size_t at = offset();
  uint64_t v = 0;
  for (int shift = 0;; shift += 7) {
    if (atEnd()) fail(field, "truncated inside a varint");
    const uint8_t b = uint8_t(bytes_[pos_++]);
    if (shift == 63 && b > 1) failAt(at, field, "varint longer than 64 bits");
    v |= uint64_t(b & 0x7F) << shift;
    if (!(b & 0x80)) break;
    if (shift == 63) failAt(at, field, "varint longer than 10 bytes");
  }
  if (v < lo || v > hi) {
    failAt(at, field, std::to_string(v) + " is out of range (" + std::to_string(lo) + " to " + std::to_string(hi) + ")");
  }
  return v;
}

int64_t ByteReader::zigzag(const std::string& field, int64_t lo, int64_t hi) {
  const size_t at = offset();
  const uint64_t u = varint(field);
  const int64_t v = int64_t(u >> 1) ^ -int64_t(u & 1);
  if (v < lo || v > hi) {
    failAt(at, field, std::to_string(v) + " is out of range (" + std::to_string(lo) + " to " + std::to_string(hi) + ")");
  }
  return v;
}

bool ByteReader::flag(const std::string& field) {
  const size_t at = offset();
  const uint8_t b = u8(field);
  if (b > 1) failAt(at, field, std::to_string(b) + ": expected 0 or 1");
  return b == 1;
}

std::string ByteReader::str(const std::string& field, size_t maxBytes) {
  const size_t at = offset();
  const uint64_t n = varint(field + " length");
  if (n > maxBytes) failAt(at, field, "string of " + std::to_string(n) + " bytes; at most " + std::to_string(maxBytes) + " allowed");
  if (n > remaining()) failAt(at, field, "string of " + std::to_string(n) + " bytes, only " + std::to_string(remaining()) + " left");
  return std::string(bytes(field, size_t(n)));
}

std::string_view ByteReader::bytes(const std::string& field, size_t n) {
  if (n > remaining()) fail(field, "truncated: needs " + std::to_string(n) + " bytes, " + std::to_string(remaining()) + " left");
  std::string_view out = bytes_.substr(pos_, n);
  pos_ += n;
  return out;
}

size_t ByteReader::count(const std::string& field, size_t minBytesEach, size_t hi) {
  const size_t at = offset();
  const uint64_t n = varint(field);
  if (n > hi) failAt(at, field, std::to_string(n) + " is out of range (at most " + std::to_string(hi) + ")");
  if (minBytesEach > 0 && n > remaining() / minBytesEach) {
    failAt(at, field, std::to_string(n) + " items cannot fit in the " + std::to_string(remaining()) + " bytes left");
  }
  return size_t(n);
}

void ByteReader::expectEnd(const std::string& what) const {
  if (!atEnd()) fail(what, std::to_string(remaining()) + " unexpected bytes at the end");
}

}  // namespace rts::replay
