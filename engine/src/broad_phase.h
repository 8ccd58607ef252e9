// Private: sort-and-sweep over swept boxes.
//
// Each step every fixture of a moving body gets the box of its whole path over the step (its swept box);
// static fixtures keep their box. The proxies stay in one array sorted by the boxes' lower x edge; since
// bodies move little from one step to the next the array is nearly sorted, and insertion sort finishes it
// in close to linear time (the frame-to-frame coherence that makes sort-and-sweep fast). The sweep then
// reports every pair whose boxes overlap and of which at least one moves.
//
// Mid-step, a collision can send a body along a path that leaves the swept box the sweep saw. Its box
// then grows (never shrinks within a step) and `query` finds every proxy the grown box overlaps, using the
// current, possibly grown, boxes of the others too, so no pair is lost whichever of two bodies grew last.
// Queries use the sweep's horizontal bands, so each looks at the proxies near it, not a whole column.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "rattle/geometry.h"

namespace rattle::detail {

class BroadPhase {
 public:
  /// `sensor`: two sensors never pair (they only sense physical fixtures), so the sweep skips them.
  /// `category` and `mask`: the fixture's filter bits, so that findSensorPairs sweeps each sensor only
  /// against the fixtures it may sense.
  void add(uint32_t fixture, const Box& box, bool moving, bool sensor = false, uint32_t category = ~0u,
           uint32_t mask = ~0u);
  void setFilter(uint32_t fixture, uint32_t category, uint32_t mask) {
    proxies_[fixture].category = category;
    proxies_[fixture].mask = mask;
  }
  /// Lazy: the proxy leaves the sorted order at the next sort.
  void remove(uint32_t fixture);
  bool contains(uint32_t fixture) const { return fixture < proxies_.size() && proxies_[fixture].present; }
  const Box& box(uint32_t fixture) const { return proxies_[fixture].box; }
  void setBox(uint32_t fixture, const Box& box) { proxies_[fixture].box = box; }
  void setMoving(uint32_t fixture, bool moving) { proxies_[fixture].moving = moving; }

  /// Sorts by lower x edge and calls report(a, b) for every overlapping pair of which one moves and
  /// neither is a sensor (sensors are paired by findSensorPairs alone), and whose filter bits meet.
  /// Then prepares `query` for this step's boxes.
  template <class Report>
  void findPairs(Report&& report);

  /// The same for the pairs of a sensor and a fixture that is not one, only: within each band the
  /// sensors and the others are swept as two lists against each other, so a crowd's sight circles never
  /// look at one another; and the sensors of each filter only against the fixtures whose filter bits
  /// meet theirs, so a sight circle that senses only the other team never looks at its own team either
  /// (a packed crowd puts hundreds of friends in each one). Groups are left to the caller.
  template <class Report>
  void findSensorPairs(Report&& report);

  /// Grows a moving proxy's box mid-step (the new box must contain the old one).
  void grow(uint32_t fixture, const Box& grown);

  /// Calls found(f) once for every proxy that is not a sensor and whose current box overlaps `q`.
  template <class Found>
  void query(const Box& q, Found&& found);

 private:
  struct Proxy {
    Box box;
    bool moving = false;
    bool present = false;
    bool listed = false;   // in order_ or sensorOrder_ (a removed proxy stays listed until the next sort)
    bool sensor = false;
    uint32_t category = ~0u, mask = ~0u;  // the fixture's filter bits
    uint32_t stamp = 0;    // the last query that reported it
    uint32_t grownSweep = 0;         // the sweep in which grownLow..grownHigh were listed
    uint32_t grownLow = 0, grownHigh = 0;  // the bands whose grown lists hold it
  };
  struct Entry {
    double minX;  // lower x edge at the sweep
    uint32_t fixture;
  };
  /// Sorts the proxies that are not sensors, and the sensors too when `withSensors`: the collision
  /// sweep never looks at sensors, and a crowd's sight sensors are half its proxies.
  void sortByMinX(bool withSensors);
  void sortList(std::vector<uint32_t>& order);
  /// `withSensors`: false leaves the sensors out of the bands. A unit's sight circle spans several
  /// bands, so a crowd's sensors would be most of the entries that the collision sweep and the queries
  /// step over, for nothing: only findSensorPairs pairs them.
  void splitIntoBands(bool withSensors);
  void buildQueryBands();
  uint32_t bandOf(double y) const {
    const double b = (y - bandOrigin_) * inverseBandHeight_;
    return b <= 0 ? 0 : b >= bandCount_ - 1 ? bandCount_ - 1 : static_cast<uint32_t>(b);
  }

  std::vector<Proxy> proxies_;   // indexed by fixture index
  std::vector<uint32_t> order_;  // fixture indices, sorted by box.min.x at the last sweep: not sensors
  std::vector<uint32_t> sensorOrder_;  // the same for the sensors (sorted by the last sensor sweep)
  size_t removed_ = 0;           // proxies removed since the last sort (still listed)
  size_t misfiled_ = 0;          // indices reused since the last sort by a proxy of the other kind
  // Horizontal bands for the sweep: a single x sweep over a square region compares every proxy with a
  // whole column of others (O(N^1.5)); sweeping bands about two boxes tall keeps it near O(N).
  // Each entry carries a copy of its box, so the sweep reads each band's list in order instead of jumping
  // through proxies_ by fixture index (a cache miss per comparison in a large world).
  struct BandEntry {
    Box box;
    uint32_t fixture;
    bool moving;
    bool sensor;
    uint32_t category, mask;
  };
  std::vector<std::vector<BandEntry>> bands_;
  std::vector<std::vector<BandEntry>> sensorBands_;  // the sensors, when the bands were split with them
  std::vector<BandEntry> entries_, sensorEntries_;   // scratch of splitIntoBands: the proxies in x order
  std::vector<double> heights_, sensorHeights_;  // scratch of splitIntoBands
  // Scratch of findSensorPairs: per sensor filter, indices into a band's sensors and into its others.
  std::vector<std::vector<uint32_t>> sensorLists_, otherLists_;
  struct FilterBits {
    uint32_t category, mask;
  };
  std::vector<FilterBits> sensorFilters_;  // scratch of findSensorPairs: the sensors' filters in a band
  uint32_t bandCount_ = 1;
  double bandOrigin_ = 0;
  double inverseBandHeight_ = 0;
  // Queries (mid-step, after a path changed) use the same bands: in each, the moving proxies in x order
  // (found by binary search, reaching back by the widest box of their list: narrow or wide), the static
  // ones in x order (a long wall starts early: scanned from the band's start), and the proxies grown into
  // the band since the sweep (few; scanned whole). A band's lists are built at its first query of a step:
  // a step's queries touch few of the bands.
  // Moving boxes much wider than most (a unit's sight sensor beside its body) have their own lists, so
  // that the reach back of every search is not set by the widest box.
  struct QueryBand {
    std::vector<Entry> moving, fixed, wide;
    double movingWidth = 0, wideWidth = 0;  // the widest box of each moving list
    uint32_t builtSweep = 0;
  };
  void buildQueryBand(uint32_t band);
  bool queryBandsReady_ = false;  // wideThreshold_ is set for this sweep
  double wideThreshold_ = 0;
  std::vector<QueryBand> queryBands_;
  std::vector<std::vector<uint32_t>> grownBands_;
  uint32_t queryStamp_ = 0;
  uint32_t sweep_ = 1;  // counts sweeps, so that a proxy is listed in each band's grown list once
};

template <class Report>
void BroadPhase::findPairs(Report&& report) {
  sortByMinX(false);
  splitIntoBands(false);
  // Within each band the proxies are in x order already; a pair is reported only in the lowest band both
  // are in, so a pair that shares several bands is reported once.
  for (uint32_t band = 0; band < bandCount_; ++band) {
    const std::vector<BandEntry>& list = bands_[band];
    const size_t n = list.size();
    for (size_t i = 0; i < n; ++i) {
      const BandEntry& pi = list[i];
      for (size_t j = i + 1; j < n; ++j) {
        const BandEntry& pj = list[j];
        if (pj.box.min.x > pi.box.max.x) break;
        if (!pi.moving && !pj.moving) continue;
        if ((pi.category & pj.mask) == 0 || (pj.category & pi.mask) == 0) continue;
        if (pj.box.min.y > pi.box.max.y || pi.box.min.y > pj.box.max.y) continue;
        if (std::max(bandOf(pi.box.min.y), bandOf(pj.box.min.y)) != band) continue;
        report(pi.fixture, pj.fixture);
      }
    }
  }
  queryBandsReady_ = false;
  for (auto& g : grownBands_) g.clear();
  ++sweep_;
}

template <class Report>
void BroadPhase::findSensorPairs(Report&& report) {
  sortByMinX(true);
  splitIntoBands(true);
  // Past this many different sensor filters in one band, one sweep of all sensors against all others
  // costs less than a filtered sweep per filter.
  constexpr size_t kMaxFilters = 8;
  if (sensorLists_.size() < kMaxFilters) sensorLists_.resize(kMaxFilters);
  if (otherLists_.size() < kMaxFilters) otherLists_.resize(kMaxFilters);
  for (uint32_t band = 0; band < bandCount_; ++band) {
    const std::vector<BandEntry>& sensors = sensorBands_[band];
    const std::vector<BandEntry>& others = bands_[band];
    if (sensors.empty() || others.empty()) continue;
    // The sensors by filter, then each filter's list of the others it may sense.
    sensorFilters_.clear();
    bool filtered = true;
    for (uint32_t k = 0; k < sensors.size() && filtered; ++k) {
      const BandEntry& e = sensors[k];
      size_t g = 0;
      while (g < sensorFilters_.size() && (sensorFilters_[g].category != e.category || sensorFilters_[g].mask != e.mask)) ++g;
      if (g == sensorFilters_.size()) {
        if (g == kMaxFilters) {
          filtered = false;
          break;
        }
        sensorFilters_.push_back({e.category, e.mask});
        sensorLists_[g].clear();
        otherLists_[g].clear();
      }
      sensorLists_[g].push_back(k);
    }
    if (!filtered) {
      // One group: every sensor against every other.
      sensorFilters_.assign(1, FilterBits{~0u, ~0u});
      sensorLists_[0].clear();
      otherLists_[0].clear();
      for (uint32_t k = 0; k < sensors.size(); ++k) sensorLists_[0].push_back(k);
    }
    for (uint32_t k = 0; k < others.size(); ++k) {
      const BandEntry& e = others[k];
      for (size_t g = 0; g < sensorFilters_.size(); ++g) {
        const FilterBits f = sensorFilters_[g];
        if ((e.category & f.mask) != 0 && (f.category & e.mask) != 0) otherLists_[g].push_back(k);
      }
    }
    // Two sorted lists swept against each other: whichever next box starts further left scans the other
    // list for the boxes that start before it ends.
    auto test = [&](const BandEntry& pi, const BandEntry& pj) {
      if (!pi.moving && !pj.moving) return;
      if (pj.box.min.y > pi.box.max.y || pi.box.min.y > pj.box.max.y) return;
      if (std::max(bandOf(pi.box.min.y), bandOf(pj.box.min.y)) != band) return;
      report(pi.fixture, pj.fixture);
    };
    for (size_t g = 0; g < sensorFilters_.size(); ++g) {
      const std::vector<uint32_t>& sl = sensorLists_[g];
      const std::vector<uint32_t>& ol = otherLists_[g];
      size_t i = 0, j = 0;
      const size_t ns = sl.size(), no = ol.size();
      while (i < ns && j < no) {
        const BandEntry& s = sensors[sl[i]];
        const BandEntry& o = others[ol[j]];
        if (s.box.min.x <= o.box.min.x) {
          const double reach = s.box.max.x;
          for (size_t k = j; k < no && others[ol[k]].box.min.x <= reach; ++k) test(s, others[ol[k]]);
          ++i;
        } else {
          const double reach = o.box.max.x;
          for (size_t k = i; k < ns && sensors[sl[k]].box.min.x <= reach; ++k) test(sensors[sl[k]], o);
          ++j;
        }
      }
    }
  }
  queryBandsReady_ = false;
  for (auto& g : grownBands_) g.clear();
  ++sweep_;
}

template <class Found>
void BroadPhase::query(const Box& q, Found&& found) {
  if (!queryBandsReady_) buildQueryBands();
  if (++queryStamp_ == 0) {
    for (Proxy& p : proxies_) p.stamp = 0;
    queryStamp_ = 1;
  }
  auto visit = [&](uint32_t f) {
    Proxy& p = proxies_[f];
    if (p.stamp == queryStamp_ || !p.box.overlaps(q)) return;
    p.stamp = queryStamp_;
    found(f);
  };
  const uint32_t last = bandOf(q.max.y);
  for (uint32_t band = bandOf(q.min.y); band <= last; ++band) {
    if (queryBands_[band].builtSweep != sweep_) buildQueryBand(band);
    const QueryBand& qb = queryBands_[band];
    auto it = std::lower_bound(qb.moving.begin(), qb.moving.end(), q.min.x - qb.movingWidth,
                               [](const Entry& e, double x) { return e.minX < x; });
    for (; it != qb.moving.end() && it->minX <= q.max.x; ++it) visit(it->fixture);
    it = std::lower_bound(qb.wide.begin(), qb.wide.end(), q.min.x - qb.wideWidth,
                          [](const Entry& e, double x) { return e.minX < x; });
    for (; it != qb.wide.end() && it->minX <= q.max.x; ++it) visit(it->fixture);
    for (const Entry& e : qb.fixed) {
      if (e.minX > q.max.x) break;
      visit(e.fixture);
    }
    for (uint32_t f : grownBands_[band]) visit(f);
  }
}

}  // namespace rattle::detail
