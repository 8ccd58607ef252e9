// rattle-bench: the older detector's way (engine `bisect`), a variant of discrete stepping.
//
// It follows the "Motion" section of seeds/collision-detector-manual.txt:
//   "checking the lines of the path for intersections with the other object and its path line - whereas a
//    path line is a line from the center of the object to where the center was at the last frame. If
//    there is an intersection the objects might have intersected some time between the frames. [...]
//    the collidables are tested at different times between the end positions. The first check is done at
//    time 0.5 [...] If no intersection was found, the objects are again placed in the middle of both
//    subsections and the procedure is repeated, until the depth of the breadth-first search has reached
//    movement_check or an intersection has been found. [...] finding the first intersection point of two
//    moving objects [...] is done using the bisection method with a depth of search_depth."
// A step here:
//  1. Every disk's velocity takes the step's gravity (semi-implicit Euler, as game engines integrate), and
//     its path line runs straight from where it is to where that velocity takes it in dt.
//  2. Rough phase (the manual's first step, with boxes where it had bounding circles): the boxes around the
//     path lines, swelled by the radius, through sort-and-sweep on x for disk pairs; every disk's box
//     against every wall's and sensor's.
//  3. Path-line check: a pair is a suspect when the two overlap at the end of the step, or one's path line
//     meets the other's disk (at its end position), or the two path lines cross; a disk and a wall when it
//     overlaps the wall at the end or its path line crosses the wall. This is "not absolutely correct", as
//     the manual says: a disk that only grazes something with its rim between frames is not a suspect.
//  4. For a suspect, positions along the path lines at t = 1/2, then 1/4 and 3/4, ... (breadth first, in
//     time order within a level) for `movementCheck` levels; the first overlapping sample brackets the
//     first contact between it and the sample before it, and `searchDepth` bisections narrow the bracket.
//     The contact time is the bracket's lower end (not yet overlapping). No sample overlapping: no contact.
//  5. Response, like the discrete mode's: contacts in time order (then by ids); at its time, a pair still on
//     the paths it was detected on and approaching gets the restitution impulse along the line of centres,
//     and both continue from there on their new velocities. A contact of a disk whose path has changed
//     since is dropped (one response per pair per step, no re-detection): that is where this way misses.
//     No pushing apart: the detector never had a solver.
//  6. Sensors use the same path-line check: a disk not inside a sensor at the last frame begins a visit when
//     it overlaps the sensor at the end of the step or its path line (last frame to this one) crosses it.
// Depths: BisectDepths in engine.h (movementCheck 4, i.e. 2^4 - 1 samples at most, searchDepth 10).
#include <algorithm>
#include <cmath>
#include <numeric>

#include "engine.h"
#include "rattle/geometry.h"

namespace rattle_bench {

namespace {

double distanceToSegment(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double q = rattle::dot(ab, ab);
  const double t = q > 0 ? std::clamp(rattle::dot(p - a, ab) / q, 0.0, 1.0) : 0.0;
  return rattle::length(p - (a + t * ab));
}

Vec2 closestOnSegment(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double q = rattle::dot(ab, ab);
  const double t = q > 0 ? std::clamp(rattle::dot(p - a, ab) / q, 0.0, 1.0) : 0.0;
  return a + t * ab;
}

rattle::Box boxAround(Vec2 a, Vec2 b, double r) {
  return {{std::min(a.x, b.x) - r, std::min(a.y, b.y) - r}, {std::max(a.x, b.x) + r, std::max(a.y, b.y) + r}};
}

class BisectEngine final : public Engine {
 public:
  BisectEngine(const Scene& scene, BisectDepths depths) : scene_(scene), depths_(depths) {
    const size_t n = scene.disks.size();
    p_.resize(n);
    v_.resize(n);
    invMass_.resize(n);
    for (size_t i = 0; i < n; ++i) {
      p_[i] = scene.disks[i].position;
      v_[i] = scene.disks[i].velocity;
      invMass_[i] = 1.0 / massOf(scene.disks[i]);
    }
    for (const Wall& w : scene.walls) {
      wallGeometry_.emplace_back(rattle::Segment{w.a, w.b});
      wallBox_.push_back(boxAround(w.a, w.b, 0));
    }
    for (const SensorStrip& s : scene.sensors) {
      sensorGeometry_.emplace_back(rattle::Polygon{s.points});
      sensorBox_.push_back(rattle::boxOf(sensorGeometry_.back()));
    }
    inside_.assign(scene.sensors.size() * n, 0);
    sensorBegins.assign(scene.sensors.size() * n, 0);
    order_.resize(n);
    std::iota(order_.begin(), order_.end(), 0);
  }

  void step(double dt) override {
    const size_t n = p_.size();
    start_ = p_;
    ref_ = p_;
    pathEnd_.resize(n);
    box_.resize(n);
    tRef_.assign(n, 0.0);
    version_.assign(n, 0);
    for (size_t i = 0; i < n; ++i) {
      v_[i] += dt * scene_.gravity;
      pathEnd_[i] = start_[i] + dt * v_[i];
      box_[i] = boxAround(start_[i], pathEnd_[i], scene_.disks[i].radius);
    }
    contacts_.clear();
    // Rough phase and path-line check for disk pairs: sort-and-sweep on the boxes' x (the order from the
    // last step is nearly sorted already; ties by index keep it deterministic).
    if (scene_.disksCollide) {
      std::sort(order_.begin(), order_.end(), [this](int a, int b) {
        const double xa = box_[static_cast<size_t>(a)].min.x, xb = box_[static_cast<size_t>(b)].min.x;
        return xa != xb ? xa < xb : a < b;
      });
      for (size_t u = 0; u < n; ++u) {
        const int i = order_[u];
        const rattle::Box& bi = box_[static_cast<size_t>(i)];
        for (size_t w = u + 1; w < n; ++w) {
          const int j = order_[w];
          const rattle::Box& bj = box_[static_cast<size_t>(j)];
          if (bj.min.x > bi.max.x) break;
          if (bj.min.y > bi.max.y || bi.min.y > bj.max.y) continue;
          checkPair(std::min(i, j), std::max(i, j), dt);
        }
      }
    }
    for (size_t i = 0; i < n; ++i)
      for (size_t w = 0; w < wallBox_.size(); ++w)
        if (box_[i].overlaps(wallBox_[w])) checkWall(static_cast<int>(i), static_cast<int>(w), dt);
    // Response in time order.
    std::sort(contacts_.begin(), contacts_.end(), [](const Contact& x, const Contact& y) {
      if (x.time != y.time) return x.time < y.time;
      if (x.a != y.a) return x.a < y.a;
      return x.b < y.b;
    });
    for (const Contact& c : contacts_) respond(c);
    // Everyone finishes the step on its current path.
    for (size_t i = 0; i < n; ++i) p_[i] = at(i, dt);
    if (!sensorGeometry_.empty()) sensorStep();
  }

  void collect() override {}

  void state(std::vector<Vec2>& positions, std::vector<Vec2>& velocities) const override {
    positions = p_;
    velocities = v_;
  }

 private:
  struct Contact {
    double time;  // seconds into the step
    int a;
    int b;  // a disk index, or -1 - wall index
  };

  // Where disk i is at time t into the step on its current path (before any response: its path line).
  Vec2 at(size_t i, double t) const { return ref_[i] + (t - tRef_[i]) * v_[i]; }
  // Along the path line, as the detector sees it: the fraction s of the way from last frame to this one.
  Vec2 onPath(size_t i, double s) const { return start_[i] + s * (pathEnd_[i] - start_[i]); }

  bool pairOverlapsAt(int i, int j, double s) const {
    const double r = scene_.disks[static_cast<size_t>(i)].radius + scene_.disks[static_cast<size_t>(j)].radius;
    return rattle::lengthSquared(onPath(static_cast<size_t>(i), s) - onPath(static_cast<size_t>(j), s)) < r * r;
  }
  bool wallOverlapsAt(int i, int w, double s) const {
    const Wall& wall = scene_.walls[static_cast<size_t>(w)];
    return distanceToSegment(onPath(static_cast<size_t>(i), s), wall.a, wall.b) < scene_.disks[static_cast<size_t>(i)].radius;
  }

  // Step 4: breadth-first samples, then bisection. Returns the contact's fraction of the step, or -1.
  template <class Overlaps>
  double firstContact(bool overlapsAtEnd, const Overlaps& overlapsAt) const {
    double lo = -1, hi = -1;
    for (int level = 1; level <= depths_.movementCheck && hi < 0; ++level) {
      const double h = std::ldexp(1.0, -level);
      for (double s = h; s < 1.0; s += 2 * h)
        if (overlapsAt(s)) {
          lo = s - h;
          hi = s;
          break;
        }
    }
    if (hi < 0) {
      if (!overlapsAtEnd) return -1;
      hi = 1.0;
      lo = 1.0 - std::ldexp(1.0, -depths_.movementCheck);
    }
    for (int k = 0; k < depths_.searchDepth; ++k) {
      const double mid = 0.5 * (lo + hi);
      (overlapsAt(mid) ? hi : lo) = mid;
    }
    return lo;
  }

  void checkPair(int i, int j, double dt) {
    const size_t a = static_cast<size_t>(i), b = static_cast<size_t>(j);
    const double ra = scene_.disks[a].radius, rb = scene_.disks[b].radius;
    const bool endOverlap = pairOverlapsAt(i, j, 1.0);
    bool suspect = endOverlap;
    if (!suspect) {
      const Vec2 da = pathEnd_[a] - start_[a], db = pathEnd_[b] - start_[b];
      suspect = rattle::rayCast(rattle::Circle{{0, 0}, rb}, pathEnd_[b], start_[a], da).has_value() ||
                rattle::rayCast(rattle::Circle{{0, 0}, ra}, pathEnd_[a], start_[b], db).has_value() ||
                rattle::rayCast(rattle::Segment{start_[b], pathEnd_[b]}, {0, 0}, start_[a], da).has_value();
    }
    if (!suspect) return;
    const double s = firstContact(endOverlap, [&](double t) { return pairOverlapsAt(i, j, t); });
    if (s >= 0) contacts_.push_back({s * dt, i, j});
  }

  void checkWall(int i, int w, double dt) {
    const size_t a = static_cast<size_t>(i);
    const bool endOverlap = wallOverlapsAt(i, w, 1.0);
    const bool suspect =
        endOverlap ||
        rattle::rayCast(wallGeometry_[static_cast<size_t>(w)], {0, 0}, start_[a], pathEnd_[a] - start_[a]).has_value();
    if (!suspect) return;
    const double s = firstContact(endOverlap, [&](double t) { return wallOverlapsAt(i, w, t); });
    if (s >= 0) contacts_.push_back({s * dt, i, -1 - w});
  }

  // Step 5. A disk whose path changed since the contact was found (its version moved on) drops it.
  void respond(const Contact& c) {
    const size_t a = static_cast<size_t>(c.a);
    if (version_[a] != 0) return;
    const double e = scene_.restitution;
    if (c.b >= 0) {
      const size_t b = static_cast<size_t>(c.b);
      if (version_[b] != 0) return;
      const Vec2 pa = at(a, c.time), pb = at(b, c.time);
      const double d = rattle::length(pb - pa);
      if (!(d > 0)) return;
      const Vec2 normal = (1.0 / d) * (pb - pa);
      const double vn = rattle::dot(v_[b] - v_[a], normal);
      if (!(vn < 0)) return;
      // Impulse J = -(1 + e) v_n / (1/m_a + 1/m_b) along the line of centres.
      const double J = -(1 + e) * vn / (invMass_[a] + invMass_[b]);
      moveTo(a, c.time, pa);
      moveTo(b, c.time, pb);
      v_[a] -= (J * invMass_[a]) * normal;
      v_[b] += (J * invMass_[b]) * normal;
    } else {
      const Wall& wall = scene_.walls[static_cast<size_t>(-1 - c.b)];
      const Vec2 pa = at(a, c.time);
      const Vec2 away = pa - closestOnSegment(pa, wall.a, wall.b);
      const double d = rattle::length(away);
      if (!(d > 0)) return;
      const Vec2 normal = (1.0 / d) * away;
      const double vn = rattle::dot(v_[a], normal);
      if (!(vn < 0)) return;
      moveTo(a, c.time, pa);
      v_[a] -= ((1 + e) * vn) * normal;
    }
    ++collisions;
  }

  // Disk i leaves its path line at time t, from p. Its later contacts of this step are then dropped.
  void moveTo(size_t i, double t, Vec2 p) {
    ref_[i] = p;
    tRef_[i] = t;
    ++version_[i];
  }

  // Step 6.
  void sensorStep() {
    const size_t n = p_.size();
    for (size_t s = 0; s < sensorGeometry_.size(); ++s)
      for (size_t i = 0; i < n; ++i) {
        const double r = scene_.disks[i].radius;
        uint8_t& in = inside_[s * n + i];
        if (!boxAround(start_[i], p_[i], r).overlaps(sensorBox_[s])) {
          in = 0;
          continue;
        }
        const bool endInside = rattle::overlaps(rattle::Circle{{0, 0}, r}, p_[i], sensorGeometry_[s], {0, 0});
        if (!in && (endInside || rattle::rayCast(sensorGeometry_[s], {0, 0}, start_[i], p_[i] - start_[i]).has_value()))
          ++sensorBegins[s * n + i];
        in = endInside ? 1 : 0;
      }
  }

  const Scene scene_;
  BisectDepths depths_;
  std::vector<Vec2> p_, v_, start_, pathEnd_, ref_;
  std::vector<double> invMass_, tRef_;
  std::vector<int> version_;
  std::vector<rattle::Box> box_, wallBox_, sensorBox_;
  std::vector<rattle::Geometry> wallGeometry_, sensorGeometry_;
  std::vector<uint8_t> inside_;
  std::vector<int> order_;
  std::vector<Contact> contacts_;
};

}  // namespace

std::unique_ptr<Engine> makeBisectEngine(const Scene& scene, BisectDepths depths) {
  return std::make_unique<BisectEngine>(scene, depths);
}

}  // namespace rattle_bench
