#include "render/hud_text.h"

#include <stb_easy_font.h>

#include <cstring>

namespace rts {

std::vector<TextQuad> textQuads(const std::string& text, float x, float y, float scale) {
  // stb_easy_font writes 4 vertices per quad, 16 bytes each (x, y, z floats and an RGBA colour).
  std::vector<char> buffer(text.size() * 270 + 64);
  std::string copy = text;
  const int quads = stb_easy_font_print(0, 0, copy.data(), nullptr, buffer.data(), int(buffer.size()));
  std::vector<TextQuad> out;
  out.reserve(size_t(quads));
  for (int q = 0; q < quads; ++q) {
    float v0[2], v2[2];  // the quad's first and third corners
    std::memcpy(v0, buffer.data() + size_t(q) * 64, sizeof v0);
    std::memcpy(v2, buffer.data() + size_t(q) * 64 + 32, sizeof v2);
    out.push_back({x + v0[0] * scale, y + v0[1] * scale, x + v2[0] * scale, y + v2[1] * scale});
  }
  return out;
}

float textWidth(const std::string& text, float scale) {
  std::string copy = text;
  return float(stb_easy_font_width(copy.data())) * scale;
}

}  // namespace rts
