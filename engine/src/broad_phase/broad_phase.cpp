#include "broad_phase/broad_phase.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/out_of_memory.h"

namespace rattle::detail {

void BroadPhase::add(uint32_t fixture, const Box& box, bool moving, bool sensor, uint32_t category, uint32_t mask) {
  if (proxies_.size() <= fixture) proxies_.resize(fixture + 1);
  if (reach_.size() < proxies_.size()) reach_.resize(proxies_.size());
  if (!sensor) noteChange();
  Proxy& p = proxies_[fixture];
  if (p.escaped) {
    escaped_.erase(std::find(escaped_.begin(), escaped_.end(), fixture));
  }
  if (!p.present && p.listed) --removed_;  // removed and added again before a sort: listed once
  const bool listed = p.listed;
  if (listed && p.sensor != sensor) ++misfiled_;  // in the other list until the next sort moves it
  p = Proxy{box, moving, true, true, sensor, false, category, mask, p.stamp, kNoTag};
  if (!listed) {
    if (sensor) {
      sensorOrder_.push_back(fixture);
    } else {
      // A new proxy's band is not known yet: placed last, the next sort finds its place.
      own_.push_back({box, fixture, bandCount_ - 1, category, mask, moving, false, kNoTag});
      order_.push_back(fixture);
    }
  }
}

void BroadPhase::reserveFor(uint32_t fixture, bool sensor) {
  if (proxies_.size() <= fixture) proxies_.resize(fixture + 1);
  if (reach_.size() < proxies_.size()) reach_.resize(proxies_.size());
  if (proxies_[fixture].listed) return;
  if (sensor) {
    roomForOneMore(sensorOrder_);
  } else {
    roomForOneMore(own_);
    roomForOneMore(order_);
  }
}

void BroadPhase::forgetStep() {
  for (uint32_t f : escaped_) proxies_[f].escaped = false;
  escaped_.clear();
  forgetGrowth();
  noteChange();
}

void BroadPhase::remove(uint32_t fixture) {
  Proxy& p = proxies_[fixture];
  if (!p.present) return;
  p.present = false;
  if (!p.sensor) noteChange();
  ++removed_;
}

void BroadPhase::compact() {
  if (removed_ == 0 && misfiled_ == 0) return;
  // Every listed proxy is in own_ or in sensorOrder_ (and, not a sensor, in order_ too); a reused index
  // may sit in the list of the other kind.
  LargeArray<BandEntry> keptKeys;
  std::vector<uint32_t> kept, keptSensors, nowOthers;
  for (const BandEntry& k : own_) {
    Proxy& p = proxies_[k.fixture];
    if (!p.present) {
      p.listed = false;
    } else if (p.sensor) {
      keptSensors.push_back(k.fixture);
    } else {
      keptKeys.push_back(k);
    }
  }
  for (uint32_t f : sensorOrder_) {
    Proxy& p = proxies_[f];
    if (!p.present) {
      p.listed = false;
    } else if (p.sensor) {
      keptSensors.push_back(f);
    } else {
      nowOthers.push_back(f);
    }
  }
  for (uint32_t f : order_) {
    if (proxies_[f].present && !proxies_[f].sensor) kept.push_back(f);
  }
  for (uint32_t f : nowOthers) {
    const Proxy& p = proxies_[f];
    keptKeys.push_back({p.box, f, bandCount_ - 1, p.category, p.mask, p.moving, false, p.tag});
    kept.push_back(f);
  }
  own_ = std::move(keptKeys);
  order_ = std::move(kept);
  sensorOrder_ = std::move(keptSensors);
  removed_ = 0;
  misfiled_ = 0;
}

namespace {

// Bands of about `height` over [low, high]: how many (at most 4097) and 1 / their height; one band when
// the height is unknown (0) or the span holds less than one.
struct BandCut {
  uint32_t count = 1;
  double inverse = 0;
};
BandCut bandsFor(double low, double high, double height) {
  BandCut cut;
  if (!(height > 0)) return cut;
  const double bands = (high - low) / height;
  if (bands > 1 && bands < 1e9) {
    cut.count = static_cast<uint32_t>(std::min(bands, 4096.0)) + 1;
    cut.inverse = static_cast<double>(cut.count - 1) / (high - low);
  }
  return cut;
}

// The lowest quarter of a sample (reorders it): a typical size that a few large or fast boxes do not set.
double lowestQuarter(std::vector<double>& v) {
  auto quarter = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 4);
  std::nth_element(v.begin(), quarter, v.end());
  return *quarter;
}

// Insertion sort of a[0, n) by `less`: near-linear on the nearly sorted order left by the previous step,
// ties kept in their previous order. Far from sorted (many new proxies, a teleport) it would go quadratic,
// so past a budget of 8n + 64 moves it stops and returns false, and the caller sorts fully (a total order,
// ties by fixture index): either way the result depends only on the data.
template <class T, class Less>
bool insertionSortWithinBudget(T* a, size_t n, Less less) {
  size_t budget = 8 * n + 64;
  for (size_t i = 1; i < n; ++i) {
    if (!less(a[i], a[i - 1])) continue;
    const T e = a[i];
    size_t j = i;
    while (j > 0 && less(e, a[j - 1])) {
      a[j] = a[j - 1];
      --j;
    }
    a[j] = e;
    if (i - j > budget) return false;
    budget -= i - j;
  }
  return true;
}

}  // namespace

bool BroadPhase::cutBands(double low, double high, double height) {
  // The cut this step's boxes call for: bands twice the typical height (`height`) over [low, high].
  const auto [count, inverse] = bandsFor(low, high, height);
  // Kept while it still fits: a new cut re-sorts every proxy, so the bands are cut again only when the
  // world has grown well past them or the typical height is off by more than a factor of two. Any cut
  // finds the same pairs; this only decides how fast.
  if (bandHeight_ > 0) {
    const double span = bandCount_ * bandHeight_;
    const bool outgrown = low < bandOrigin_ - 0.25 * span || high > bandOrigin_ + 1.25 * span;
    const double wanted = count > 1 ? 1 / inverse : 0;
    const bool offHeight = wanted > 0 && (wanted < 0.5 * bandHeight_ || wanted > 2 * bandHeight_);
    if (!outgrown && !offHeight) return false;
  } else if (count == 1) {
    return false;
  }
  bandCount_ = count;
  lastBand_ = count - 1;
  bandOrigin_ = low;
  inverseBandHeight_ = inverse;
  bandHeight_ = count > 1 ? 1 / inverse : 0;
  return true;
}

void BroadPhase::sortByBand(double margin) {
  compact();
  // Read every proxy once, in the last sweep's order, with a sample of about 512 moving boxes (every
  // stride-th, which depends only on the data) for the typical height and width.
  double low = 0, high = 0;
  const size_t n = own_.size();
  // The stride from the last sweep's count of moving boxes (most boxes may be static walls).
  const size_t stride = std::max<size_t>(1, (movingCount_ > 0 ? movingCount_ : n) / 512);
  heightsScratch_.clear();
  widthsScratch_.clear();
  size_t untilSample = 1;  // the first moving box is sampled, then every stride-th
  size_t moving = 0;
  size_t crossed = 0;  // entries whose home band changed
  for (size_t i = 0; i < n; ++i) {
    BandEntry& e = own_[i];
    const Proxy& p = proxies_[e.fixture];
    e.box = p.moving ? Box{p.box.min - Vec2{margin, margin}, p.box.max + Vec2{margin, margin}} : p.box;
    reach_[e.fixture] = e.box;
    const uint32_t band = bandOf(e.box.min.y);
    e.crossed = band != e.band;
    crossed += e.crossed ? 1 : 0;
    e.band = band;
    e.category = p.category;
    e.mask = p.mask;
    e.moving = p.moving;
    e.tag = p.tag;
    if (i == 0) {
      low = e.box.min.y;
      high = e.box.max.y;
    }
    low = std::min(low, e.box.min.y);
    high = std::max(high, e.box.max.y);
    moving += p.moving ? 1 : 0;
    if (p.moving && --untilSample == 0) {
      untilSample = stride;
      heightsScratch_.push_back(p.box.max.y - p.box.min.y);
      widthsScratch_.push_back(p.box.max.x - p.box.min.x);
    }
  }
  movingCount_ = moving;
  // Typical: the lowest quarter of the moving boxes (static walls are left out, they can be long).
  const bool sampled = moving >= 64;
  typicalHeight_ = sampled ? lowestQuarter(heightsScratch_) : 0;
  const double height = sampled ? 2 * typicalHeight_ + 2 * margin : 0;
  wideThreshold_ = std::numeric_limits<double>::infinity();
  if (sampled) {
    const double w = lowestQuarter(widthsScratch_);
    if (w > 0) wideThreshold_ = 4 * w;
  }
  // The order of a full sort: total, ties by fixture index.
  auto before = [](const BandEntry& a, const BandEntry& b) {
    if (a.band != b.band) return a.band < b.band;
    return a.box.min.x < b.box.min.x || (a.box.min.x == b.box.min.x && a.fixture < b.fixture);
  };
  auto fullSort = [&] { std::sort(own_.begin(), own_.end(), before); };
  if (cutBands(low, high, height)) {
    for (BandEntry& e : own_) e.band = bandOf(e.box.min.y);
    fullSort();
    return;
  }
  // An entry that changed band must move past about a band's worth of entries, so insertion sort costs
  // about n / bands moves for each. When that would pass the budget below (a large world whose boxes
  // drifted for several steps since the last sort), the entries that kept their band (nearly sorted)
  // and those that changed it (few) are sorted apart and merged: the full sort's order, in O(n). Only
  // with the pair cache on, whose callers do not depend on the order of the pairs: where the old path
  // would have sorted within its budget, ties may come out in another order (island solves under
  // gravity read pairs in sweep order, and the 2,000-disk pour test fails with this order).
  if (pairCache_ && bandCount_ > 1 && crossed > 4 * static_cast<size_t>(bandCount_)) {
    crossedScratch_.clear();
    crossedScratch_.reserve(crossed);  // own_ is compacted in place below: no push may fail half way
    size_t kept = 0;
    for (size_t i = 0; i < n; ++i) {
      if (own_[i].crossed) {
        crossedScratch_.push_back(own_[i]);
      } else {
        own_[kept++] = own_[i];
      }
    }
    if (!insertionSortWithinBudget(own_.data(), kept, before)) {
      for (const BandEntry& c : crossedScratch_) own_[kept++] = c;
      fullSort();
      return;
    }
    std::sort(crossedScratch_.begin(), crossedScratch_.end(), before);
    // Merged from the back, in place: the kept entries fill own_ from the front.
    size_t i = kept, j = crossedScratch_.size(), k = n;
    while (j > 0) {
      if (i > 0 && before(crossedScratch_[j - 1], own_[i - 1])) {
        own_[--k] = own_[--i];
      } else {
        own_[--k] = crossedScratch_[--j];
      }
    }
    return;
  }
  // By (band, lower x edge) alone: ties keep the previous step's order, which is what island solves
  // under gravity have always read.
  auto byBandAndX = [](const BandEntry& a, const BandEntry& b) {
    return a.band < b.band || (a.band == b.band && a.box.min.x < b.box.min.x);
  };
  if (!insertionSortWithinBudget(own_.data(), n, byBandAndX)) fullSort();
}

void BroadPhase::sweepReaches() {
  // The margin from the typical height the last sort sampled (none at the first).
  sortByBand(marginFraction_ * typicalHeight_);
  splitIntoBands();
  // Every candidate is written and the count moves on only for a pair (sweepBands): room for a quarter
  // more than the last sweep kept, grown when a sweep finds more.
  size_t kept = 0;
  cachedPairs_.resize(std::max<size_t>(1024, cachedPairs_.size() + cachedPairs_.size() / 4));
  sweepBands([&](const BandEntry& a, const BandEntry& b, bool meets) {
    if (kept == cachedPairs_.size()) cachedPairs_.resize(2 * kept);
    cachedPairs_[kept] = {a.fixture, b.fixture};
    kept += meets ? 1 : 0;
  });
  cachedPairs_.resize(kept);
  // The pairs by fixture (a counting sort), for queryAround.
  partnerStart_.assign(proxies_.size() + 1, 0);
  for (const CachedPair& c : cachedPairs_) {
    ++partnerStart_[c.a + 1];
    ++partnerStart_[c.b + 1];
  }
  for (size_t f = 0; f < proxies_.size(); ++f) partnerStart_[f + 1] += partnerStart_[f];
  partners_.resize(2 * cachedPairs_.size());
  for (const CachedPair& c : cachedPairs_) {
    partners_[partnerStart_[c.a]++] = c.b;
    partners_[partnerStart_[c.b]++] = c.a;
  }
  // The fill moved each start to the next fixture's: move them back.
  for (size_t f = proxies_.size(); f > 0; --f) partnerStart_[f] = partnerStart_[f - 1];
  partnerStart_[0] = 0;
  // A sweep stopped at its budget kept only some of the pairs.
  cacheValid_ = !overflowed_;
}

void BroadPhase::splitIntoBands() {
  bandStart_.assign(bandCount_ + 1, 0);
  if (spill_.size() < bandCount_) spill_.resize(bandCount_);
  if (wide_.size() < bandCount_) wide_.resize(bandCount_);
  if (grownBands_.size() < bandCount_) grownBands_.resize(bandCount_);
  if (tall_.size() < bandCount_) tall_.resize(bandCount_);
  for (uint32_t b = 0; b < bandCount_; ++b) {
    spill_[b].clear();
    tall_[b].clear();
    wide_[b].clear();
  }
  const size_t n = own_.size();
  ownKeys_.clear();
  ownKeyStart_.assign(bandCount_ + 1, 0);
  ownReach_.assign(bandCount_, 0);
  spillReach_.assign(bandCount_, 0);
  wholeReach_.assign(bandCount_, 0);
  uint32_t band = 0;
  for (size_t i = 0; i < n; ++i) {
    const BandEntry& e = own_[i];
    while (band < e.band) {
      bandStart_[++band] = static_cast<uint32_t>(i);
      ownKeyStart_[band] = static_cast<uint32_t>(ownKeys_.size());
    }
    if ((i - bandStart_[band]) % kKeyStride == 0) ownKeys_.push_back(e.box.min.x);
    const double width = e.box.max.x - e.box.min.x;
    const bool wide = width > wideThreshold_;
    wholeReach_[e.band] = std::max(wholeReach_[e.band], width);
    if (wide) {
      wide_[e.band].push_back({e.box.min.x, e.fixture});
    } else {
      ownReach_[e.band] = std::max(ownReach_[e.band], width);
    }
    const uint32_t top = bandOf(e.box.max.y);
    if (top == e.band + 1) {
      // Into the band above only: appended in x order, as the band's own are read.
      spill_[top].push_back(e);
      if (wide) {
        wide_[top].push_back({e.box.min.x, e.fixture});
      } else {
        spillReach_[top] = std::max(spillReach_[top], width);
      }
    } else {
      for (uint32_t b = e.band + 1; b <= top; ++b) tall_[b].push_back(e);
    }
  }
  while (band < bandCount_) {
    bandStart_[++band] = static_cast<uint32_t>(n);
    ownKeyStart_[band] = static_cast<uint32_t>(ownKeys_.size());
  }
  spillKeys_.clear();
  spillKeyStart_.assign(bandCount_ + 1, 0);
  for (uint32_t b = 0; b < bandCount_; ++b) {
    spillKeyStart_[b] = static_cast<uint32_t>(spillKeys_.size());
    const std::vector<BandEntry>& spill = spill_[b];
    for (size_t i = 0; i < spill.size(); i += kKeyStride) spillKeys_.push_back(spill[i].box.min.x);
  }
  spillKeyStart_[bandCount_] = static_cast<uint32_t>(spillKeys_.size());
}

void BroadPhase::sortList(std::vector<uint32_t>& order) {
  // By lower x edge, with the same budget and fallback as sortByBand.
  auto byX = [this](uint32_t a, uint32_t b) { return proxies_[a].box.min.x < proxies_[b].box.min.x; };
  if (insertionSortWithinBudget(order.data(), order.size(), byX)) return;
  std::sort(order.begin(), order.end(), [this](uint32_t a, uint32_t b) {
    const double xa = proxies_[a].box.min.x, xb = proxies_[b].box.min.x;
    return xa < xb || (xa == xb && a < b);
  });
}

void BroadPhase::splitIntoSensorBands() {
  // Band height: the height of the lowest quarter of the moving sensors' boxes when many sensors move
  // (a sight circle is many times a body's height, and in bands cut for the bodies each circle would be
  // listed in a dozen of them, while what it is swept against has been filtered down to what it can
  // sense), else twice that of the moving others. At most 4096 bands, and one when little moves. The
  // quarter is taken from a sample of about 512 boxes, every stride-th in x order.
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
      entries.push_back({p.box, f, 0, p.category, p.mask, p.moving, p.sensor, kNoTag});
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
  measure(sensorOrder_, sensorHeights_, sensorsSeen, sensorEntries_);
  sensorBandCount_ = 1;
  sensorBandOrigin_ = low;
  sensorInverseBandHeight_ = 0;
  const bool bySensors = sensorsSeen >= 64;
  std::vector<double>& sample = bySensors ? sensorHeights_ : heights_;
  if (movingSeen >= 64 || bySensors) {
    const BandCut cut = bandsFor(low, high, (bySensors ? 1 : 2) * lowestQuarter(sample));
    sensorBandCount_ = cut.count;
    sensorInverseBandHeight_ = cut.inverse;
  }
  if (sensorOthers_.size() < sensorBandCount_) sensorOthers_.resize(sensorBandCount_);
  if (sensorBands_.size() < sensorBandCount_) sensorBands_.resize(sensorBandCount_);
  for (uint32_t b = 0; b < sensorBandCount_; ++b) {
    sensorOthers_[b].clear();
    sensorBands_[b].clear();
  }
  for (const BandEntry& e : entries_) {
    const uint32_t last = sensorBandOf(e.box.max.y);
    for (uint32_t b = sensorBandOf(e.box.min.y); b <= last; ++b) sensorOthers_[b].push_back(e);
  }
  for (const BandEntry& e : sensorEntries_) {
    const uint32_t last = sensorBandOf(e.box.max.y);
    for (uint32_t b = sensorBandOf(e.box.min.y); b <= last; ++b) sensorBands_[b].push_back(e);
  }
}

void BroadPhase::grow(uint32_t fixture, const Box& grown) {
  // Listed, from now until the next sweep, in every band the grown box reaches; its entry in the sorted
  // lists stays where the sweep put it, with the box the sweep saw (a query may meet it twice: the stamp
  // reports it once). The box only grows, so only bands beyond those already listed are new.
  proxies_[fixture].box = grown;
  noteReach(fixture, proxies_[fixture]);
  if (grownBands_.size() < bandCount_) grownBands_.resize(bandCount_);
  if (growth_.size() <= fixture) growth_.resize(proxies_.size());
  Growth& g = growth_[fixture];
  const uint32_t low = bandOf(grown.min.y), high = bandOf(grown.max.y);
  const bool listed = g.sweep == sweep_;
  if (listed) {
    grown_[g.index].box = grown;
  } else {
    g.index = static_cast<uint32_t>(grown_.size());
    grown_.push_back({grown, fixture});
  }
  for (uint32_t band = low; band <= high; ++band) {
    if (listed && band >= g.low && band <= g.high) continue;
    grownBands_[band].push_back(g.index);
  }
  g.low = listed ? std::min(g.low, low) : low;
  g.high = listed ? std::max(g.high, high) : high;
  g.sweep = sweep_;
}

}  // namespace rattle::detail
