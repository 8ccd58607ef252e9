// Draws a Scene with OpenGL 1.x vertex arrays into whatever context is current: the offscreen OSMesa
// context for PNG frames, and (through the same offscreen buffer) the SDL window.
#pragma once

#include "render/scene.h"

namespace rts {

/// Where the world lands on the screen: screen = world * scale + offset (pixels, y down).
struct View {
  double scale = 1;
  Vec2 offset;
  Vec2 toScreen(Vec2 w) const { return w * scale + offset; }
  Vec2 toWorld(Vec2 s) const { return (s - offset) * (1.0 / scale); }
};

/// The whole map, as large as fits, centred.
View fitView(double worldWidth, double worldHeight, int width, int height);

/// Draws the scene into the current GL context's framebuffer of width x height pixels (with a stencil
/// buffer for the fog of war).
void drawScene(const Scene& scene, int width, int height);

}  // namespace rts
