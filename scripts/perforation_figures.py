#!/usr/bin/env python3
"""Figures of the rigid-projectile examples (docs/verification.md "Rigid projectiles").

Reads the history.csv of one or more runs with a projectile and prints, per run, the peak
deceleration along the initial velocity (raw and filtered), the impulse (the integral of
the contact force, trapezoidal over the history rows), the residual speed and the run's
wall time (summary.json), and the relative difference of each figure from the first run.
With --png, draws the filtered deceleration history of each run through `horizon plot`
(one PNG per run; no plotting library needed).

  python3 scripts/perforation_figures.py --name ball RUN_DIR [RUN_DIR ...] [--png docs/images/x]
                                         [--plug-density 2700] [--title TITLE ...]

--title gives each picture's title, one per run in order (default: the run's directory name).
"""
import argparse
import csv
import glob
import re
import struct
import json
import math
import os
import subprocess
import sys


def figures(run, name, density=None):
    rows = list(csv.DictReader(open(os.path.join(run, "history.csv"))))
    summary = json.load(open(os.path.join(run, "summary.json")))
    p = summary["projectiles"][name]
    v0 = [float(rows[0][f"{name}_v{c}"]) for c in "xyz"]
    s0 = math.sqrt(sum(v * v for v in v0))
    e = [v / s0 for v in v0]  # the initial direction of flight
    t = [float(r["time"]) for r in rows]

    def along(r, q):
        return -sum(float(r[f"{name}_{q.format(c)}"]) * e[k] for k, c in enumerate("xyz"))

    dec = [along(r, "a{}") for r in rows]
    dec_f = [along(r, "a{}_filtered") for r in rows]
    force = [along(r, "f{}") for r in rows]
    impulse = sum(0.5 * (force[k] + force[k + 1]) * (t[k + 1] - t[k]) for k in range(len(t) - 1))
    fig = {}
    if density:
        fig["plug_particles"], fig["plug_mass_kg"] = plug(run, p["final_speed"], e, density)
    return fig | {
        "peak_deceleration": max(dec),
        "peak_filtered_deceleration": max(dec_f),
        "time_of_filtered_peak": t[dec_f.index(max(dec_f))],
        "impulse": impulse,
        "impulse_summary": -sum(p["impulse"][k] * e[k] for k in range(3)),
        "residual_speed": p["final_speed"],
        "wall_time_s": summary["wall_time_s"],
        "particles": summary.get("particles"),
        "damage_max": summary.get("damage", {}).get("max"),
    }


def last_frame_fields(run, names):
    """Float64 point arrays of the run's last frame (.vtu, raw appended data)."""
    path = sorted(glob.glob(os.path.join(run, "frames", "frame_*.vtu")))[-1]
    data = open(path, "rb").read()
    start = data.index(b'<AppendedData encoding="raw">')
    start = data.index(b"_", start) + 1
    out = {}
    for m in re.finditer(rb'<DataArray type="Float64" Name="(\w+)" NumberOfComponents="(\d+)"[^>]*offset="(\d+)"', data):
        name = m.group(1).decode()
        if name not in names:
            continue
        at = start + int(m.group(3))
        (size,) = struct.unpack_from("<Q", data, at)
        vals = struct.unpack_from(f"<{size // 8}d", data, at + 8)
        k = int(m.group(2))
        out[name] = [vals[i:i + k] for i in range(0, len(vals), k)] if k > 1 else list(vals)
    return out


def plug(run, speed, e, density):
    """Particles of the last frame moving along the flight at more than half the
    projectile's residual speed: the plug pushed out ahead of it."""
    f = last_frame_fields(run, {"velocity", "volume"})
    n, mass = 0, 0.0
    for v, vol in zip(f["velocity"], f["volume"]):
        if sum(v[k] * e[k] for k in range(3)) > 0.5 * speed:
            n += 1
            mass += density * vol
    return n, mass


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--name", default="ball")
    ap.add_argument("--png", help="prefix of the PNG files (one per run: PREFIX_<run name>.png)")
    ap.add_argument("--horizon", default="build/horizon")
    ap.add_argument("--plug-density", type=float, help="the target's density: report the plug of the last frame")
    ap.add_argument("--title", nargs="+", default=[], help="the pictures' titles, one per run")
    a = ap.parse_args()
    if a.title and len(a.title) != len(a.runs):
        ap.error(f"--title: {len(a.title)} titles for {len(a.runs)} runs")
    first = None
    for index, run in enumerate(a.runs):
        f = figures(run, a.name, a.plug_density)
        print(f"{run}:")
        for k, v in f.items():
            rel = ""
            if first and isinstance(v, float) and first[k]:
                rel = f"  ({100 * (v / first[k] - 1):+.2f} % from the first run)"
            print(f"  {k:28s} {v}{rel}")
        first = first or f
        if a.png:
            out = f"{a.png}_{os.path.basename(os.path.normpath(run))}.png"
            title = ["--title", a.title[index]] if a.title else []
            subprocess.run([a.horizon, "plot", run, "--x", "time", "--y", f"{a.name}_az_filtered", *title,
                            "-o", out], check=True)
            print(f"  figure {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
