#!/usr/bin/env python3
"""Control cases that explain where Horizon and LAMMPS differ on in.peri.ves and
in.peri.eps (docs/benchmarks_ves_eps.md). One thread, one run of each case.

1. `limits`: LAMMPS's example deck with the model reduced to the linear peridynamic solid
   (LPS) in three ways: peri/lps itself; peri/ves with lambda_i = 0 (no viscous part);
   peri/eps with a yield stress of 1e30 Pa (never yields). By the models' definitions the
   three are the same material. The same three limits of Horizon's decks (lps.yaml;
   ves.yaml with the relaxing fraction 0; eps.yaml with yield stress 1e30) with --horizon.
   Mean damage and kinetic energy at steps 250, 500, 750, 1000.
2. `momentum`: a free cylinder (the example's, no indenter, no breaking: s00 = 1) given
   the velocity field v_y = 10 sin(pi y / 5 mm) m/s, 200 steps of 0.1 us. No external
   force acts, so the total momentum sum rho V v must not change. LAMMPS prints
   sum rho v_y (its `mass` is the density; every particle has the same volume).

   bench/lammps/ves_eps_checks.py [--horizon build/horizon] [--only limits|momentum]
"""
import argparse
import csv
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
VOLUME = 1.25e-10
STEPS = (250, 500, 750, 1000)
COEFF = "14.9e9 14.9e9 0.0015001"

LIMITS = [  # name, pair_style, pair_coeff tail after "K G delta"
    ("peri/lps", "peri/lps", "0.0005 0.25"),
    ("peri/ves lambda_i=0", "peri/ves", "0.0005 0.25 0.0 0.001"),
    ("peri/eps yield 1e30", "peri/eps", "0.0005 0.25 1.0e30"),
    ("peri/ves (example)", "peri/ves", "0.0005 0.25 0.5 0.001"),
    ("peri/ves tau_i=1 s", "peri/ves", "0.0005 0.25 0.5 1.0"),
    ("peri/eps (example)", "peri/eps", "0.0005 0.25 10.0e8"),
]


def examples_dir():
    out = subprocess.run(["dpkg", "-L", "lammps-examples"], stdout=subprocess.PIPE, text=True).stdout
    for line in out.splitlines():
        if line.endswith("/peri/in.peri.ves"):
            return os.path.dirname(line)
    sys.exit("LAMMPS's examples/peri not found (apt-get install lammps lammps-examples)")


def run(cmd, cwd):
    p = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       env=dict(os.environ, OMP_NUM_THREADS="1"))
    if p.returncode != 0:
        sys.exit(f"failed: {' '.join(cmd)}\n{p.stdout[-3000:]}")
    return p.stdout


def lammps_deck(src, style, tail, thermo_every=250, extra=None, drop_indenter=False):
    out = []
    for line in open(src).read().splitlines():
        if re.match(r"^\s*pair_style\s", line):
            line = f"pair_style      {style}"
        elif re.match(r"^\s*pair_coeff\s", line):
            line = f"pair_coeff      * * {COEFF} {tail}"
        elif drop_indenter and re.match(r"^\s*fix\s+2\s+all\s+indent", line):
            continue
        elif re.match(r"^\s*velocity\s", line) and extra is not None:
            line = extra["velocity"]
        elif re.match(r"^\s*thermo\s+\d+", line):
            if extra is not None:
                out += extra["thermo"]
                continue
            line = ("compute         dmean all reduce ave c_1\ncompute         kea all ke\n"
                    "thermo_style    custom step c_kea c_dmean\n"
                    f"thermo          {thermo_every}\nthermo_modify   format float %.10g")
        elif re.match(r"^\s*run\s", line) and extra is not None:
            line = f"run             {extra['steps']}"
        out.append(line)
    return "\n".join(out) + "\n"


def thermo_rows(log, header):
    rows = {}
    block = log[log.index(header):]
    for line in block.splitlines()[1:]:
        parts = line.split()
        if not parts or not parts[0].isdigit():
            break
        rows[int(parts[0])] = [float(x) for x in parts[1:]]
    return rows


def limits(ex, work, horizon):
    print("== limits: the model reduced to the LPS; kinetic energy [J] and mean damage")
    print(f"{'case':34s}" + "".join(f"{'KE ' + str(s):>14s}{'D ' + str(s):>10s}" for s in STEPS))
    for name, style, tail in LIMITS:
        deck = os.path.join(work, "in.limit")
        open(deck, "w").write(lammps_deck(os.path.join(ex, "in.peri.ves"), style, tail))
        log = run(["lmp", "-in", deck, "-log", "none", "-nocite"], work)
        rows = thermo_rows(log, "Step c_kea c_dmean")
        print(f"{'LAMMPS ' + name:34s}" + "".join(f"{rows[s][0] * VOLUME:14.6e}{rows[s][1]:10.6f}" for s in STEPS),
              flush=True)
    if not horizon:
        return
    import yaml
    cases = [("lps.yaml", {}), ("ves.yaml relaxed fraction 0", {"ves": 0.0}), ("eps.yaml yield 1e30", {"eps": 1e30}),
             ("ves.yaml (as posed)", {"ves": None}), ("ves.yaml tau 1 s", {"ves_tau": 1.0}),
             ("eps.yaml (as posed)", {"eps": None})]
    for name, change in cases:
        base = name.split()[0]
        d = yaml.safe_load(open(os.path.join(HERE, base)))
        mat = d["materials"]["target"]
        if change.get("ves") is not None:
            mat[VES_FRACTION_KEY] = change["ves"]
        if change.get("ves_tau") is not None:
            mat[VES_TIME_KEY] = change["ves_tau"]
        if change.get("eps") is not None:
            mat[EPS_YIELD_KEY] = change["eps"]
        deck = os.path.join(work, "limit.yaml")
        yaml.safe_dump(d, open(deck, "w"))
        outdir = os.path.join(work, "hz")
        run([horizon, "run", deck, "--threads", "1", "--quiet", "--output", outdir], work)
        rows = {}
        with open(os.path.join(outdir, "history.csv")) as f:
            for r in csv.DictReader(f):
                rows[int(r["step"])] = (float(r["kinetic_energy"]), float(r["damage_mean"]))
        print(f"{'Horizon ' + name:34s}" + "".join(f"{rows[s][0]:14.6e}{rows[s][1]:10.6f}" for s in STEPS),
              flush=True)


def momentum(ex, work):
    print("\n== momentum: free cylinder, no indenter, no breaking, v_y = 10 sin(pi y/5 mm) m/s, 200 steps")
    extra = {
        "velocity": ("variable        vy0 atom 10.0*sin(PI*y/0.005)\n"
                     "velocity        all set 0.0 v_vy0 0.0 sum no units box"),
        "thermo": ["variable        py equal vcm(all,y)*mass(all)*1.25e-10",
                   "variable        pabs atom abs(vy)*mass*1.25e-10",
                   "compute         pa all reduce sum v_pabs",
                   "compute         kea all ke",
                   "thermo_style    custom step v_py c_pa c_kea",
                   "thermo          50",
                   "thermo_modify   format float %.10g"],
        "steps": 200,
    }
    print(f"{'case':24s}{'p_y(0) [kg m/s]':>18s}{'p_y(200)':>16s}{'sum|rho V v_y|(0)':>20s}{'drift/sum':>12s}")
    for name, style, tail in [("peri/lps", "peri/lps", "1.0 0.25"), ("peri/ves lambda_i=0", "peri/ves", "1.0 0.25 0.0 0.001"),
                              ("peri/eps yield 1e30", "peri/eps", "1.0 0.25 1.0e30")]:
        deck = os.path.join(work, "in.mom")
        open(deck, "w").write(lammps_deck(os.path.join(ex, "in.peri.ves"), style, tail, extra=extra, drop_indenter=True))
        log = run(["lmp", "-in", deck, "-log", "none", "-nocite"], work)
        rows = thermo_rows(log, "Step v_py c_pa c_kea")
        p0, p1, pa = rows[0][0], rows[200][0], rows[0][1]
        print(f"{'LAMMPS ' + name:24s}{p0:18.6e}{p1:16.6e}{pa:20.6e}{(p1 - p0) / pa:12.3e}", flush=True)


# Horizon's deck keys of the two models (docs/models/*.md on branch models-eps).
VES_FRACTION_KEY = "lambda_1"
VES_TIME_KEY = "tau_1"
EPS_YIELD_KEY = "yield_stress"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--horizon", default="", help="the horizon executable (leave out: LAMMPS alone)")
    ap.add_argument("--only", choices=["limits", "momentum"], default=None)
    args = ap.parse_args()
    ex = examples_dir()
    work = tempfile.mkdtemp(prefix="ves_eps_checks_")
    horizon = os.path.abspath(args.horizon) if args.horizon else ""
    if args.only in (None, "limits"):
        limits(ex, work, horizon)
    if args.only in (None, "momentum"):
        momentum(ex, work)
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
