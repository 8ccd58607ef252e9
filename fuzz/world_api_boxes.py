# Writes random world_api programs (byte format: fuzz/world_api.cpp) of one closed static box each, with
# points and disks put where the fuzzer seldom puts them: along the walls, in the corners, and made
# overlapping the walls. Run them with the release runner, which is about as fast per input as the
# fuzz build and reads a directory at a time:
#
#   python3 fuzz/world_api_boxes.py --family corners --count 3000 --seed 2 /tmp/boxes
#   RATTLE_WORLD_API_REPORT=budget build/bin/rattle-world-api-inputs --quiet /tmp/boxes
#
# The runner stops at the first violated invariant and names the file before it. The same count, seed
# and family write the same files. fuzz/README.md says more.
import argparse
import math
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from world_api_seeds import HYB, PRE, disk, head, real, step, vec  # noqa: E402

ZERO = bytes([0xF8, 0])  # the first of world_api_seeds.EXTREMES: 0.0 (a circle of radius 0, a point)


def box(rng, kind, centre, hx, hy, count, radius, speed, restitution):
    b = bytes([4, kind]) + vec(*centre, -50, 50) + real(hx, 1, 20) + real(hy, 1, 20) + bytes([count]) + radius
    b += real(speed, 0, 50) + real(restitution, 0, 1)
    # The members' directions and speeds, two bytes each; what fewer members leave is read as more calls.
    return b + bytes(rng.randrange(256) for _ in range(32))


def corners(rng):
    """Predictive, no gravity: a Polyline or Polygon box of points, more points moving into its corners
    at shallow angles (the family that found the escapes of points parted onto walls)."""
    kind = rng.choice([0, 2])
    c = (rng.uniform(-20, 20), rng.uniform(-20, 20))
    hx, hy = rng.uniform(1, 12), rng.uniform(1, 12)
    b = box(rng, kind, c, hx, hy, rng.choice([0, 0, 8, 16]), ZERO, rng.uniform(0, 5),
            rng.choice([0, 1, rng.random()]))
    for _ in range(rng.randint(1, 10)):
        sx, sy = rng.choice([-1, 1]), rng.choice([-1, 1])
        corner = (c[0] + sx * hx, c[1] + sy * hy)
        d = rng.uniform(0.01, 3) if rng.random() < 0.7 else rng.uniform(0.001, 0.05)
        off = rng.uniform(0.0005, 0.5) if rng.random() < 0.5 else rng.uniform(1e-5, 0.01)
        speed = rng.uniform(0.2, 5)
        angle = rng.uniform(-0.3, 0.3) if rng.random() < 0.5 else rng.uniform(-0.02, 0.02)
        if rng.random() < 0.5:
            p = (corner[0] - sx * d, corner[1] - sy * off)
            v = (sx * speed * math.cos(angle), sy * speed * abs(math.sin(angle)))
        else:
            p = (corner[0] - sx * off, corner[1] - sy * d)
            v = (sx * speed * abs(math.sin(angle)), sy * speed * math.cos(angle))
        radius = ZERO if rng.random() < 0.8 else real(rng.uniform(0.05, 1), 0.05, 5)
        b += disk(p, v, radius, rng.choice([0, 0.3, 1, rng.random()]))
    return head(PRE, 0) + b + step(rng.choice([60, 60, 30, 120])) * 20


def mixed(rng):
    """Hybrid or predictive, with or without gravity: a box of any kind, points and disks of all sizes
    near its walls (large ones made through them), and now and then a velocity set between steps."""
    c = (rng.uniform(-30, 30), rng.uniform(-30, 30))
    hx, hy = rng.uniform(1, 8), rng.uniform(1, 8)
    b = box(rng, rng.choice([0, 1, 2]), c, hx, hy, rng.choice([0, 4, 8, 16]),
            rng.choice([ZERO, real(rng.uniform(0.05, 0.5), 0.05, 1)]), rng.uniform(0, 6),
            rng.choice([0, 1, rng.random()]))
    for _ in range(rng.randint(1, 8)):
        p = (c[0] + rng.uniform(-hx, hx), c[1] + rng.uniform(-hy, hy))
        if rng.random() < 0.6:
            sx, sy = rng.choice([-1, 1]), rng.choice([-1, 1])
            if rng.random() < 0.5:
                p = (c[0] + sx * (hx - rng.uniform(0, 0.3)), p[1])
            else:
                p = (p[0], c[1] + sy * (hy - rng.uniform(0, 0.3)))
        v = (rng.uniform(-5, 5), rng.uniform(-5, 5))
        radius = rng.choice([ZERO, real(rng.uniform(0.05, 0.3), 0.05, 5), real(rng.uniform(0.3, 3), 0.05, 5)])
        b += disk(p, v, radius, rng.choice([0, 0.5, 1, rng.random()]))
    dt = rng.choice([60, 60, 30, 120, 20])
    for _ in range(20):
        if rng.random() < 0.1:
            b += bytes([8, rng.randrange(256)]) + vec(rng.uniform(-8, 8), rng.uniform(-8, 8), -50, 50)
        b += step(dt)
    return head(rng.choice([HYB, PRE]), rng.choice([0, 1])) + b


FAMILIES = {"corners": corners, "mixed": mixed}


def main():
    parser = argparse.ArgumentParser(description="Writes random world_api programs of one closed box each.")
    parser.add_argument("out", help="directory to write the programs into (made if missing)")
    parser.add_argument("--family", choices=sorted(FAMILIES), default="mixed",
                        help="what goes into the box (default: mixed)")
    parser.add_argument("--count", type=int, default=1000, help="how many programs (default: 1000)")
    parser.add_argument("--seed", type=int, default=1, help="the random seed (default: 1)")
    args = parser.parse_args()
    if args.count < 1:
        parser.error(f"--count {args.count}: must be at least 1")
    os.makedirs(args.out, exist_ok=True)
    rng = random.Random(args.seed)
    for k in range(args.count):
        with open(os.path.join(args.out, f"{args.family}-{k:06d}"), "wb") as f:
            f.write(FAMILIES[args.family](rng))
    print(f"world_api_boxes: {args.count} {args.family} programs in {args.out}")


if __name__ == "__main__":
    main()
