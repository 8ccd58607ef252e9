#include "tool/image_compare.h"

#include <algorithm>
#include <cstdlib>

namespace rts::replay {

ImageComparison compareImages(const std::vector<uint8_t>& golden, int gw, int gh, const std::vector<uint8_t>& actual, int aw, int ah,
                              int tolerance) {
  ImageComparison c;
  const size_t n = size_t(std::max(gw, 0)) * size_t(std::max(gh, 0));
  if (gw != aw || gh != ah || golden.size() != n * 4 || actual.size() != n * 4) {
    c.sameSize = false;
    return c;
  }
  c.pixels = n;
  c.diff.resize(n * 4);
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* g = &golden[i * 4];
    const uint8_t* a = &actual[i * 4];
    int worst = 0;
    for (int k = 0; k < 3; ++k) worst = std::max(worst, std::abs(int(g[k]) - int(a[k])));
    c.largestDifference = std::max(c.largestDifference, worst);
    uint8_t* d = &c.diff[i * 4];
    if (worst > tolerance) {
      ++c.differing;
      d[0] = 255;
      d[1] = d[2] = uint8_t(std::max(0, 160 - worst));
    } else {
      const uint8_t grey = uint8_t((int(g[0]) + int(g[1]) + int(g[2])) / 3 / 3);
      d[0] = d[1] = d[2] = grey;
    }
    d[3] = 255;
  }
  return c;
}

}  // namespace rts::replay
