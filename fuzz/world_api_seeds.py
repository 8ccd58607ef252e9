# Writes the hand-written seed programs of fuzz/corpus/world_api/ (byte format: fuzz/world_api.cpp).
# usage: python3 fuzz/world_api_seeds.py fuzz/corpus/world_api
import os, sys
def real(v, lo, hi):
    q = round((v - lo) / (hi - lo) * (0xF8 * 256 - 1))
    q = max(0, min(0xF8 * 256 - 1, q))
    return bytes([q >> 8, q & 0xFF])
def vec(x, y, lo, hi): return real(x, lo, hi) + real(y, lo, hi)
DT = {0: 0, 240: 1, 120: 2, 60: 3, 30: 5, 20: 6, 10: 7}
def step(per_second=60): return bytes([12, DT[per_second]])
# r: a radius in [0.05, 5], or its two bytes already encoded (extreme(0.0) for a point).
def disk(p, v, r, e=0.0):
    radius = r if isinstance(r, bytes) else real(r, 0.05, 5)
    return bytes([0]) + vec(*p, -100, 100) + vec(*v, -50, 50) + radius + real(e, 0, 1) + bytes([0, 0])
def body(t, p, v=(0, 0)):
    b = bytes([2, t]) + vec(*p, -100, 100)
    return b + (bytes([0]) if t == 0 else vec(*v, -50, 50))
def typebyte(g, sensor):
    for x in range(256):
        if x % 5 == g and bool(x & 0x20) == sensor: return x
def fixture(bodyindex, g, args, sensor=False, e=0.0):
    return bytes([3, bodyindex, typebyte(g, sensor)]) + args + bytes([0]) + real(e, 0, 1) + bytes([0])
def rect(c, w, h): return bytes([0]) + vec(*c, -10, 10) + real(w, 0.05, 10) + real(h, 0.05, 10)
def circle(r): return bytes([0]) + real(r, 0.05, 5)
def segment(a, b): return vec(*a, -20, 20) + vec(*b, -20, 20)
def container(kind, c, hx, hy, n, r, speed, e):
    b = bytes([4, kind]) + vec(*c, -50, 50) + real(hx, 1, 20) + real(hy, 1, 20) + bytes([n]) + real(r, 0.05, 1) + real(speed, 0, 50) + real(e, 0, 1)
    for i in range(n): b += bytes([(i * 37) % 256, 128 + (i * 53) % 128])
    return b
def query(kind, args=b""): return bytes([14, kind, 1]) + args
EXTREMES = [0.0, -0.0, 1e-300, -1e-12, 1e300, -1e300, "inf", "-inf", "nan", 1e9, -1e9, "denorm_min", "max", -1.0, 1.5, 1e-12]
def extreme(v): return bytes([0xF8, EXTREMES.index(v)])
def set_velocity(bodyindex, vx, vy): return bytes([8, bodyindex]) + vx + vy
def point_fixture(bodyindex, at=(0, 0)): return bytes([3, bodyindex, typebyte(0, False)]) + vec(*at, -5, 5) + bytes([0]) + real(0, 0, 1) + bytes([0])
HYB, DIS, PRE = 0, 1, 2
def head(mode, gravity): return bytes([mode + 3 * gravity])
def main(out):
  seeds = {
  # A gas in a Polyline box, restitution 1: energy and escape checks at their strictest.
  "hybrid-gas-in-polyline-box": head(HYB, 0) + container(0, (0, 0), 4, 4, 16, 0.3, 20, 1.0) + step(60) * 10 + query(1, vec(-10, 0, -100, 100) + vec(20, 0, -200, 200)) + step(30) * 5,
  # A pile poured into a ring of polygons under gravity.
  "hybrid-gravity-pile-in-polygon-ring": head(HYB, 1) + container(2, (0, 0), 3, 6, 16, 0.4, 2, 0.5) + step(30) * 20,
  # Four segments, the discrete mode, slow disks.
  "discrete-gas-in-segment-box": head(DIS, 0) + container(1, (10, -10), 5, 5, 12, 0.5, 3, 1.0) + step(60) * 15,
  "discrete-gravity-pile": head(DIS, 1) + container(0, (0, 0), 4, 8, 16, 0.3, 1, 0.3) + step(30) * 20,
  # A kinematic piston drives a disk toward a static segment (no container: crushing is allowed).
  "predictive-piston": head(PRE, 0) + body(2, (5, 0), (-2, 0)) + fixture(0, 4, rect((-0.5, -3), 1, 6)) + disk((2.5, 0), (0, 0), 0.5) + body(0, (0, 0)) + fixture(2, 2, segment((0, -5), (0, 5))) + step(30) * 20,
  "predictive-gravity-pile": head(PRE, 1) + container(0, (0, 0), 3, 10, 16, 0.4, 1, 0.5) + step(20) * 20,
  # A sensor on a static body, disks crossing it, a body destroyed between steps, queries.
  "hybrid-sensor-and-destroy": head(HYB, 0) + body(0, (0, 0)) + fixture(0, 1, circle(2), sensor=True) + disk((-5, 0), (20, 0), 0.3) + disk((5, 0.5), (-20, 0), 0.3) + step(60) * 3 + query(5, bytes([0])) + bytes([5, 1]) + step(60) * 3 + query(3, vec(0, 0, -100, 100) + real(3, 0, 20)) + step(60) * 3,
  "predictive-sensor-and-filter": head(PRE, 0) + body(0, (0, 0)) + fixture(0, 4, rect((-1, -1), 2, 2), sensor=True) + disk((-5, 0), (10, 0), 0.3) + step(60) * 5 + bytes([11, 2, 200, 1, 0, 1]) + step(60) * 5,
}
  for name, data in seeds.items():
    open(os.path.join(out, name), "wb").write(data)
    print(name, len(data))

if __name__ == "__main__":
    main(sys.argv[1])
