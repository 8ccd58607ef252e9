#include "render/offscreen.h"

#include <GL/osmesa.h>

#include <cstdlib>
#include <string>

#include "render/renderer.h"

namespace rts {

struct OffscreenRenderer::Context {
  OSMesaContext ctx = nullptr;
  ~Context() {
    if (ctx) OSMesaDestroyContext(ctx);
  }
};

OffscreenRenderer::OffscreenRenderer(int width, int height, int supersample)
    : width_(width), height_(height), supersample_(supersample), context_(std::make_unique<Context>()) {
  if (width < 1 || height < 1 || supersample < 1 || width * supersample > 16384 || height * supersample > 16384) {
    throw RenderError("frame size " + std::to_string(width) + "x" + std::to_string(height) + " (x" +
                      std::to_string(supersample) + " supersampling) is outside what OSMesa draws (16384 pixels a side)");
  }
  // Mesa keeps compiled shaders in ~/.cache/mesa_shader_cache unless told not to: a headless run writes
  // frames where it is asked and nothing else. A value the user set is kept.
  setenv("MESA_SHADER_CACHE_DISABLE", "true", 0);
  setenv("MESA_DISK_CACHE_DISABLE", "true", 0);
  // RGBA colour, no depth buffer, 8 stencil bits for the fog of war, no accumulation buffer.
  context_->ctx = OSMesaCreateContextExt(OSMESA_RGBA, 0, 8, 0, nullptr);
  if (!context_->ctx) throw RenderError("OSMesa could not create an OpenGL context");
  big_.assign(size_t(width) * size_t(supersample) * size_t(height) * size_t(supersample) * 4, 0);
  pixels_.assign(size_t(width) * size_t(height) * 4, 0);
}

OffscreenRenderer::~OffscreenRenderer() = default;

const std::vector<uint8_t>& OffscreenRenderer::render(const Scene& scene) {
  const int bw = width_ * supersample_, bh = height_ * supersample_;
  if (!OSMesaMakeCurrent(context_->ctx, big_.data(), GL_UNSIGNED_BYTE, bw, bh)) {
    throw RenderError("OSMesa could not draw into a " + std::to_string(bw) + "x" + std::to_string(bh) + " buffer");
  }
  drawScene(scene, bw, bh);
  // Average each supersample x supersample block; OSMesa's rows run bottom to top, PNG's top to bottom.
  const int s = supersample_, area = s * s;
  for (int y = 0; y < height_; ++y) {
    for (int x = 0; x < width_; ++x) {
      unsigned sum[4] = {0, 0, 0, 0};
      for (int dy = 0; dy < s; ++dy) {
        const uint8_t* row = &big_[(size_t(bh - 1 - (y * s + dy)) * size_t(bw) + size_t(x * s)) * 4];
        for (int dx = 0; dx < s; ++dx) {
          for (int c = 0; c < 4; ++c) sum[c] += row[dx * 4 + c];
        }
      }
      uint8_t* out = &pixels_[(size_t(y) * size_t(width_) + size_t(x)) * 4];
      for (int c = 0; c < 4; ++c) out[c] = uint8_t((sum[c] + unsigned(area) / 2) / unsigned(area));
      out[3] = 255;
    }
  }
  return pixels_;
}

}  // namespace rts
