// Text read from a file (a map's names and values, a replay's map name and build facts) on its way to a
// terminal. Maps and replays are shared, so their strings are untrusted: an ESC or OSC sequence in a map
// name would otherwise be run by the terminal of whoever prints it (set the window title, move the
// cursor, write to the clipboard, ...). Header-only, so the replay format's library, which links no demo
// code, shares it.
#pragma once

#include <string>
#include <string_view>

namespace rts {

/// `text` with each byte a terminal could act on replaced by '?': C0 controls (newline and tab too: a
/// message stays one line), DEL, bytes that are not well-formed UTF-8 (in a Latin-1 terminal 0x9b alone
/// starts a control sequence), the C1 controls U+0080 to U+009F, and the bidirectional overrides and
/// isolates (U+202A to U+202E, U+2066 to U+2069), which reorder what is shown. Other UTF-8 is kept.
inline std::string printable(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  size_t i = 0;
  while (i < text.size()) {
    const unsigned char b = static_cast<unsigned char>(text[i]);
    if (b < 0x80) {
      out += (b < 0x20 || b == 0x7f) ? '?' : char(b);
      ++i;
      continue;
    }
    // A UTF-8 lead byte, its length, and the range its first continuation byte must fall in (that range
    // rules out overlong forms, surrogates and code points past U+10FFFF).
    size_t length = 0;
    unsigned char lo = 0x80, hi = 0xbf;
    if (b >= 0xc2 && b <= 0xdf) {
      length = 2;
    } else if (b >= 0xe0 && b <= 0xef) {
      length = 3;
      if (b == 0xe0) lo = 0xa0;
      if (b == 0xed) hi = 0x9f;
    } else if (b >= 0xf0 && b <= 0xf4) {
      length = 4;
      if (b == 0xf0) lo = 0x90;
      if (b == 0xf4) hi = 0x8f;
    }
    bool valid = length > 0 && i + length <= text.size();
    for (size_t k = 1; valid && k < length; ++k) {
      const unsigned char c = static_cast<unsigned char>(text[i + k]);
      valid = k == 1 ? (c >= lo && c <= hi) : (c >= 0x80 && c <= 0xbf);
    }
    if (!valid) {
      out += '?';
      ++i;
      continue;
    }
    unsigned codePoint = b & (0x7f >> length);
    for (size_t k = 1; k < length; ++k) codePoint = codePoint << 6 | (static_cast<unsigned char>(text[i + k]) & 0x3f);
    const bool control = codePoint <= 0x9f || (codePoint >= 0x202a && codePoint <= 0x202e) ||
                         (codePoint >= 0x2066 && codePoint <= 0x2069);
    if (control) {
      out += '?';
    } else {
      out.append(text.substr(i, length));
    }
    i += length;
  }
  return out;
}

}  // namespace rts
