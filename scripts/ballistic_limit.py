#!/usr/bin/env python3
"""Residual velocity against impact velocity, and the ballistic limit (standard library only).

usage: ballistic_limit.py [--deck examples/ballistic_plate.yaml] [--speeds 200,350,500,650,800]
                          [--coarsen F] [--threads N] [--out out/ballistic] [--png docs/images/ballistic_plate.png]
                          [--horizon build/horizon] [--body sphere] [--axis z]

For each impact speed v_i the deck is copied with the projectile's initial velocity (the
`velocity: [0, 0, -V]` line of `initial_conditions`) replaced by -v_i and run with
`horizon run`; the residual velocity v_r is the projectile's centre-of-mass velocity along
the impact direction at the end of the run (history.csv's BODY_vz, last row), taken as 0
when the projectile has stopped or rebounds (v_r <= 0: it did not perforate).
Writes OUT/residual.csv (impact_velocity, residual_velocity), plots it with `horizon plot`
and fits the Lambert-Jonas relation (Lambert and Jonas, BRL-R-1852, 1976)
    v_r = a (v_i^p - v_bl^p)^(1/p)  for v_i > v_bl,  0 below,
by least squares over a grid of (v_bl, p) with a in closed form; prints a, p and the
ballistic limit v_bl. With fewer than two perforations v_bl is bracketed instead: it
lies between the highest speed that stopped and the lowest that perforated.
"""
import argparse
import csv
import os
import re
import subprocess
import sys


def run_one(args, v):
    deck = open(args.deck).read()
    pattern = re.compile(r"(velocity:\s*\[\s*0\s*,\s*0\s*,\s*)-?[0-9.eE+-]+(\s*\])")
    if not pattern.search(deck):
        sys.exit("no 'velocity: [0, 0, -V]' line in " + args.deck)
    out = os.path.join(args.out, "v%g" % v)
    os.makedirs(out, exist_ok=True)
    deck = pattern.sub(lambda m: m.group(1) + ("-%g" % v) + m.group(2), deck, count=1)
    path = os.path.join(out, "deck.yaml")
    open(path, "w").write(deck)
    cmd = [args.horizon, "run", path, "-o", out, "-q", "--threads", str(args.threads)]
    if args.coarsen != 1:
        cmd += ["--coarsen", str(args.coarsen)]
    subprocess.run(cmd, check=True)
    rows = list(csv.DictReader(open(os.path.join(out, "history.csv"))))
    col = "%s_v%s" % (args.body, args.axis)
    if col not in rows[-1]:
        sys.exit("no column %s in %s/history.csv" % (col, out))
    return -float(rows[-1][col]), rows


def lambert_jonas(data):
    """Least-squares (a, p, v_bl) of v_r = a (v^p - v_bl^p)^(1/p) (0 below v_bl)."""
    vmax = max(v for v, _ in data)
    best = None
    for ib in range(1, 1000):
        vbl = vmax * ib / 1000.0
        for ip in range(10, 61):
            p = ip / 10.0
            g = [max(v ** p - vbl ** p, 0.0) ** (1.0 / p) for v, _ in data]
            gg = sum(x * x for x in g)
            if gg == 0:
                continue
            a = min(1.0, sum(x * r for x, (_, r) in zip(g, data)) / gg)
            err = sum((a * x - r) ** 2 for x, (_, r) in zip(g, data))
            if best is None or err < best[0]:
                best = (err, a, p, vbl)
    return best


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--deck", default="examples/ballistic_plate.yaml")
    ap.add_argument("--speeds", default="200,350,500,650,800")
    ap.add_argument("--coarsen", type=float, default=1.0)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--out", default="out/ballistic")
    ap.add_argument("--png", default="docs/images/ballistic_plate.png")
    ap.add_argument("--horizon", default="build/horizon")
    ap.add_argument("--body", default="sphere")
    ap.add_argument("--axis", default="z")
    args = ap.parse_args()
    speeds = [float(s) for s in args.speeds.split(",")]
    data = []
    for v in speeds:
        along, _ = run_one(args, v)
        vr = max(along, 0.0)
        data.append((v, vr))
        print("impact %7.1f m/s  residual %7.1f m/s  (centre-of-mass velocity along the impact %+.1f)" % (v, vr, along),
              flush=True)
    table = os.path.join(args.out, "residual.csv")
    with open(table, "w") as f:
        f.write("impact_velocity,residual_velocity\n")
        for v, r in data:
            f.write("%g,%g\n" % (v, r))
    if args.png:
        subprocess.run([args.horizon, "plot", table, "--x", "impact_velocity", "--y", "residual_velocity",
                        "--x-label", "Impact velocity (m/s)", "--y-label", "Residual velocity (m/s)",
                        "-o", args.png], check=True)
    stopped = [v for v, r in data if r == 0]
    through = [v for v, r in data if r > 0]
    if stopped and through:
        print("ballistic limit bracket: %.0f < v_bl < %.0f m/s" % (max(stopped), min(through)))
    if len(through) >= 2:
        err, a, p, vbl = lambert_jonas(data)
        print("Lambert-Jonas fit: a = %.3f, p = %.1f, v_bl = %.0f m/s (rms residual %.1f m/s)"
              % (a, p, vbl, (err / len(data)) ** 0.5))


if __name__ == "__main__":
    main()
