#!/usr/bin/env python3
"""Crack angles of a Kalthoff-Winkler run, frame by frame (standard library only).

usage: kalthoff_crack_path.py RUN_DIR [--horizon D] [--spacing H] [--frames all|last]

For each notch tip (x = 0.05, y = +-0.025, notch along +x) it follows the damage ridge as
src/horizon/damage/crack_angle.cpp does (the most damaged particle with damage >= 0.35 per
ring of one spacing, within one horizon of the previous ridge point; a Python port of that
fit) and prints three readings of the angle, signed counter-clockwise from +x:
  fit2-8  the line through the tip fitted to the ridge points 2 to 8 horizons away: the
          figure of summary.json fracture.crack_angles_signed_deg;
  fit0-*  the same fit over the whole ridge (every ridge point, however far);
  chord   the line from the tip to the ridge's last point (the direction of the whole
          crack, as one would read it off a picture of the damage);
and the ridge's reach (distance of its last point from the tip). The thesis (sec. 6.2.2)
does not say how or when it measured its Table 6.2 angles; these readings bracket the
plausible ones.
"""
import math
import os
import struct
import sys

sys.dont_write_bytecode = True  # no __pycache__ in scripts/
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from taylor_bar_metrics import read_vtu  # noqa: E402


def ridge(X, dmg, tip, step, reach, r_cap, threshold=0.35):
    n = len(dmg)
    cand = []
    for i in range(n):
        if dmg[i] < threshold:
            continue
        dx, dy = X[3 * i] - tip[0], X[3 * i + 1] - tip[1]
        if dx < 0:  # ahead of the tip: the notch runs along +x
            continue
        r = math.hypot(dx, dy)
        if r > r_cap + step:
            continue
        cand.append((r, dx, dy, dmg[i]))
    cand.sort(key=lambda q: q[0])
    pts = []
    px = py = pr = 0.0
    nxt = 0
    k = 0
    while True:
        lo, hi = k * step, (k + 1) * step
        k += 1
        if lo > r_cap or lo - pr >= reach:
            break
        best = None
        while nxt < len(cand) and cand[nxt][0] < hi:
            q = cand[nxt]
            nxt += 1
            if q[0] < lo:
                continue
            if (q[1] - px) ** 2 + (q[2] - py) ** 2 > reach * reach:
                continue
            if best is None or q[3] > best[3]:
                best = q
        if best is None:
            continue
        px, py, pr = best[1], best[2], best[0]
        pts.append((best[0], best[1], best[2]))
    return pts


def fit(pts, r_min, r_max):
    sel = [(x, y) for r, x, y in pts if r_min <= r <= r_max]
    if len(sel) < 3:
        return None
    sxx = sum(x * x for x, y in sel)
    sxy = sum(x * y for x, y in sel)
    syy = sum(y * y for x, y in sel)
    mx = sum(x for x, y in sel)
    my = sum(y for x, y in sel)
    phi = 0.5 * math.atan2(2 * sxy, sxx - syy)
    ux, uy = math.cos(phi), math.sin(phi)
    if ux * mx + uy * my < 0:
        ux, uy = -ux, -uy
    return math.degrees(math.atan2(uy, ux))


def main():
    args = sys.argv[1:]
    run = args[0]
    opt = {"--horizon": None, "--spacing": None, "--frames": "last"}
    for key in opt:
        if key in args:
            opt[key] = args[args.index(key) + 1]
    fdir = os.path.join(run, "frames")
    frames = sorted(f for f in os.listdir(fdir) if f.endswith(".vtu"))
    if opt["--frames"] == "last":
        frames = frames[-1:]
    for f in frames:
        a = read_vtu(os.path.join(fdir, f))
        X = a["Points"][1]
        dmg = a["damage"][1]
        if opt["--spacing"]:
            h = float(opt["--spacing"])
        else:
            xs = sorted(set(round(X[3 * i], 12) for i in range(len(dmg))))
            h = min(b - c for c, b in zip(xs, xs[1:]))
        d = float(opt["--horizon"]) if opt["--horizon"] else 5 * h
        data = open(os.path.join(fdir, f), "rb").read()
        # TIME is the first appended Float64 (FieldData)
        start = data.index(b"_", data.index(b"<AppendedData")) + 1
        t = struct.unpack_from("<d", data, start + 8)[0]
        out = [f"{f} t={t * 1e6:.1f}us"]
        for tip in ((0.05, 0.025), (0.05, -0.025)):
            pts = ridge(X, dmg, tip, h, d, 1.0)
            a28 = fit(pts, 2 * d, 8 * d)
            aall = fit(pts, 0, 1.0)
            chord = math.degrees(math.atan2(pts[-1][2], pts[-1][1])) if pts else None
            reach = pts[-1][0] if pts else 0.0
            fmt = lambda v: "  none" if v is None else f"{v:+6.1f}"  # noqa: E731
            out.append(f"tip y={tip[1]:+.3f}: fit2-8 {fmt(a28)} fit0-* {fmt(aall)} chord {fmt(chord)}"
                       f" reach {reach * 1e3:5.1f} mm")
        print("  ".join(out))


if __name__ == "__main__":
    main()
