#include "broad_phase.h"

#include <algorithm>
#include <limits>

namespace rattle::detail {

void BroadPhase::add(uint32_t fixture, const Box& box, bool moving, bool sensor, uint32_t category, uint32_t mask) {
  if (proxies_.size() <= fixture) proxies_.resize(fixture + 1);
  Proxy& p = proxies_[fixture];
  if (!p.present && p.listed) --removed_;  // removed and added again before a sort: listed once
  const bool listed = p.listed;
  if (listed && p.sensor != sensor) ++misfiled_;  // in the other list until the next sort moves it
  p = Proxy{box, moving, true, true, sensor, category, mask, p.stamp};
  if (!listed) (sensor ? sensorOrder_ : order_).push_back(fixture);
}

void BroadPhase::remove(uint32_t fixture) {
  Proxy& p = proxies_[fixture];
  if (!p.present) return;
  p.present = false;
  ++removed_;
}

void BroadPhase::sortByMinX(bool withSensors) {
  if (removed_ > 0 || misfiled_ > 0) {
    std::vector<uint32_t> kept, keptSensors;
    for (const std::vector<uint32_t>* list : {&order_, &sensorOrder_}) {
      for (uint32_t f : *list) {
        if (proxies_[f].present) {
          (proxies_[f].sensor ? keptSensors : kept).push_back(f);
        } else {
          proxies_[f].listed = false;
        }
      }
    }
    order_ = std::move(kept);
    sensorOrder_ = std::move(keptSensors);
    removed_ = 0;
    misfiled_ = 0;
  }
  sortList(order_);
  if (withSensors) sortList(sensorOrder_);
}

void BroadPhase::sortList(std::vector<uint32_t>& order) {
  // Insertion sort: near-linear on the nearly sorted order left by the previous step. When the order is
  // far from sorted (the first step, many new proxies, a teleport) it would go quadratic, so past a
  // budget of moves it hands over to a full sort. Both orders are total (ties by fixture index in the
  // full sort, by the previous order in insertion sort), so the result depends only on the data.
  const size_t n = order.size();
  size_t budget = 8 * n + 64;
  for (size_t i = 1; i < n; ++i) {
    const uint32_t f = order[i];
    const double x = proxies_[f].box.min.x;
    size_t j = i;
    while (j > 0 && proxies_[order[j - 1]].box.min.x > x) {
      order[j] = order[j - 1];
      --j;
    }
    order[j] = f;
    if (i - j > budget) {
      std::sort(order.begin(), order.end(), [this](uint32_t a, uint32_t b) {
        const double xa = proxies_[a].box.min.x, xb = proxies_[b].box.min.x;
        return xa < xb || (xa == xb && a < b);
      });
      return;
    }
    budget -= i - j;
  }
}

void BroadPhase::splitIntoBands(bool withSensors) {
  // Band height: twice the height of the lowest quarter of the moving bodies' boxes (sensors do not
  // count). Static walls can be long and say nothing about how crowded the moving ones are. At most 4096
  // bands, and one when little moves. The quarter is taken from a sample of about 512 boxes, every
  // stride-th in x order (which depends only on the data), so that choosing the bands stays a small
  // part of a large sweep.
  // For the sensor sweep, when many sensors move, the band height is the height of the lowest quarter
  // of the moving sensors' boxes instead: a sight circle is many times a body's height, and in bands
  // cut for the bodies each circle would be listed in a dozen of them (most of the sweep's work, with
  // a crowd's sensors), while what it is swept against has been filtered down to what it can sense.
  double low = 0, high = 0;
  bool first = true;
  heights_.clear();
  sensorHeights_.clear();
  size_t movingSeen = 0, sensorsSeen = 0;
  // Each proxy is read once, in x order, into `entries`; the bands are then filled from that copy, not
  // by a second pass of jumps through proxies_ by fixture index (a cache miss each in a large world).
  auto measure = [&](const std::vector<uint32_t>& order, std::vector<double>& sample, size_t& seen,
                     std::vector<BandEntry>& entries) {
    const size_t stride = std::max<size_t>(1, order.size() / 512);
    entries.clear();
    for (uint32_t f : order) {
      const Proxy& p = proxies_[f];
      entries.push_back({p.box, f, p.moving, p.sensor, p.category, p.mask});
      const Box& b = p.box;
      if (first) {
        low = b.min.y;
        high = b.max.y;
        first = false;
      }
      low = std::min(low, b.min.y);
      high = std::max(high, b.max.y);
      if (p.moving && seen++ % stride == 0) sample.push_back(b.max.y - b.min.y);
    }
  };
  measure(order_, heights_, movingSeen, entries_);
  if (withSensors) measure(sensorOrder_, sensorHeights_, sensorsSeen, sensorEntries_);
  bandCount_ = 1;
  bandOrigin_ = low;
  inverseBandHeight_ = 0;
  const bool bySensors = sensorsSeen >= 64;
  std::vector<double>& sample = bySensors ? sensorHeights_ : heights_;
  if (movingSeen >= 64 || bySensors) {
    auto quarter = sample.begin() + static_cast<std::ptrdiff_t>(sample.size() / 4);
    std::nth_element(sample.begin(), quarter, sample.end());
    const double bandHeight = (bySensors ? 1 : 2) * *quarter;
    const double count = bandHeight > 0 ? (high - low) / bandHeight : 1;
    if (count > 1 && count < 1e9) {
      bandCount_ = static_cast<uint32_t>(std::min(count, 4096.0)) + 1;
      inverseBandHeight_ = static_cast<double>(bandCount_ - 1) / (high - low);
    }
  }
  if (bands_.size() < bandCount_) bands_.resize(bandCount_);
  if (sensorBands_.size() < bandCount_) sensorBands_.resize(bandCount_);
  for (uint32_t b = 0; b < bandCount_; ++b) {
    bands_[b].clear();
    sensorBands_[b].clear();
  }
  for (const BandEntry& e : entries_) {
    const uint32_t last = bandOf(e.box.max.y);
    for (uint32_t b = bandOf(e.box.min.y); b <= last; ++b) bands_[b].push_back(e);
  }
  if (!withSensors) return;
  for (const BandEntry& e : sensorEntries_) {
    const uint32_t last = bandOf(e.box.max.y);
    for (uint32_t b = bandOf(e.box.min.y); b <= last; ++b) sensorBands_[b].push_back(e);
  }
}

void BroadPhase::buildQueryBands() {
  if (queryBands_.size() < bandCount_) queryBands_.resize(bandCount_);
  if (grownBands_.size() < bandCount_) grownBands_.resize(bandCount_);
  // Wide: more than four times the width of the narrowest quarter of the moving boxes (from a sample,
  // as for the band height).
  std::vector<double>& widths = heights_;
  widths.clear();
  const size_t stride = std::max<size_t>(1, order_.size() / 512);
  size_t movingSeen = 0;
  for (uint32_t f : order_) {
    const Proxy& p = proxies_[f];
    if (p.moving && movingSeen++ % stride == 0) widths.push_back(p.box.max.x - p.box.min.x);
  }
  wideThreshold_ = std::numeric_limits<double>::infinity();
  if (movingSeen >= 64 && !widths.empty()) {
    auto quarter = widths.begin() + static_cast<std::ptrdiff_t>(widths.size() / 4);
    std::nth_element(widths.begin(), quarter, widths.end());
    if (*quarter > 0) wideThreshold_ = 4 * *quarter;
  }
  queryBandsReady_ = true;
}

void BroadPhase::buildQueryBand(uint32_t band) {
  QueryBand& qb = queryBands_[band];
  qb.moving.clear();
  qb.fixed.clear();
  qb.wide.clear();
  qb.movingWidth = 0;
  qb.wideWidth = 0;
  for (const BandEntry& e : bands_[band]) {
    if (e.sensor) continue;
    const double width = e.box.max.x - e.box.min.x;
    if (!e.moving) {
      qb.fixed.push_back({e.box.min.x, e.fixture});
    } else if (width > wideThreshold_) {
      qb.wide.push_back({e.box.min.x, e.fixture});
      qb.wideWidth = std::max(qb.wideWidth, width);
    } else {
      qb.moving.push_back({e.box.min.x, e.fixture});
      qb.movingWidth = std::max(qb.movingWidth, width);
    }
  }
  qb.builtSweep = sweep_;
}

void BroadPhase::grow(uint32_t fixture, const Box& grown) {
  // Listed, from now until the next sweep, in every band the grown box reaches; its entry in the sorted
  // lists stays where the sweep put it (a query may meet it twice: the stamp reports it once).
  Proxy& p = proxies_[fixture];
  p.box = grown;
  if (grownBands_.size() < bandCount_) grownBands_.resize(bandCount_);
  const uint32_t low = bandOf(grown.min.y), high = bandOf(grown.max.y);
  // A body growing again and again within a step (a disk rattling in a narrowing gap) is listed in each
  // band once: the box only grows, so only bands beyond those already listed are new.
  const bool listed = p.grownSweep == sweep_;
  for (uint32_t band = low; band <= high; ++band) {
    if (listed && band >= p.grownLow && band <= p.grownHigh) continue;
    grownBands_[band].push_back(fixture);
  }
  p.grownLow = listed ? std::min(p.grownLow, low) : low;
  p.grownHigh = listed ? std::max(p.grownHigh, high) : high;
  p.grownSweep = sweep_;
}

}  // namespace rattle::detail
