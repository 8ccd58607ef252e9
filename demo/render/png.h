// PNG files, written and read with stb (Debian's libstb).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace rts {

/// Writes RGBA pixels (top row first) as an RGB PNG. Returns an error message, or "" on success.
std::string writePng(const std::string& path, int width, int height, const std::vector<uint8_t>& rgba);

/// Reads a PNG as RGBA. Returns an error message, or "" on success.
std::string readPng(const std::string& path, int& width, int& height, std::vector<uint8_t>& rgba);

}  // namespace rts
