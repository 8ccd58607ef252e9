#include "render/png.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <cerrno>
#include <cstring>

namespace rts {

std::string writePng(const std::string& path, int width, int height, const std::vector<uint8_t>& rgba) {
  if (width < 1 || height < 1 || rgba.size() != size_t(width) * size_t(height) * 4) return path + ": bad image size";
  std::vector<uint8_t> rgb(size_t(width) * size_t(height) * 3);
  for (size_t i = 0, n = size_t(width) * size_t(height); i < n; ++i) std::memcpy(&rgb[i * 3], &rgba[i * 4], 3);
  errno = 0;
  if (!stbi_write_png(path.c_str(), width, height, 3, rgb.data(), width * 3)) {
    return path + ": cannot write the PNG" + (errno ? std::string(" (") + std::strerror(errno) + ")" : std::string());
  }
  return "";
}

std::string readPng(const std::string& path, int& width, int& height, std::vector<uint8_t>& rgba) {
  int channels = 0;
  unsigned char* data = stbi_load(path.c_str(), &width, &height, &channels, 4);
  if (!data) return path + ": cannot read the PNG (" + std::string(stbi_failure_reason()) + ")";
  rgba.assign(data, data + size_t(width) * size_t(height) * 4);
  stbi_image_free(data);
  return "";
}

}  // namespace rts
