// rattle-bench: the error measures (see measure.h).
#include "measure.h"

#include <algorithm>
#include <cmath>

namespace rattle_bench {

namespace {

/// The cell of coordinate f (in cells), clamped into [0, n) (NaN and infinities included).
int cellCoordinate(double f, int n) {
  if (!(f >= 0)) return 0;
  if (!(f < n)) return n - 1;
  return static_cast<int>(f);
}

/// Distance from p to the closed segment [a, b].
double distanceToSegment(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double q = rattle::dot(ab, ab);
  const double t = q > 0 ? std::clamp(rattle::dot(p - a, ab) / q, 0.0, 1.0) : 0.0;
  return rattle::length(p - (a + t * ab));
}

}  // namespace

OverlapMeter::OverlapMeter(const Scene& scene) : scene_(scene) {
  double rmax = 0;
  for (const DiskStart& d : scene.disks) rmax = std::max(rmax, d.radius);
  cell_ = std::max(2 * rmax, 1e-9);
  const Vec2 size = scene.bounds.max - scene.bounds.min;
  nx_ = std::max(1, static_cast<int>(std::ceil(size.x / cell_)));
  ny_ = std::max(1, static_cast<int>(std::ceil(size.y / cell_)));
}

void OverlapMeter::measure(const std::vector<Vec2>& p, OverlapStats& stats) {
  const std::vector<DiskStart>& disks = scene_.disks;
  const size_t n = disks.size();
  auto record = [&stats](double depth) {
    if (depth > 0) {
      stats.max = std::max(stats.max, depth);
      stats.sum += depth;
      ++stats.count;
    }
  };
  // Disks against walls.
  for (size_t i = 0; i < n; ++i)
    for (const Wall& w : scene_.walls) {
      const double r = disks[i].radius;
      const double d = distanceToSegment(p[i], w.a, w.b);
      if (d < r) record((r - d) / r);
    }
  if (!scene_.disksCollide) return;
  // Disks against disks: counting sort into cells (a centre outside the container goes to the nearest
  // edge cell, which keeps every touching pair in neighbouring cells), then each cell against itself and
  // four of its neighbours, so each pair is looked at once.
  const size_t cells = static_cast<size_t>(nx_) * static_cast<size_t>(ny_);
  cellOf_.resize(n);
  start_.assign(cells + 1, 0);
  order_.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const Vec2 q = p[i] - scene_.bounds.min;
    const int cx = cellCoordinate(q.x / cell_, nx_);
    const int cy = cellCoordinate(q.y / cell_, ny_);
    cellOf_[i] = cy * nx_ + cx;
    ++start_[static_cast<size_t>(cellOf_[i]) + 1];
  }
  for (size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
  {
    std::vector<int> fill(start_.begin(), start_.end() - 1);
    for (size_t i = 0; i < n; ++i) order_[static_cast<size_t>(fill[static_cast<size_t>(cellOf_[i])]++)] = static_cast<int>(i);
  }
  auto pairDepth = [&](int i, int j) {
    const double ri = disks[static_cast<size_t>(i)].radius, rj = disks[static_cast<size_t>(j)].radius;
    const double d = rattle::length(p[static_cast<size_t>(i)] - p[static_cast<size_t>(j)]);
    const double depth = ri + rj - d;
    if (depth > 0) record(depth / std::min(ri, rj));
  };
  static constexpr int kNeighbours[4][2] = {{1, 0}, {-1, 1}, {0, 1}, {1, 1}};
  for (int cy = 0; cy < ny_; ++cy)
    for (int cx = 0; cx < nx_; ++cx) {
      const size_t c = static_cast<size_t>(cy * nx_ + cx);
      const int b = start_[c], e = start_[c + 1];
      if (b == e) continue;
      for (int u = b; u < e; ++u)
        for (int v = u + 1; v < e; ++v) pairDepth(order_[static_cast<size_t>(u)], order_[static_cast<size_t>(v)]);
      for (const auto& off : kNeighbours) {
        const int ox = cx + off[0], oy = cy + off[1];
        if (ox < 0 || ox >= nx_ || oy >= ny_) continue;
        const size_t o = static_cast<size_t>(oy * nx_ + ox);
        for (int u = b; u < e; ++u)
          for (int v = start_[o]; v < start_[o + 1]; ++v)
            pairDepth(order_[static_cast<size_t>(u)], order_[static_cast<size_t>(v)]);
      }
    }
}

long double totalEnergy(const Scene& scene, const std::vector<Vec2>& p, const std::vector<Vec2>& v) {
  long double e = 0;
  for (size_t i = 0; i < scene.disks.size(); ++i) {
    const long double m = massOf(scene.disks[i]);
    e += 0.5L * m * (static_cast<long double>(v[i].x) * v[i].x + static_cast<long double>(v[i].y) * v[i].y);
    e -= m * (static_cast<long double>(scene.gravity.x) * p[i].x + static_cast<long double>(scene.gravity.y) * p[i].y);
  }
  return e;
}

int markTunnelled(const Scene& scene, const std::vector<Vec2>& p, std::vector<uint8_t>& outside) {
  outside.resize(p.size(), 0);
  int count = 0;
  const rattle::Box& b = scene.bounds;
  for (size_t i = 0; i < p.size(); ++i) {
    if (!(p[i].x >= b.min.x && p[i].x <= b.max.x && p[i].y >= b.min.y && p[i].y <= b.max.y)) outside[i] = 1;
    count += outside[i];
  }
  return count;
}

long long sensorMisses(const std::vector<long long>& reference, const std::vector<long long>& engine) {
  long long missed = 0;
  for (size_t k = 0; k < reference.size(); ++k) {
    const long long got = k < engine.size() ? engine[k] : 0;
    missed += std::max(0LL, reference[k] - got);
  }
  return missed;
}

}  // namespace rattle_bench
