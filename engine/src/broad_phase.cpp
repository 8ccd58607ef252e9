#include "broad_phase.h"

namespace rattle::detail {

void BroadPhase::add(uint32_t fixture, const Box& box, bool moving) {
  if (proxies_.size() <= fixture) proxies_.resize(fixture + 1);
  proxies_[fixture] = Proxy{box, moving, true, box.min.x};
  order_.push_back(fixture);
}

void BroadPhase::remove(uint32_t fixture) {
  proxies_[fixture].present = false;
  order_.erase(std::find(order_.begin(), order_.end(), fixture));
}

void BroadPhase::sortByMinX() {
  // Insertion sort: near-linear on the nearly sorted order left by the previous step. When the order is
  // far from sorted (the first step, many new proxies, a teleport) it would go quadratic, so past a
  // budget of moves it hands over to a full sort. Both orders are total (ties by fixture index in the
  // full sort, by the previous order in insertion sort), so the result depends only on the data.
  const size_t n = order_.size();
  size_t budget = 8 * n + 64;
  for (size_t i = 1; i < n; ++i) {
    const uint32_t f = order_[i];
    const double x = proxies_[f].box.min.x;
    size_t j = i;
    while (j > 0 && proxies_[order_[j - 1]].box.min.x > x) {
      order_[j] = order_[j - 1];
      --j;
    }
    order_[j] = f;
    if (i - j > budget) {
      std::sort(order_.begin(), order_.end(), [this](uint32_t a, uint32_t b) {
        const double xa = proxies_[a].box.min.x, xb = proxies_[b].box.min.x;
        return xa < xb || (xa == xb && a < b);
      });
      return;
    }
    budget -= i - j;
  }
}

void BroadPhase::splitIntoBands() {
  // Band height: twice the mean height of the moving proxies' boxes (static walls can be long and would
  // say nothing about how crowded the moving ones are). At most 4096 bands, and one when little moves.
  double low = 0, high = 0, heights = 0;
  size_t moving = 0;
  bool first = true;
  for (uint32_t f : order_) {
    const Box& b = proxies_[f].box;
    if (first) {
      low = b.min.y;
      high = b.max.y;
      first = false;
    }
    low = std::min(low, b.min.y);
    high = std::max(high, b.max.y);
    if (proxies_[f].moving) {
      heights += b.max.y - b.min.y;
      ++moving;
    }
  }
  bandCount_ = 1;
  bandOrigin_ = low;
  inverseBandHeight_ = 0;
  if (moving >= 64) {
    const double bandHeight = 2 * heights / static_cast<double>(moving);
    const double count = bandHeight > 0 ? (high - low) / bandHeight : 1;
    if (count > 1 && count < 1e9) {
      bandCount_ = static_cast<uint32_t>(std::min(count, 4096.0)) + 1;
      inverseBandHeight_ = static_cast<double>(bandCount_ - 1) / (high - low);
    }
  }
  if (bands_.size() < bandCount_) bands_.resize(bandCount_);
  for (uint32_t b = 0; b < bandCount_; ++b) bands_[b].clear();
  for (uint32_t f : order_) {
    const Box& box = proxies_[f].box;
    const uint32_t last = bandOf(box.max.y);
    for (uint32_t b = bandOf(box.min.y); b <= last; ++b) bands_[b].push_back(f);
  }
}

void BroadPhase::prepareQueries() {
  moving_.clear();
  static_.clear();
  movingReach_ = 0;
  movingGrowLeft_ = 0;
  for (uint32_t f : order_) {
    Proxy& p = proxies_[f];
    p.sortedMinX = p.box.min.x;
    if (p.moving) {
      moving_.push_back({p.box.min.x, f});
      movingReach_ = std::max(movingReach_, p.box.max.x - p.box.min.x);
    } else {
      static_.push_back({p.box.min.x, f});
    }
  }
}

void BroadPhase::grow(uint32_t fixture, const Box& grown) {
  Proxy& p = proxies_[fixture];
  p.box = grown;
  movingReach_ = std::max(movingReach_, grown.max.x - p.sortedMinX);
  movingGrowLeft_ = std::max(movingGrowLeft_, p.sortedMinX - grown.min.x);
}

}  // namespace rattle::detail
