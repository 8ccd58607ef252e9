// rattle-bench: building the scenes (see scenes.h for what each one is).
#include "scenes.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <string>

#include "random.h"
#include "rattle/world.h"

namespace rattle_bench {

namespace {

constexpr double kPi = std::numbers::pi;
// Clearance between any two starting disks, and between a disk and a wall, relative to the radius.
constexpr double kGapPerRadius = 2e-3;

std::string str(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

/// A uniformly random unit vector: a point drawn uniformly in the unit disk by rejection, normalised
/// (sqrt is correctly rounded everywhere; cos and sin are not).
Vec2 randomDirection(Random& rng) {
  for (;;) {
    const double x = rng.uniform(-1.0, 1.0), y = rng.uniform(-1.0, 1.0);
    const double q = x * x + y * y;
    if (q > 1e-6 && q <= 1.0) {
      const double s = std::sqrt(q);
      return {x / s, y / s};
    }
  }
}

/// `count` centres in the region [lo, hi] (centres; the caller has already kept them r + gap from the
/// walls), at least 2r + gap apart. They sit on a lattice of rows stretched to fill the region: triangular
/// (every other row shifted by half a spacing) or square, whichever row length and kind puts the nearest
/// neighbours farthest apart; a random subset of the sites is taken when there are more sites than disks
/// (kept in row order, so disks are created in space order as a game would), and each centre is shaken
/// uniformly within a disk of radius (spacing - 2r - gap) / 2, so no two can touch.
std::vector<Vec2> jitteredLattice(Random& rng, int count, Vec2 lo, Vec2 hi, double r, double gap,
                                  const std::string& what) {
  const double W = hi.x - lo.x, H = hi.y - lo.y;
  if (!(W >= 0 && H >= 0)) throw SceneError(what + ": the container is smaller than one disk");
  const double inf = std::numeric_limits<double>::infinity();
  struct Lattice {
    int nx = 1, ny = 1;
    bool shifted = false;
    double dx = 0, dy = 0;
    double nearest = -1;  // distance between nearest sites
  };
  auto lattice = [&](int nx, bool shifted) {
    Lattice l;
    l.nx = nx;
    l.ny = (count + nx - 1) / nx;
    l.shifted = shifted && nx > 1 && l.ny > 1;
    l.dy = l.ny > 1 ? H / (l.ny - 1) : inf;
    l.dx = nx == 1 ? inf : l.shifted ? W / (nx - 0.5) : W / (nx - 1);
    // Neighbours: along a row (dx) and, triangular, in the next row half a spacing across and two rows on
    // in the same column; square, in the next row straight up.
    l.nearest = l.shifted ? std::min({l.dx, std::sqrt(0.25 * l.dx * l.dx + l.dy * l.dy), 2 * l.dy})
                          : std::min(l.dx, l.dy);
    return l;
  };
  Lattice best;
  for (int nx = 1; nx <= count; ++nx)
    for (bool shifted : {true, false}) {
      const Lattice l = lattice(nx, shifted);
      if (l.nearest > best.nearest) best = l;
    }
  const double d = best.nearest;
  if (!(d >= 2 * r + gap))
    throw SceneError(what + ": " + std::to_string(count) + " disks of radius " + str(r) +
                     " do not fit (nearest lattice neighbours " + str(d) + " apart)");
  const int nx = best.nx, ny = best.ny;
  const double dx = best.dx, dy = best.dy;
  const int sites = nx * ny;
  // A random subset of `count` sites: a partial Fisher-Yates shuffle, then back into row order.
  std::vector<int> order(static_cast<size_t>(sites));
  for (int i = 0; i < sites; ++i) order[static_cast<size_t>(i)] = i;
  for (int i = 0; i < count; ++i) {
    const int j = i + static_cast<int>(rng.below(static_cast<uint64_t>(sites - i)));
    std::swap(order[static_cast<size_t>(i)], order[static_cast<size_t>(j)]);
  }
  order.resize(static_cast<size_t>(count));
  std::sort(order.begin(), order.end());
  const double shake = std::isfinite(d) ? 0.5 * (d - 2 * r - gap) : 0.5 * std::min(W, H);
  std::vector<Vec2> centres;
  centres.reserve(static_cast<size_t>(count));
  for (int site : order) {
    const int row = site / nx, col = site % nx;
    const double shift = (best.shifted && row % 2 == 1) ? 0.5 : 0.0;
    Vec2 p{nx > 1 ? lo.x + (col + shift) * dx : 0.5 * (lo.x + hi.x), ny > 1 ? lo.y + row * dy : 0.5 * (lo.y + hi.y)};
    double jx, jy;
    do {
      jx = rng.uniform(-1.0, 1.0);
      jy = rng.uniform(-1.0, 1.0);
    } while (jx * jx + jy * jy > 1.0);
    // Clamping back into the region moves a centre toward its site, so it stays within `shake` of it.
    p.x = std::clamp(p.x + shake * jx, lo.x, hi.x);
    p.y = std::clamp(p.y + shake * jy, lo.y, hi.y);
    centres.push_back(p);
  }
  return centres;
}

/// Four walls around [x0, x1] x [y0, y1]: left, right, bottom, top.
void closedBox(Scene& s, double x0, double y0, double x1, double y1) {
  s.walls = {{{x0, y0}, {x0, y1}}, {{x1, y0}, {x1, y1}}, {{x0, y0}, {x1, y0}}, {{x0, y1}, {x1, y1}}};
  s.bounds = {{x0, y0}, {x1, y1}};
}

double orDefault(double v, double fallback) { return std::isnan(v) ? fallback : v; }

void requireSpeed(const std::string& scene, double speed) {
  if (!(std::isfinite(speed) && speed >= 0 && speed < rattle::World::kMaxSpeed))
    throw SceneError("--speed " + str(speed) + ": must be >= 0 and below " + str(rattle::World::kMaxSpeed) +
                     " (World::kMaxSpeed; scene " + scene + ")");
}

Scene gas(const SceneParams& p) {
  Scene s;
  const double r = 0.5;
  s.packing = orDefault(p.packing, 0.3);
  if (!(s.packing > 0 && s.packing < 0.9))
    throw SceneError("--packing " + str(s.packing) + ": must be in (0, 0.9) (scene gas)");
  s.speed = orDefault(p.speed, 1.0);
  requireSpeed("gas", s.speed);
  // Box side L from the packing fraction phi = n pi r^2 / L^2.
  const double L = std::sqrt(p.n * kPi * r * r / s.packing);
  closedBox(s, 0, 0, L, L);
  Random rng(p.seed);
  const double gap = kGapPerRadius * r;
  for (Vec2 c : jitteredLattice(rng, p.n, {r + gap, r + gap}, {L - r - gap, L - r - gap}, r, gap, "gas"))
    s.disks.push_back({c, {}, r, 1.0});
  for (DiskStart& d : s.disks) d.velocity = s.speed * randomDirection(rng);
  return s;
}

Scene pile(const SceneParams& p) {
  Scene s;
  const double r = 0.5;
  const double blockPacking = 0.35;
  const double S = std::sqrt(p.n * kPi * r * r / blockPacking);
  closedBox(s, 0, 0, S, 2 * S);
  s.gravity = {0, -10};
  s.restitution = 0.5;
  const double maxSpeed = orDefault(p.speed, 1.0);
  requireSpeed("pile", maxSpeed);
  s.speed = std::numeric_limits<double>::quiet_NaN();  // speeds differ
  s.packing = p.n * kPi * r * r / (2 * S * S);
  Random rng(p.seed);
  const double gap = kGapPerRadius * r;
  for (Vec2 c : jitteredLattice(rng, p.n, {r + gap, S + r + gap}, {S - r - gap, 2 * S - r - gap}, r, gap, "pile"))
    s.disks.push_back({c, {}, r, 1.0});
  for (DiskStart& d : s.disks) {
    // Two draws in one expression run in an order C++ leaves open (g++ and clang++ chose differently,
    // giving two piles from one seed): the direction is drawn first, as g++ did.
    const Vec2 direction = randomDirection(rng);
    d.velocity = rng.uniform(0.0, maxSpeed) * direction;
  }
  return s;
}

Scene bullets(const SceneParams& p) {
  Scene s;
  const double r = 0.05, L = 20;
  closedBox(s, 0, 0, L, L);
  s.packing = p.n * kPi * r * r / (L * L);
  Random rng(p.seed);
  const double gap = kGapPerRadius * r;
  for (Vec2 c : jitteredLattice(rng, p.n, {r + gap, r + gap}, {L - r - gap, L - r - gap}, r, gap, "bullets"))
    s.disks.push_back({c, {}, r, 1.0});
  if (!std::isnan(p.speed)) requireSpeed("bullets", p.speed);
  s.speed = p.speed;  // NaN: the scene's default speeds, which differ
  static constexpr double kDecades[4] = {10, 100, 1000, 10000};
  for (size_t i = 0; i < s.disks.size(); ++i)
    s.disks[i].velocity = (std::isnan(p.speed) ? kDecades[i % 4] : p.speed) * randomDirection(rng);
  return s;
}

Scene cradle(const SceneParams& p) {
  if (p.n % 6 != 0)
    throw SceneError("--n " + std::to_string(p.n) +
                                ": the cradle scene needs a multiple of 6 (a striker and five disks per lane)");
  Scene s;
  const int lanes = p.n / 6;
  const double r = 0.5, L = 16;
  closedBox(s, 0, 0, L, 2.0 * lanes);
  s.packing = p.n * kPi * r * r / (L * 2.0 * lanes);
  if (!std::isnan(p.speed)) requireSpeed("cradle", p.speed);
  s.speed = p.speed;  // NaN: the scene's default speeds, which differ
  Random rng(p.seed);
  for (int k = 0; k < lanes; ++k) {
    const double y = 2.0 * k + 1.0;
    const double v = std::isnan(p.speed) ? rng.uniform(1.0, 3.0) : p.speed;
    s.disks.push_back({{4.5, y}, {v, 0}, r, 1.0});
    // Centres exactly 1 apart (integers): the five disks touch, with no round-off in the gaps.
    for (int j = 0; j < 5; ++j) s.disks.push_back({{7.0 + j, y}, {}, r, 1.0});
  }
  return s;
}

Scene sensors(const SceneParams& p) {
  Scene s;
  const double r = 0.1, L = 20, half = 0.025;
  closedBox(s, 0, 0, L, L);
  s.disksCollide = false;
  s.packing = p.n * kPi * r * r / (L * L);
  for (double at : {5.0, 10.0, 15.0}) {
    s.sensors.push_back({{{at - half, 0}, {at + half, 0}, {at + half, L}, {at - half, L}}});
    s.sensors.push_back({{{0, at - half}, {L, at - half}, {L, at + half}, {0, at + half}}});
  }
  Random rng(p.seed);
  const double gap = kGapPerRadius * r;
  // The disks never meet one another, so they need not start apart; the lattice just spreads them out.
  for (Vec2 c : jitteredLattice(rng, p.n, {r + gap, r + gap}, {L - r - gap, L - r - gap}, r, gap, "sensors"))
    s.disks.push_back({c, {}, r, 1.0});
  if (!std::isnan(p.speed)) requireSpeed("sensors", p.speed);
  s.speed = p.speed;  // NaN: the scene's default speeds, which differ
  for (DiskStart& d : s.disks) {
    const Vec2 direction = randomDirection(rng);  // first, as in pile()
    d.velocity = (std::isnan(p.speed) ? rng.uniform(10.0, 40.0) : p.speed) * direction;
  }
  return s;
}

Scene crowd(const SceneParams& p) {
  Scene s;
  const double r = 0.5, roomPacking = 0.35, doorwayWidth = 4;
  // Each room a square of side L, the first holding the disks at packing 0.35; at least 16 units, so that
  // the two doorways (4 wide, at L/4 and 3L/4) stay apart and clear of the corners.
  const double L = std::max(16.0, std::sqrt(p.n * kPi * r * r / roomPacking));
  closedBox(s, 0, 0, 2 * L, L);
  s.restitution = 0;
  s.speed = orDefault(p.speed, 3.0);
  requireSpeed("crowd", s.speed);
  s.packing = p.n * kPi * r * r / (2 * L * L);
  Steering& st = s.steering;
  st.enabled = true;
  st.speed = s.speed;
  st.wallX = L;
  st.doorwayY = {0.25 * L, 0.75 * L};
  st.doorwayHalfWidth = 0.5 * doorwayWidth;
  st.goal = {1.5 * L, 0.5 * L};
  const double h = st.doorwayHalfWidth;
  s.walls.push_back({{L, 0}, {L, st.doorwayY[0] - h}, true});
  s.walls.push_back({{L, st.doorwayY[0] + h}, {L, st.doorwayY[1] - h}, true});
  s.walls.push_back({{L, st.doorwayY[1] + h}, {L, L}, true});
  Random rng(p.seed);
  const double gap = kGapPerRadius * r;
  for (Vec2 c : jitteredLattice(rng, p.n, {r + gap, r + gap}, {L - r - gap, L - r - gap}, r, gap, "crowd"))
    s.disks.push_back({c, {}, r, 1.0});
  std::vector<Vec2> positions, velocities;
  for (const DiskStart& d : s.disks) positions.push_back(d.position);
  steerCrowd(s, positions, velocities);
  for (size_t i = 0; i < s.disks.size(); ++i) s.disks[i].velocity = velocities[i];
  return s;
}

}  // namespace

void steerCrowd(const Scene& scene, const std::vector<Vec2>& positions, std::vector<Vec2>& velocities) {
  const Steering& st = scene.steering;
  velocities.resize(positions.size());
  for (size_t i = 0; i < positions.size(); ++i) {
    const Vec2 p = positions[i];
    Vec2 aim = st.goal;
    if (p.x < st.wallX && !st.doorwayY.empty()) {
      double best = st.doorwayY[0];
      for (double y : st.doorwayY)
        if (std::fabs(p.y - y) < std::fabs(p.y - best)) best = y;
      aim = {st.wallX + 1, best};
    }
    const Vec2 to = aim - p;
    const double l = rattle::length(to);
    velocities[i] = l > 0 ? (st.speed / l) * to : Vec2{0, 0};
  }
}

bool inGoalRegion(const Scene& scene, size_t disk, Vec2 p) {
  const rattle::Box& b = scene.bounds;
  return scene.steering.enabled && p.x >= scene.steering.wallX + scene.disks[disk].radius && p.x <= b.max.x &&
         p.y >= b.min.y && p.y <= b.max.y;
}

bool crossedWallOutsideDoorways(const Scene& scene, Vec2 from, Vec2 to) {
  const Steering& st = scene.steering;
  if (!st.enabled || (from.x < st.wallX) == (to.x < st.wallX)) return false;
  const double t = (st.wallX - from.x) / (to.x - from.x);
  const double y = from.y + t * (to.y - from.y);
  for (double d : st.doorwayY)
    if (y >= d - st.doorwayHalfWidth && y <= d + st.doorwayHalfWidth) return false;
  return true;
}

const std::vector<std::string>& sceneNames() {
  static const std::vector<std::string> names = {"gas", "pile", "bullets", "cradle", "sensors", "crowd"};
  return names;
}

int defaultDiskCount(const std::string& scene) {
  if (scene == "bullets") return 100;
  if (scene == "cradle") return 60;
  if (scene == "sensors") return 200;
  return 1000;
}

Scene buildScene(const SceneParams& p) {
  if (p.n < 1) throw SceneError("--n " + std::to_string(p.n) + ": must be at least 1");
  if (!std::isnan(p.packing) && p.name != "gas")
    throw SceneError("--packing: only the gas scene takes a packing fraction (scene " + p.name + ")");
  Scene s;
  if (p.name == "gas")
    s = gas(p);
  else if (p.name == "pile")
    s = pile(p);
  else if (p.name == "bullets")
    s = bullets(p);
  else if (p.name == "cradle")
    s = cradle(p);
  else if (p.name == "sensors")
    s = sensors(p);
  else if (p.name == "crowd")
    s = crowd(p);
  else
    throw SceneError("--scene " + p.name + ": unknown (gas, pile, bullets, cradle, sensors, crowd)");
  s.name = p.name;
  s.seed = p.seed;
  return s;
}

double massOf(const DiskStart& d) { return d.density * kPi * d.radius * d.radius; }

uint64_t sceneHash(const Scene& s) {
  uint64_t h = 0xcbf29ce484222325ull;
  auto mix = [&h](uint64_t v) {
    for (int i = 0; i < 8; ++i) {
      h ^= (v >> (8 * i)) & 0xFF;
      h *= 0x100000001b3ull;
    }
  };
  auto mixD = [&mix](double v) { mix(std::bit_cast<uint64_t>(v)); };
  auto mixV = [&mixD](Vec2 v) {
    mixD(v.x);
    mixD(v.y);
  };
  for (char c : s.name) mix(static_cast<unsigned char>(c));
  mix(s.disks.size());
  for (const DiskStart& d : s.disks) {
    mixV(d.position);
    mixV(d.velocity);
    mixD(d.radius);
    mixD(d.density);
  }
  for (const Wall& w : s.walls) {
    mixV(w.a);
    mixV(w.b);
    if (w.solidEnds) mix(1);  // only then, so that the hashes of the scenes without such walls stay as they were
  }
  for (const SensorStrip& st : s.sensors)
    for (Vec2 v : st.points) mixV(v);
  mixD(s.restitution);
  mixV(s.gravity);
  mixV(s.bounds.min);
  mixV(s.bounds.max);
  mix(s.disksCollide ? 1 : 0);
  if (s.steering.enabled) {  // likewise
    mixD(s.steering.speed);
    mixD(s.steering.wallX);
    for (double y : s.steering.doorwayY) mixD(y);
    mixD(s.steering.doorwayHalfWidth);
    mixV(s.steering.goal);
  }
  return h;
}

}  // namespace rattle_bench
