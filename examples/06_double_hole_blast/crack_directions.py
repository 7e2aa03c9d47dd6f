#!/usr/bin/env python3
"""Crack directions and linking of the double-hole blast, from a run's breaks.csv.

For each hole it bins the bonds broken between 30 and 80 mm from the hole's centre by the
direction from the centre (10-degree sectors centred on 0, 10, 20, ... degrees; 0 points along
+x, to the right, 90 up) and
lists the sectors that hold a local maximum of at least 0.3 times the largest count: the directions
of the crack branches. It also says whether, and when, the holes are linked: every 5 mm of the
segment between the two rims holds a broken bond within 5 mm of the centre line.

    python3 examples/06_double_hole_blast/crack_directions.py out/blast/breaks.csv
"""
import argparse
import csv
import math

HOLES = [(0.2, 0.125), (0.3, 0.125)]  # centres (m), as in blast.geo
RADIUS = 0.005
SECTOR = 10  # degrees


def branches(counts):
    """Centres (degrees, -180..170) of sectors that are local maxima of at least 0.3 times the largest."""
    n, top = len(counts), max(counts) if counts else 0
    out = []
    for k, c in enumerate(counts):
        if top == 0 or c < 0.3 * top:
            continue
        if c >= counts[(k - 1) % n] and c > counts[(k + 1) % n]:
            out.append(-180 + SECTOR * k)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("breaks", help="breaks.csv of a run of scene.toml or quick.toml")
    args = ap.parse_args()
    with open(args.breaks, newline="") as f:
        rows = [(float(r["time"]), float(r["x"]), float(r["y"]), int(r["mode"])) for r in csv.DictReader(f)]
    print(f"broken bonds: {len(rows)} ({sum(1 for r in rows if r[3] == 1)} in tension, "
          f"{sum(1 for r in rows if r[3] == 2)} in shear)")
    if not rows:
        return
    print(f"first break: {rows[0][0] * 1e6:.1f} us")
    for name, (cx, cy) in zip(["left hole", "right hole"], HOLES):
        counts = [0] * (360 // SECTOR)
        for _, x, y, _ in rows:
            r = math.hypot(x - cx, y - cy)
            if 0.030 <= r <= 0.080:
                a = math.degrees(math.atan2(y - cy, x - cx))
                counts[int(round((a + 180) / SECTOR)) % len(counts)] += 1  # sectors centred on 0, 10, ...
        print(f"{name}: crack branches at {branches(counts)} degrees "
              f"({sum(counts)} broken bonds 30-80 mm from its centre)")
    # linking: 5 mm bins along the segment between the rims
    lo, hi = HOLES[0][0] + RADIUS, HOLES[1][0] - RADIUS
    bins = int(round((hi - lo) / 0.005))
    first = [math.inf] * bins
    for t, x, y, _ in rows:
        if lo <= x < hi and abs(y - HOLES[0][1]) < 0.005:
            k = min(int((x - lo) / 0.005), bins - 1)
            first[k] = min(first[k], t)
    filled = sum(1 for t in first if math.isfinite(t))
    if filled == bins:
        print(f"holes linked at {max(first) * 1e6:.1f} us")
    else:
        print(f"holes not linked: {filled} of {bins} stretches of 5 mm between them hold a crack")


if __name__ == "__main__":
    main()
