// Comparing a rendered frame with a golden one, with a per-pixel tolerance, and a picture of the
// difference for a person to look at.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace rts::replay {

struct ImageComparison {
  bool sameSize = true;
  size_t pixels = 0;           ///< pixels compared
  size_t differing = 0;        ///< pixels with a channel off by more than the tolerance
  int largestDifference = 0;   ///< over all channels of all pixels, 0 to 255
  /// RGBA, the size of the images: the golden dimmed to grey, differing pixels in bright red (more
  /// red the larger the difference). Empty when the sizes differ.
  std::vector<uint8_t> diff;
};

/// Compares RGBA images of width x height; a pixel differs when one of its R, G, B channels differs by
/// more than `tolerance` (alpha is not compared: PNG frames are RGB).
ImageComparison compareImages(const std::vector<uint8_t>& golden, int goldenWidth, int goldenHeight, const std::vector<uint8_t>& actual,
                              int actualWidth, int actualHeight, int tolerance);

}  // namespace rts::replay
