// Text for the HUD, from stb_easy_font: quads in pixel coordinates, no font files.
#pragma once

#include <string>
#include <vector>

namespace rts {

struct TextQuad {
  float x0, y0, x1, y1;
};

/// The quads of `text` drawn at (x, y) with each font pixel `scale` screen pixels wide.
std::vector<TextQuad> textQuads(const std::string& text, float x, float y, float scale);
/// Width in screen pixels of `text` at `scale`.
float textWidth(const std::string& text, float scale);

}  // namespace rts
