// Private: sort-and-sweep over swept boxes.
//
// Each step every fixture of a moving body gets the box of its whole path over the step (its swept box);
// static fixtures keep their box. The sweep reports every pair whose boxes overlap and of which at least
// one moves.
//
// A single x sweep over a square region compares every proxy with a whole column of others (O(N^1.5)),
// so the plane is cut into horizontal bands about two boxes tall and each band is swept on its own. A
// proxy belongs to the band of its lower edge (its home band) and reaches into the bands above it that
// its box spans. The proxies stay in one array sorted by (home band, lower x edge), kept from step to
// step: since bodies move little from one step to the next the array is nearly sorted, and insertion sort
// finishes it in close to linear time (the frame-to-frame coherence that makes sort-and-sweep fast). The
// bands are kept too, and cut again only when the boxes' heights or the world's extent have changed
// a lot, so that the order stays nearly sorted. Sorted this way, a sweep walks the proxies one band
// after another instead of in x order across the whole world: bodies created row by row (as a game
// places them, as a gas starts from a lattice) are read near where they lie in memory, not one cache
// miss apart, which is what a world of a million bodies pays for most.
//
// Mid-step, a collision can send a body along a path that leaves the swept box the sweep saw. Its box
// then grows (never shrinks within a step) and `query` finds every proxy the grown box overlaps, using the
// current, possibly grown, boxes of the others too, so no pair is lost whichever of two bodies grew last.
// Queries use the sweep's bands, so each looks at the proxies near it, not a whole column.
//
// Without gravity the hybrid step lets the broad phase keep its pairs from step to step (the pair cache,
// at the end of the class): a sweep widens each moving box by a margin, and while the boxes stay inside
// those reaches a step only filters the kept pairs, as molecular dynamics does with a Verlet list.
//
// Sensors are swept apart from the collisions, after the step (findSensorPairs), in bands of their own
// over an x order of their own: a crowd's sight circles are many times a body's height.
#pragma once

#include <algorithm>
#include <cstdint>
#include <new>
#include <type_traits>
#include <vector>

#include "common/large_array.h"
#include "rattle/geometry.h"

namespace rattle::detail {

class BroadPhase {
 public:
  /// `sensor`: two sensors never pair (they only sense physical fixtures), so the sweep skips them.
  /// `category` and `mask`: the fixture's filter bits, so that findSensorPairs sweeps each sensor only
  /// against the fixtures it may sense.
  void add(uint32_t fixture, const Box& box, bool moving, bool sensor = false, uint32_t category = ~0u,
           uint32_t mask = ~0u);
  /// Makes the room add(fixture, ..., sensor, ...) takes, so that the add that follows cannot fail.
  void reserveFor(uint32_t fixture, bool sensor);
  void setFilter(uint32_t fixture, uint32_t category, uint32_t mask) {
    proxies_[fixture].category = category;
    proxies_[fixture].mask = mask;
    noteChange();
  }
  /// Lazy: the proxy leaves the sorted order at the next sort.
  void remove(uint32_t fixture);
  bool contains(uint32_t fixture) const { return fixture < proxies_.size() && proxies_[fixture].present; }
  const Box& box(uint32_t fixture) const { return proxies_[fixture].box; }
  /// Asks for what setMoving, setBox and setTag will read and write of a proxy (a prefetch; changes
  /// nothing).
  void prefetch(uint32_t fixture) const {
    if (fixture >= proxies_.size()) return;
    __builtin_prefetch(&proxies_[fixture], 1);
    if (fixture < reach_.size()) __builtin_prefetch(&reach_[fixture]);
  }
  void setBox(uint32_t fixture, const Box& box) {
    Proxy& p = proxies_[fixture];
    p.box = box;
    if (!p.sensor) noteReach(fixture, p);
  }
  void setMoving(uint32_t fixture, bool moving) {
    Proxy& p = proxies_[fixture];
    if (p.moving != moving && !p.sensor) noteChange();
    p.moving = moving;
  }
  /// A tag that findPairs hands back with the proxy's pairs (the caller's; kept until set again;
  /// kNoTag unless set).
  void setTag(uint32_t fixture, uint32_t tag) {
    Proxy& p = proxies_[fixture];
    if (p.tag != tag) noteChange();
    p.tag = tag;
  }
  /// Whether findPairs may keep pairs from one step to the next (the pair cache, below; off unless set).
  /// It reports the same pairs either way, in another order: on only for callers whose results do not
  /// depend on the order (the hybrid step without gravity, where no island solve reads its pairs).
  void setPairCache(bool on) {
    if (on != pairCache_) cacheValid_ = false;
    pairCache_ = on;
  }
  /// The margin of the pair cache, as a fraction of the typical moving box's height: how far a box may
  /// move from where the last sweep saw it before it is looked up on its own. Any margin finds the same
  /// pairs; this only decides how fast. 0.2 measured best on the bench's gas (10^4 disks, dt 1/60):
  /// wider reaches keep more pairs that never meet, narrower ones are left sooner.
  static constexpr double kDefaultMargin = 0.2;
  void setMargin(double fraction) { marginFraction_ = fraction; }
  /// Whether the last findPairs took its pairs from the cache (no sort, no sweep).
  bool lastFromCache() const { return lastFromCache_; }
  /// At most this many pairs of boxes overlapping in x are tested by one sweep (plus one band row's).
  /// Bodies piled on one point make every pair such a pair: a sweep past the budget stops, reports
  /// only what it found, and says so (overflowed()), so a degenerate world costs a bounded step.
  void setPairTestBudget(size_t tests) { pairTestBudget_ = tests; }
  /// The last findPairs stopped at the pair-test budget: its pairs are incomplete.
  bool overflowed() const { return overflowed_; }
  static constexpr uint32_t kNoTag = 0xFFFFFFFFu;

  /// Sorts and calls report(a, b) (or report(a, b, tagA, tagB), with what setTag last set) for every
  /// overlapping pair of which one moves and neither is a sensor (sensors are paired by findSensorPairs
  /// alone), and whose filter bits meet. Then prepares `query` for this step's boxes.
  template <class Report>
  void findPairs(Report&& report) {
    findPairs(report, [](uint32_t, uint32_t, uint32_t, uint32_t) {});
  }
  /// The same, and where the order of the pairs is known before they are reported (the pair cache's
  /// steps), ahead(a, b, tagA, tagB) is called with each pair kReportAhead pairs before report gets it,
  /// so that the caller can ask for what it will read then (a prefetch). It must change nothing.
  template <class Report, class Ahead>
  void findPairs(Report&& report, Ahead&& ahead);
  static constexpr size_t kReportAhead = 16;

  /// The same for the pairs of a sensor and a fixture that is not one, only: within each band the
  /// sensors and the others are swept as two lists against each other, so a crowd's sight circles never
  /// look at one another; and the sensors of each filter only against the fixtures whose filter bits
  /// meet theirs, so a sight circle that senses only the other team never looks at its own team either
  /// (a packed crowd puts hundreds of friends in each one). Groups are left to the caller.
  template <class Report>
  void findSensorPairs(Report&& report);

  /// A step stopped part way (memory ran out): everything kept from the sweeps (the pairs, the growth,
  /// the escaped list) is void, and the next findPairs sorts and sweeps afresh. The proxies and the
  /// sorted lists stay whole whatever allocation failed, so nothing here allocates.
  void forgetStep();

  /// Grows a moving proxy's box mid-step (the new box must contain the old one).
  void grow(uint32_t fixture, const Box& grown);

  /// Calls found(f) once for every proxy that is not a sensor and whose current box overlaps `q`.
  template <class Found>
  void query(const Box& q, Found&& found);

  /// The same for the box of a moving proxy `fixture` after it has grown, for the caller that only wants
  /// the proxies whose filter bits meet its own: those are all found, others may be left out. While the
  /// box is within the fixture's reach, its kept pairs and the grown lists hold every answer, and they
  /// are read instead of the bands.
  template <class Found>
  void queryAround(uint32_t fixture, Found&& found);

 private:
  struct Proxy {
    Box box;
    bool moving = false;
    bool present = false;
    bool listed = false;   // in own_ or sensorOrder_ (a removed proxy stays listed until the next sort)
    bool sensor = false;
    bool escaped = false;  // in escaped_: its box left its reach since the last sweep
    uint32_t category = ~0u, mask = ~0u;  // the fixture's filter bits
    uint32_t stamp = 0;    // the last query that reported it
    uint32_t tag = kNoTag;
  };
  /// A new stamp for a query: a proxy is reported once per query, by the stamp it carries.
  void startQuery() {
    if (++queryStamp_ == 0) {
      for (Proxy& p : proxies_) p.stamp = 0;
      queryStamp_ = 1;
    }
  }
  /// Reports proxy f to a query of box q, unless it does not overlap q or the query has reported it.
  template <class Found>
  void visitOnce(uint32_t f, const Box& q, Found& found) {
    Proxy& p = proxies_[f];
    if (p.stamp == queryStamp_ || !p.box.overlaps(q)) return;
    p.stamp = queryStamp_;
    found(f);
  }
  /// A step's growth is over: the grown lists are emptied and growth_ entries go stale.
  void forgetGrowth() {
    for (auto& g : grownBands_) g.clear();
    grown_.clear();
    ++sweep_;
  }
  /// Something the sweep decided by changed (a proxy added or removed, a filter, a moving flag, a tag):
  /// the kept pairs are void.
  void noteChange() {
    cacheValid_ = false;
    changed_ = true;
  }
  /// Lists the proxy as escaped when its box has left the reach of the last sweep.
  void noteReach(uint32_t fixture, Proxy& p) {
    if (!cacheValid_ || p.escaped || reach_[fixture].contains(p.box)) return;
    try {
      escaped_.push_back(fixture);
    } catch (const std::bad_alloc&) {
      noteChange();  // with the kept pairs void, nothing needs the list: it is swept afresh
      return;
    }
    p.escaped = true;
  }
  /// Calls pair(a, b, meets) for every pair of entries whose boxes overlap in x, band by band (the sweep
  /// proper); `meets`: they overlap in y too, one of them moves and their filter bits meet.
  template <class Pair>
  void sweepBands(Pair&& pair);
  /// Sorts, and keeps every pair of overlapping reaches in cachedPairs_ (findPairs, when the cache
  /// cannot serve).
  void sweepReaches();
  struct Entry {
    double minX;  // lower x edge at the sweep
    uint32_t fixture;
  };
  // A proxy grown since the sweep, with its current box: grown_[k], listed by k in the grown lists of the
  // bands its box reaches. Its place in grown_ and those bands are kept by fixture (Growth) for this sweep,
  // so that a body growing again and again within a step (a disk rattling in a narrowing gap) is listed
  // once in each band.
  struct GrownEntry {
    Box box;
    uint32_t fixture;
  };
  struct Growth {
    uint32_t sweep = 0;  // the sweep in which the rest was set
    uint32_t index = 0;  // in grown_
    uint32_t low = 0, high = 0;  // the bands whose grown lists hold it
  };
  // A proxy as a sweep reads it: a copy of its box and bits, in the order of the sweep, so that the sweep
  // reads each band's list in order instead of jumping through proxies_ by fixture index.
  struct BandEntry {
    Box box;
    uint32_t fixture;
    uint32_t band;  // the collision sweep's: its home band (the band of its lower edge)
    uint32_t category, mask;
    bool moving;
    bool sensor;
    uint32_t tag;  // the collision sweep's only
    bool crossed = false;  // scratch of sortByBand: its home band is not the one it had at the last sort
  };
  /// Drops removed proxies from the orders and moves a reused index to the list of its kind.
  void compact();
  /// Reads every proxy into own_, cuts the bands again when they no longer fit (cutBands) and sorts own_
  /// by (home band, lower x edge).
  /// `margin` widens every moving box (the pair cache's reach; 0 for a plain sweep).
  void sortByBand(double margin);
  /// Chooses the bands for boxes spanning [low, high] whose typical height is `height` (0: unknown, one
  /// band); true when that is a new cut.
  bool cutBands(double low, double high, double height);
  /// Finds each band's range of own_, and copies each proxy into the spill or tall list of every band
  /// above its own that its box reaches; wide boxes are listed apart for queries.
  void splitIntoBands();
  uint32_t bandOf(double y) const {
    const double b = (y - bandOrigin_) * inverseBandHeight_;
    return b <= 0 ? 0 : b >= lastBand_ ? bandCount_ - 1 : static_cast<uint32_t>(b);
  }
  /// The same for the sensor sweep's bands.
  uint32_t sensorBandOf(double y) const {
    const double b = (y - sensorBandOrigin_) * sensorInverseBandHeight_;
    return b <= 0 ? 0 : b >= sensorBandCount_ - 1 ? sensorBandCount_ - 1 : static_cast<uint32_t>(b);
  }
  /// Sorts a list of fixture indices by their boxes' lower x edge (the sensor sweep's orders).
  void sortList(std::vector<uint32_t>& order);
  /// The sensor sweep's bands, cut for this sweep alone (sensorBands_, sensorOthers_).
  void splitIntoSensorBands();

  LargeArray<Proxy> proxies_;   // indexed by fixture index
  size_t removed_ = 0;           // proxies removed since the last sort (still listed)
  size_t misfiled_ = 0;          // indices reused since the last sort by a proxy of the other kind

  // The collision sweep. Band k covers y in [origin + k h, origin + (k + 1) h), the first and the last
  // reaching on to infinity; h is about twice the height of the lowest quarter of the moving boxes.
  // The proxies that are not sensors, by (home band, lower x edge): band k's are [bandStart_[k], [k + 1]).
  // Sorting the entries themselves (few move in a step) lets the sweep read them in order.
  LargeArray<BandEntry> own_;
  std::vector<uint32_t> bandStart_;
  uint32_t bandCount_ = 1;
  double lastBand_ = 0;  // bandCount_ - 1
  double bandOrigin_ = 0;
  double inverseBandHeight_ = 0;
  double bandHeight_ = 0;  // 0: one band
  std::vector<double> heightsScratch_, widthsScratch_;  // scratch of sortByBand: a sample of boxes
  LargeArray<BandEntry> crossedScratch_;  // scratch of sortByBand: the entries that changed band
  // By band: the proxies from the band below that reach into it (in x order, as they are read), and those
  // from further below (few: a wall across many bands; in no order).
  std::vector<std::vector<BandEntry>> spill_, tall_;
  // Queries: a band's narrow boxes are found by binary search on the lower x edge, reaching back by the
  // widest narrow box of the list; boxes much wider than most (a long wall, a body's sight sensor) are
  // listed apart and scanned whole, so that they do not set every search's reach.
  std::vector<double> ownReach_, spillReach_;  // by band
  std::vector<double> wholeReach_;  // by band: the widest of its own boxes, wide ones too (for tall_)
  std::vector<std::vector<Entry>> wide_;       // by band: its wide boxes, own or spilled
  double wideThreshold_ = 0;
  size_t movingCount_ = 0;  // moving boxes at the last sweep
  std::vector<GrownEntry> grown_;
  LargeArray<Growth> growth_;  // by fixture index
  std::vector<std::vector<uint32_t>> grownBands_;  // by band: indices into grown_
  uint32_t sweep_ = 1;  // counts findPairs calls: growth_ entries from earlier ones are stale
  // Queries find where to start in a band's sorted list by a binary search over every kKeyStride-th
  // lower x edge of it, copied into one small array (a band's keys are ownKeys_[ownKeyStart_[b],
  // ownKeyStart_[b + 1]), likewise for the spills): in a large world that array stays in cache while the
  // lists themselves do not, so a search costs a miss or two instead of one per halving.
  static constexpr uint32_t kKeyStride = 8;
  std::vector<double> ownKeys_, spillKeys_;
  std::vector<uint32_t> ownKeyStart_, spillKeyStart_;
  uint32_t queryStamp_ = 0;

  // The pair cache: frame-to-frame coherence carried one step further, as molecular dynamics keeps a
  // Verlet neighbour list with a skin (Verlet 1967; Allen & Tildesley, Computer Simulation of Liquids,
  // 5.3). A sweep widens every moving box by a margin (its reach, kept by fixture) and keeps every pair of
  // overlapping reaches. While a later step's boxes stay inside their reaches, the pairs whose boxes
  // overlap are among those kept, and that step only filters them: no sort, no split, no sweep. A box
  // that leaves its reach (escaped) is looked up by query instead, and its kept pairs are passed over;
  // when many have escaped, the next step sweeps the reaches again. When anything the sweep decided by has
  // changed (a proxy added or removed, a filter, a moving flag, a tag), the next step sweeps plainly, and
  // the reaches are swept at the first step after an unchanged one. Either way findPairs reports the same
  // pairs.
  struct CachedPair {
    uint32_t a, b;
  };
  std::vector<CachedPair> cachedPairs_;
  // The kept pairs by fixture, both ways: fixture f's partners are partners_[partnerStart_[f],
  // partnerStart_[f + 1]) (queryAround).
  std::vector<uint32_t> partnerStart_, partners_;
  // Scratch of findPairs: the kept pairs whose boxes overlap, with their proxies' tags (read with the
  // boxes: by the time the pairs are reported, a large world's proxies are out of cache again).
  struct Hit {
    uint32_t a, b, tagA, tagB;
  };
  std::vector<Hit> hits_;
  LargeArray<Box> reach_;          // by fixture index: the box widened by the margin, at the last sweep
  std::vector<uint32_t> escaped_;  // proxies whose box left their reach (Proxy::escaped)
  bool pairCache_ = false;
  bool cacheValid_ = false;
  bool lastFromCache_ = false;
  double marginFraction_ = kDefaultMargin;
  bool changed_ = false;  // noteChange since the last findPairs
  size_t pairTestBudget_ = SIZE_MAX;
  bool overflowed_ = false;
  double typicalHeight_ = 0;  // of the moving boxes, as the last sweep sampled it (lowest quarter)

  // The sensor sweep: both kinds in x order, swept in bands cut for the sensors.
  std::vector<uint32_t> order_;        // the proxies that are not sensors, by box.min.x at the last sensor sweep
  std::vector<uint32_t> sensorOrder_;  // the sensors, likewise
  uint32_t sensorBandCount_ = 1;
  double sensorBandOrigin_ = 0;
  double sensorInverseBandHeight_ = 0;
  std::vector<std::vector<BandEntry>> sensorOthers_, sensorBands_;
  std::vector<BandEntry> entries_, sensorEntries_;  // scratch of splitIntoSensorBands: the proxies in x order
  std::vector<double> heights_, sensorHeights_;     // scratch of splitIntoSensorBands
  // Scratch of findSensorPairs: per sensor filter, indices into a band's sensors and into its others.
  std::vector<std::vector<uint32_t>> sensorLists_, otherLists_;
  struct FilterBits {
    uint32_t category, mask;
  };
  std::vector<FilterBits> sensorFilters_;  // scratch of findSensorPairs: the sensors' filters in a band
};

template <class Report, class Ahead>
void BroadPhase::findPairs(Report&& report, Ahead&& ahead) {
  auto reportTagged = [&](uint32_t a, uint32_t b, uint32_t tagA, uint32_t tagB) {
    if constexpr (std::is_invocable_v<Report, uint32_t, uint32_t, uint32_t, uint32_t>) {
      report(a, b, tagA, tagB);
    } else {
      report(a, b);
    }
  };
  auto reportPair = [&](uint32_t a, uint32_t b) { reportTagged(a, b, proxies_[a].tag, proxies_[b].tag); };
  // A world that changed since the last step (a game's shots come and go, its units stop and start) is
  // likely to change again before kept pairs could serve: it is swept plainly, and the pairs are kept
  // only from a step that follows an unchanged one.
  const bool changed = changed_;
  changed_ = false;
  overflowed_ = false;
  if (!pairCache_ || changed) {
    // Every step sorts and sweeps this step's boxes, and reports in the sweep's order.
    lastFromCache_ = false;
    sortByBand(0);
    splitIntoBands();
    sweepBands([&](const BandEntry& a, const BandEntry& b, bool meets) {
      if (meets) reportTagged(a.fixture, b.fixture, a.tag, b.tag);
    });
    forgetGrowth();
    return;
  }
  // An escaped box that is back inside its reach is served by the kept pairs again.
  size_t stillOut = 0;
  for (uint32_t f : escaped_) {
    Proxy& p = proxies_[f];
    if (p.present && !p.sensor && !reach_[f].contains(p.box)) {
      escaped_[stillOut++] = f;
    } else {
      p.escaped = false;
    }
  }
  escaped_.resize(stillOut);
  // Past this many escapes a sweep costs less than their queries (measured on the bench's gas: at 10^6
  // disks a query costs about 1 us, a sweep about 60 ns a disk more than a step from the cache).
  const bool fromCache = cacheValid_ && escaped_.size() <= 16 + cachedPairs_.size() / 128;
  lastFromCache_ = fromCache;
  if (!fromCache) {
    for (uint32_t f : escaped_) proxies_[f].escaped = false;
    escaped_.clear();
    sweepReaches();
  }
  forgetGrowth();
  // Most kept pairs do not overlap this step, and which do is a coin toss to the branch predictor: the
  // test writes every pair and keeps those that pass, without a branch.
  const size_t kept = cachedPairs_.size();
  hits_.resize(kept);
  size_t hits = 0;
  for (size_t k = 0; k < kept; ++k) {
    const CachedPair& c = cachedPairs_[k];
    const Proxy& a = proxies_[c.a];
    const Proxy& b = proxies_[c.b];
    const bool overlap = (a.box.min.x <= b.box.max.x) & (b.box.min.x <= a.box.max.x) &
                         (a.box.min.y <= b.box.max.y) & (b.box.min.y <= a.box.max.y);
    hits_[hits] = {c.a, c.b, a.tag, b.tag};
    hits += static_cast<size_t>(overlap & !(a.escaped | b.escaped));
  }
  // The report reads what the two proxies stand for (a plain pair: both bodies' disk paths and pair
  // lists), scattered over memory at 10^6 bodies; one pair after another, each of those reads waited for
  // memory in turn. Told ahead, the caller has them on their way several pairs at a time.
  auto tellAhead = [&](const Hit& x) { ahead(x.a, x.b, x.tagA, x.tagB); };
  for (size_t h = 0; h < std::min(hits, kReportAhead); ++h) tellAhead(hits_[h]);
  for (size_t h = 0; h < hits; ++h) {
    if (h + kReportAhead < hits) tellAhead(hits_[h + kReportAhead]);
    reportTagged(hits_[h].a, hits_[h].b, hits_[h].tagA, hits_[h].tagB);
  }
  if (escaped_.empty()) return;
  // The escaped boxes, listed as grown (so that queries, theirs and those mid-step, see where they are
  // now), then each looked up; a pair of two escaped ones is reported by the lower fixture's query.
  for (uint32_t f : escaped_) grow(f, proxies_[f].box);
  for (uint32_t f : escaped_) {
    const Proxy& p = proxies_[f];
    const Box box = p.box;
    query(box, [&](uint32_t g) {
      const Proxy& q = proxies_[g];
      if (g == f || (q.escaped && g < f)) return;
      if (!p.moving && !q.moving) return;
      if ((p.category & q.mask) == 0 || (q.category & p.mask) == 0) return;
      reportPair(f, g);
    });
  }
}

template <class Pair>
void BroadPhase::sweepBands(Pair&& pair) {
  // Whether two boxes that overlap in x make a pair, without a branch: whether they overlap in y is a coin
  // toss to the branch predictor, and the caller that keeps the pairs (sweepReaches) stores every
  // candidate and keeps those that pass, without one either.
  auto test = [&](const BandEntry& pi, const BandEntry& pj) {
    const bool meets = (pi.moving | pj.moving) & ((pi.category & pj.mask) != 0) & ((pj.category & pi.mask) != 0) &
                       !(pj.box.min.y > pi.box.max.y) & !(pi.box.min.y > pj.box.max.y);
    pair(pi, pj, meets);
  };
  // A pair is found in the higher of its two home bands: there both are listed, the one as its own, the
  // other as its own or as a spill from below. Two spills are never swept against each other.
  // The budget (setPairTestBudget) is looked at once per box, outside the inner loops.
  size_t tests = 0;
  auto overBudget = [&] {
    if (tests <= pairTestBudget_) return false;
    overflowed_ = true;
    return true;
  };
  for (uint32_t band = 0; band < bandCount_; ++band) {
    const BandEntry* own = own_.data() + bandStart_[band];
    const size_t n = bandStart_[band + 1] - bandStart_[band];
    for (size_t i = 0; i < n; ++i) {
      const BandEntry& pi = own[i];
      size_t j = i + 1;
      for (; j < n && own[j].box.min.x <= pi.box.max.x; ++j) test(pi, own[j]);
      tests += j - i - 1;
      if (overBudget()) return;
    }
    // The band's own against its spills: two sorted lists swept against each other; whichever next box
    // starts further left scans the other list for the boxes that start before it ends.
    const std::vector<BandEntry>& spill = spill_[band];
    const size_t m = spill.size();
    size_t i = 0, j = 0;
    while (i < n && j < m) {
      if (own[i].box.min.x <= spill[j].box.min.x) {
        const double reach = own[i].box.max.x;
        size_t k = j;
        for (; k < m && spill[k].box.min.x <= reach; ++k) test(own[i], spill[k]);
        tests += k - j;
        ++i;
      } else {
        const double reach = spill[j].box.max.x;
        size_t k = i;
        for (; k < n && own[k].box.min.x <= reach; ++k) test(own[k], spill[j]);
        tests += k - i;
        ++j;
      }
      if (overBudget()) return;
    }
    // The band's own against the tall boxes from further below, each found by binary search.
    for (const BandEntry& t : tall_[band]) {
      const BandEntry* it = std::lower_bound(own, own + n, t.box.min.x - wholeReach_[band],
                                             [](const BandEntry& e, double x) { return e.box.min.x < x; });
      const BandEntry* from = it;
      for (; it != own + n && it->box.min.x <= t.box.max.x; ++it) {
        if (!(it->box.max.x < t.box.min.x)) test(*it, t);
      }
      tests += static_cast<size_t>(it - from);
      if (overBudget()) return;
    }
  }
}

template <class Report>
void BroadPhase::findSensorPairs(Report&& report) {
  compact();
  sortList(order_);
  sortList(sensorOrder_);
  splitIntoSensorBands();
  // Past this many different sensor filters in one band, one sweep of all sensors against all others
  // costs less than a filtered sweep per filter.
  constexpr size_t kMaxFilters = 8;
  if (sensorLists_.size() < kMaxFilters) sensorLists_.resize(kMaxFilters);
  if (otherLists_.size() < kMaxFilters) otherLists_.resize(kMaxFilters);
  for (uint32_t band = 0; band < sensorBandCount_; ++band) {
    const std::vector<BandEntry>& sensors = sensorBands_[band];
    const std::vector<BandEntry>& others = sensorOthers_[band];
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
    // Two sorted lists swept against each other, as the collision sweep does a band's own and spills; a
    // pair is reported only in the lowest band both are in.
    auto test = [&](const BandEntry& pi, const BandEntry& pj) {
      if (!pi.moving && !pj.moving) return;
      if (pj.box.min.y > pi.box.max.y || pi.box.min.y > pj.box.max.y) return;
      if (std::max(sensorBandOf(pi.box.min.y), sensorBandOf(pj.box.min.y)) != band) return;
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
}

template <class Found>
void BroadPhase::query(const Box& q, Found&& found) {
  startQuery();
  auto visit = [&](uint32_t f) { visitOnce(f, q, found); };
  // The boxes that start within a list's reach before q and before q ends. An entry's box is the one the
  // sweep saw; a box grown since is in the band's grown list with its grown box, so an entry whose box
  // misses q is passed over without a look at its proxy.
  auto scan = [&](const BandEntry* begin, const BandEntry* end, const double* keys, const double* keysEnd,
                  double reach) {
    const double x = q.min.x - reach;
    // keys[k] is begin[k * stride]'s lower edge: the first entry at or past x lies in
    // (stride (k - 1), stride k] for the first key k at or past x.
    const size_t k = static_cast<size_t>(std::lower_bound(keys, keysEnd, x) - keys);
    const size_t n = static_cast<size_t>(end - begin);
    const BandEntry* from = begin + (k == 0 ? 0 : std::min(n, kKeyStride * (k - 1) + 1));
    const BandEntry* to = begin + std::min(n, kKeyStride * k);
    const BandEntry* it =
        std::lower_bound(from, to, x, [](const BandEntry& e, double v) { return e.box.min.x < v; });
    for (; it != end && it->box.min.x <= q.max.x; ++it) {
      if (it->box.overlaps(q)) visit(it->fixture);
    }
  };
  if (bandStart_.size() <= bandCount_) return;  // no sweep yet: nothing to find
  const uint32_t last = bandOf(q.max.y);
  for (uint32_t band = bandOf(q.min.y); band <= last; ++band) {
    scan(own_.data() + bandStart_[band], own_.data() + bandStart_[band + 1], ownKeys_.data() + ownKeyStart_[band],
         ownKeys_.data() + ownKeyStart_[band + 1], ownReach_[band]);
    const std::vector<BandEntry>& spill = spill_[band];
    scan(spill.data(), spill.data() + spill.size(), spillKeys_.data() + spillKeyStart_[band],
         spillKeys_.data() + spillKeyStart_[band + 1], spillReach_[band]);
    for (const Entry& e : wide_[band]) {
      if (e.minX <= q.max.x) visit(e.fixture);
    }
    for (const BandEntry& t : tall_[band]) visit(t.fixture);
    for (uint32_t k : grownBands_[band]) {
      if (grown_[k].box.overlaps(q)) visit(grown_[k].fixture);
    }
  }
}

template <class Found>
void BroadPhase::queryAround(uint32_t fixture, Found&& found) {
  const Proxy& p = proxies_[fixture];
  const Box q = p.box;
  // Every proxy whose box overlaps q is either inside its own reach, which then overlaps this one's, so
  // that the sweep kept the pair (p moves, and a pair whose filters meet is kept when one of the two
  // moves), or it has left its reach and is in the grown lists.
  // (A valid cache has every present proxy in partnerStart_: an added one voids it.)
  if (!pairCache_ || !cacheValid_ || p.escaped || !p.moving || !reach_[fixture].contains(q)) {
    query(q, found);
    return;
  }
  startQuery();
  auto visit = [&](uint32_t f) { visitOnce(f, q, found); };
  visit(fixture);
  for (uint32_t k = partnerStart_[fixture]; k < partnerStart_[fixture + 1]; ++k) visit(partners_[k]);
  const uint32_t last = bandOf(q.max.y);
  for (uint32_t band = bandOf(q.min.y); band <= last; ++band) {
    for (uint32_t k : grownBands_[band]) {
      if (grown_[k].box.overlaps(q)) visit(grown_[k].fixture);
    }
  }
}

}  // namespace rattle::detail
