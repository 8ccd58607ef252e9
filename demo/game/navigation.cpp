#include "game/navigation.h"

#include <cmath>
#include <limits>

namespace rts {
namespace {

bool insideConvex(const std::vector<Vec2>& poly, Vec2 p) {
  bool pos = false, neg = false;
  for (size_t i = 0; i < poly.size(); ++i) {
    double c = rattle::cross(poly[(i + 1) % poly.size()] - poly[i], p - poly[i]);
    pos |= c > 0;
    neg |= c < 0;
  }
  return !(pos && neg);
}

Vec2 normalized(Vec2 v) {
  double l = rattle::length(v);
  return l > 0 ? v * (1.0 / l) : Vec2{1, 0};
}

}  // namespace

Navigation::Navigation(const Map& map) {
  for (const MapRoom& r : map.rooms) rooms_.push_back(r.polygon);
  auto addPortal = [&](Vec2 a, Vec2 b, double probe, int doorway, int gate) {
    Portal p;
    p.a = a;
    p.b = b;
    p.middle = (a + b) * 0.5;
    p.along = normalized(b - a);
    p.normal = rattle::perpendicular(p.along);
    p.halfWidth = rattle::length(b - a) * 0.5;
    p.region[0] = regionOf(p.middle - p.normal * probe);
    p.region[1] = regionOf(p.middle + p.normal * probe);
    p.doorway = doorway;
    p.gate = gate;
    portals_.push_back(p);
  };
  for (size_t i = 0; i < map.doorways.size(); ++i) addPortal(map.doorways[i].a, map.doorways[i].b, 1.0, int(i), -1);
  for (size_t i = 0; i < map.gates.size(); ++i) {
    // A gate slides along its length: the opening runs along the slide direction, through the middle
    // of the closed gate, and is crossed at right angles to it.
    const MapGate& g = map.gates[i];
    Vec2 u = normalized(g.openOffset), n = rattle::perpendicular(u), c{0, 0};
    for (Vec2 p : g.polygon) c += p;
    c = c * (1.0 / double(g.polygon.size()));
    double halfLength = 0, halfThickness = 0;
    for (Vec2 p : g.polygon) {
      halfLength = std::max(halfLength, std::fabs(rattle::dot(p - c, u)));
      halfThickness = std::max(halfThickness, std::fabs(rattle::dot(p - c, n)));
    }
    c += g.origin;
    addPortal(c - u * halfLength, c + u * halfLength, halfThickness + 1.0, -1, int(i));
  }
}

int Navigation::regionOf(Vec2 p) const {
  for (size_t i = 0; i < rooms_.size(); ++i) {
    if (insideConvex(rooms_[i], p)) return int(i);
  }
  return fieldRegion();
}

int Navigation::side(int portal, Vec2 p) const {
  const Portal& q = portals_[size_t(portal)];
  return rattle::dot(p - q.a, q.normal) > 0 ? 1 : -1;
}

std::vector<Leg> Navigation::route(Vec2 from, Vec2 to, const std::vector<bool>& gateOpen, bool* found) const {
  const int start = regionOf(from), goal = regionOf(to);
  if (found) *found = true;
  if (start == goal) return {};
  // Dijkstra over portals: the cost of a portal is the length of the best path of straight lines from
  // `from` through portal midpoints to it. Ties keep the lower index, so the result is reproducible.
  const size_t n = portals_.size();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> dist(n, inf);
  std::vector<int> previous(n, -1), enteredRegion(n, -1);
  std::vector<bool> done(n, false);
  auto usable = [&](size_t i) {
    const Portal& p = portals_[i];
    return p.region[0] != p.region[1] && (p.gate < 0 || (size_t(p.gate) < gateOpen.size() && gateOpen[size_t(p.gate)]));
  };
  for (size_t i = 0; i < n; ++i) {
    if (!usable(i)) continue;
    const Portal& p = portals_[i];
    if (p.region[0] == start || p.region[1] == start) {
      dist[i] = rattle::length(p.middle - from);
      enteredRegion[i] = p.region[0] == start ? p.region[1] : p.region[0];
    }
  }
  double bestTotal = inf;
  int bestLast = -1;
  for (;;) {
    int u = -1;
    for (size_t i = 0; i < n; ++i) {
      if (!done[i] && dist[i] < inf && (u < 0 || dist[i] < dist[size_t(u)])) u = int(i);
    }
    if (u < 0) break;
    done[size_t(u)] = true;
    const Portal& pu = portals_[size_t(u)];
    const int region = enteredRegion[size_t(u)];
    if (region == goal) {
      double total = dist[size_t(u)] + rattle::length(to - pu.middle);
      if (total < bestTotal) {
        bestTotal = total;
        bestLast = u;
      }
      continue;
    }
    for (size_t v = 0; v < n; ++v) {
      if (done[v] || !usable(v)) continue;
      const Portal& pv = portals_[v];
      if (pv.region[0] != region && pv.region[1] != region) continue;
      double d = dist[size_t(u)] + rattle::length(pv.middle - pu.middle);
      if (d < dist[v]) {
        dist[v] = d;
        previous[v] = u;
        enteredRegion[v] = pv.region[0] == region ? pv.region[1] : pv.region[0];
      }
    }
  }
  if (bestLast < 0) {
    if (found) *found = false;
    return {};
  }
  std::vector<Leg> legs;
  for (int p = bestLast; p >= 0; p = previous[size_t(p)]) {
    const Portal& q = portals_[size_t(p)];
    legs.insert(legs.begin(), Leg{p, q.region[1] == enteredRegion[size_t(p)] ? 1 : -1});
  }
  return legs;
}

}  // namespace rts
