// An OSMesa (software OpenGL) context that draws scenes into memory. Edges are smoothed by
// supersampling: the scene is drawn `supersample` times larger in each direction and averaged down,
// which gives the same bytes on every run (multisampling would depend on the driver's sample pattern).
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

#include "render/scene.h"

namespace rts {

class RenderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class OffscreenRenderer {
 public:
  /// Throws RenderError when OSMesa cannot make a context of that size.
  OffscreenRenderer(int width, int height, int supersample = 2);
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  /// Draws the scene; returns width x height RGBA pixels, top row first. Valid until the next call.
  const std::vector<uint8_t>& render(const Scene& scene);
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  struct Context;
  int width_, height_, supersample_;
  std::unique_ptr<Context> context_;
  std::vector<uint8_t> big_;     // what OpenGL draws into, supersampled, bottom row first
  std::vector<uint8_t> pixels_;  // the result
};

}  // namespace rts
