#!/usr/bin/env python3
"""Control cases that explain where Horizon and LAMMPS differ on in.peri.ves and
in.peri.eps (docs/benchmarks.md ("the viscoelastic and elastic-plastic examples")). One thread, one run of each case.

1. `limits`: LAMMPS's example deck with the model reduced to the linear peridynamic solid
   (LPS) in three ways: peri/lps itself; peri/ves with lambda_i = 0 (no viscous part);
   peri/eps with a yield stress of 1e30 Pa (never yields). By the models' definitions the
   three are the same material. The same three limits of Horizon's decks (lps.yaml;
   ves.yaml with the relaxing fraction 0; eps.yaml with yield stress 1e30) with --horizon.
   Mean damage and kinetic energy at steps 250, 500, 750, 1000.
2. `momentum`: a free cylinder (the example's, no indenter, no breaking: s00 = 1) given
   the velocity field v_y = 10 sin(pi y / 5 mm) m/s, 200 steps of 0.1 us (LAMMPS: after
   one step at rest, see lammps_deck). No external
   force acts, so the total momentum sum rho V v must not change. LAMMPS prints
   sum rho v_y (its `mass` is the density; every particle has the same volume); Horizon's
   is summed from the first and last frames (velocity and volume arrays).

3. `shear`: a 10 x 10 x 10 particle block (the example's lattice, material and horizon;
   no breaking) given the homogeneous shear u = (gamma/2)(y, x, 0), gamma = 1e-4, and
   held: the force on the top four layers (y >= 2.9 mm) at once and its relaxation over
   3 ms in 300 steps of 10 us, against the standard linear solid
   F(t)/F(0) = (1 - lambda) + lambda exp(-t/tau) (LAMMPS: the shear is applied between
   two steps, so its first step is a ramp over dt; the SLS value printed is the one for
   that ramp, lambda_inf + lambda (tau/dt)(1 - e^(-h)) e^(-(n-1)h)/(...), h = dt/tau).

   bench/lammps/ves_eps_checks.py [--horizon build/horizon] [--only limits|momentum|shear]
                                  [--lammps-form PATCHED_HORIZON]

`--lammps-form` names a Horizon built with bench/lammps/lammps_asymmetry.patch (an
experiment, never merged: the viscoelastic model with LAMMPS peri/ves's form of the bond
force); `limits` then also runs ves.yaml and ves.yaml with lambda_1 = 0 in that form.
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
        elif re.match(r"^\s*thermo\s+\d+", line):
            if extra is not None:
                out += extra["thermo"]
                continue
            line = ("compute         dmean all reduce ave c_1\ncompute         kea all ke\n"
                    "thermo_style    custom step c_kea c_dmean\n"
                    f"thermo          {thermo_every}\nthermo_modify   format float %.10g")
        elif re.match(r"^\s*run\s", line) and extra is not None:
            # One step at rest first: LAMMPS PERI sets each particle's critical stretch s0
            # in the first force pass that has the bond partners, so in the first step of
            # a first run s0 is 0 and every bond in tension breaks (harmless in the
            # examples, where nothing moves in step 1; not here).
            line = f"run             1\n{extra['velocity']}\nrun             {extra['steps']}"
        out.append(line)
    return "\n".join(out) + "\n"


def thermo_rows(log, header, last=False):
    rows = {}
    block = log[(log.rindex if last else log.index)(header):]
    for line in block.splitlines()[1:]:
        parts = line.split()
        if not parts or not parts[0].isdigit():
            break
        rows[int(parts[0])] = [float(x) for x in parts[1:]]
    return rows


def horizon_rows(binary, deck, work, env=None):
    outdir = os.path.join(work, "hz")
    p = subprocess.run([binary, "run", deck, "--threads", "1", "--quiet", "--output", outdir], cwd=work,
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       env=dict(os.environ, OMP_NUM_THREADS="1", **(env or {})))
    if p.returncode != 0:
        sys.exit(f"failed: {binary} run {deck}\n{p.stdout[-3000:]}")
    rows = {}
    with open(os.path.join(outdir, "history.csv")) as f:
        for r in csv.DictReader(f):
            rows[int(r["step"])] = (float(r["kinetic_energy"]), float(r["damage_mean"]))
    return rows


def limits(ex, work, horizon, lammps_form=""):
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
    cases = [("lps.yaml", {}), ("ves.yaml lambda_1=0", {"ves": 0.0}), ("eps.yaml yield 1e30", {"eps": 1e30}),
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
        rows = horizon_rows(horizon, deck, work)
        print(f"{'Horizon ' + name:34s}" + "".join(f"{rows[s][0]:14.6e}{rows[s][1]:10.6f}" for s in STEPS),
              flush=True)
    if not lammps_form:
        return
    for name, lam in [("ves.yaml", None), ("ves.yaml lambda_1=0", 0.0)]:
        d = yaml.safe_load(open(os.path.join(HERE, "ves.yaml")))
        if lam is not None:
            d["materials"]["target"][VES_FRACTION_KEY] = lam
        deck = os.path.join(work, "limit.yaml")
        yaml.safe_dump(d, open(deck, "w"))
        rows = horizon_rows(lammps_form, deck, work, {"HORIZON_LAMMPS_ASYM": "1"})
        print(f"{'Horizon, LAMMPS form, ' + name:34s}" + "".join(f"{rows[s][0]:14.6e}{rows[s][1]:10.6f}" for s in STEPS),
              flush=True)


SHEAR_LAMMPS = """units           si
boundary        s s s
atom_style      peri
atom_modify     map array
neighbor        0.0010 bin
lattice         sc 0.0005
region          box block -0.0001 0.0046 -0.0001 0.0046 -0.0001 0.0046 units box
create_box      1 box
create_atoms    1 region box
pair_style      {style}
pair_coeff      * * 14.9e9 14.9e9 0.0015001 1.0 0.25 {tail}
set             group all density 2200
set             group all volume 1.25e-10
velocity        all set 0.0 0.0 0.0 sum no units box
region          top block INF INF 0.0029 INF INF INF units box
group           top region top
group           rest subtract all top
fix             1 all nve
timestep        1.0e-5
run             1
variable        dx atom 0.5e-4*y
variable        dy atom 0.5e-4*x
displace_atoms  all move v_dx v_dy 0.0 units box
fix             3 top setforce 0.0 0.0 0.0
fix             4 rest setforce 0.0 0.0 0.0
thermo_style    custom step f_3[1]
thermo_modify   format float %.10g
thermo          100
run             300
"""

SHEAR_HORIZON = """dimension: 3
spacing: 0.0005
horizon: 0.0015001
lattice_origin: [0, 0, 0]
partial_volume: lammps
materials:
  target: {{model: {model}, density: 2200, bulk_modulus: 14.9e9, shear_modulus: 14.9e9, influence: inverse{extra}}}
bodies:
  - {{name: block, material: target, shape: {{box: {{min: [-0.0001, -0.0001, -0.0001], max: [0.0046, 0.0046, 0.0046]}}}}}}
regions:
  top: {{box: {{min: [-1, 0.0029, -1], max: [1, 1, 1]}}}}
  rest: {{box: {{min: [-1, -1, -1], max: [1, 0.0029, 1]}}}}
loads:
  - {{region: top, displacement: ["5e-5*y", "5e-5*x", 0]}}
  - {{region: rest, displacement: ["5e-5*y", "5e-5*x", 0]}}
solver: {{end_time: 3.0e-3, time_step: 1.0e-5}}
output: {{directory: out, frames: 1, history_every: 100}}
"""


def shear(work, horizon):
    import math
    lam, tau, dt = 0.5, 1.0e-3, 1.0e-5
    h = dt / tau
    c = -math.expm1(-h) / h

    def sls_ramp(n):  # n force passes since the shear, the first a ramp over dt
        return ((1 - lam) + lam * c * math.exp(-(n - 1) * h)) / ((1 - lam) + lam * c)

    print("\n== shear: 10^3 block, gamma = 1e-4 held; force on the top 4 layers [N], F(t)/F(0+) against the SLS")
    print(f"{'case':30s}{'F(0+) [N]':>12s}{'F/F0 1 ms':>11s}{'SLS':>8s}{'F/F0 3 ms':>11s}{'SLS':>8s}")
    for name, style, tail, visc in [("peri/lps", "peri/lps", "", False), ("peri/ves lambda_i=0", "peri/ves", "0.0 0.001", False),
                                    ("peri/ves lambda_i=0.5", "peri/ves", "0.5 0.001", True)]:
        deck = os.path.join(work, "in.shear")
        open(deck, "w").write(SHEAR_LAMMPS.format(style=style, tail=tail))
        rows = thermo_rows(run(["lmp", "-in", deck, "-log", "none", "-nocite"], work), "Step f_3[1]", last=True)
        f0, f1, f3 = (-rows[n][0] * VOLUME for n in (1, 100, 300))
        s1, s3 = (sls_ramp(100), sls_ramp(300)) if visc else (1.0, 1.0)
        print(f"{'LAMMPS ' + name:30s}{f0:12.5f}{f1 / f0:11.5f}{s1:8.5f}{f3 / f0:11.5f}{s3:8.5f}", flush=True)
    if not horizon:
        return
    for name, model, extra, visc in [("lps", "lps", "", False), ("viscoelastic lambda_1=0", "viscoelastic", ", lambda_1: 0.0, tau_1: 0.001", False),
                                     ("viscoelastic lambda_1=0.5", "viscoelastic", ", lambda_1: 0.5, tau_1: 0.001", True)]:
        deck = os.path.join(work, "shear.yaml")
        open(deck, "w").write(SHEAR_HORIZON.format(model=model, extra=extra))
        outdir = os.path.join(work, "hzs")
        run([horizon, "run", deck, "--threads", "1", "--quiet", "--output", outdir], work)
        rows = {int(r["step"]): float(r["top:displacement_fx"]) for r in csv.DictReader(open(os.path.join(outdir, "history.csv")))}
        f0, f1, f3 = rows[0], rows[100], rows[300]
        # Horizon imposes the shear at t = 0 (a step): F/F0 = (1 - lambda) + lambda exp(-t/tau).
        s1, s3 = ((1 - lam) + lam * math.exp(-1.0), (1 - lam) + lam * math.exp(-3.0)) if visc else (1.0, 1.0)
        print(f"{'Horizon ' + name:30s}{f0:12.5f}{f1 / f0:11.5f}{s1:8.5f}{f3 / f0:11.5f}{s3:8.5f}", flush=True)


def read_vtu(path):
    """The appended raw arrays of a Horizon frame, by name."""
    import struct
    data = open(path, "rb").read()
    at = data.index(b"<AppendedData")
    head = data[:at].decode()
    start = data.index(b"_", at) + 1
    size = 8 if 'header_type="UInt64"' in head else 4
    out = {}
    for m in re.finditer(r'<DataArray type="(\w+)" Name="(\w+)" NumberOfComponents="(\d+)" '
                         r'NumberOfTuples="(\d+)" format="appended" offset="(\d+)"', head):
        kind, name, _, _, off = m.groups()
        off = start + int(off)
        n = struct.unpack("<Q" if size == 8 else "<I", data[off:off + size])[0]
        fmt = {"Float64": "d", "Float32": "f", "Int64": "q", "Int32": "i", "UInt8": "B"}[kind]
        out[name] = struct.unpack(f"<{n // struct.calcsize(fmt)}{fmt}", data[off + size:off + size + n])
    return out


def horizon_momentum(horizon, work, base, change, env=None):
    import yaml
    d = yaml.safe_load(open(os.path.join(HERE, base)))
    mat = d["materials"]["target"]
    mat.update(change)
    mat["damage"] = {"critical_stretch": 1.0, "alpha": 0.25, "breaks": "after_force"}
    d["contact"].pop("indenters", None)
    d["initial_conditions"] = [{"velocity": [0, "10*sin(pi*y/0.005)", 0]}]
    d["solver"]["end_time"] = 2.0e-5
    d["output"]["frames"] = 1
    deck = os.path.join(work, "mom.yaml")
    yaml.safe_dump(d, open(deck, "w"))
    outdir = os.path.join(work, "hzm")
    p = subprocess.run([horizon, "run", deck, "--threads", "1", "--quiet", "--output", outdir], cwd=work,
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                       env=dict(os.environ, OMP_NUM_THREADS="1", **(env or {})))
    if p.returncode != 0:
        sys.exit(f"failed: {horizon} run {deck}\n{p.stdout[-3000:]}")
    frames = sorted(f for f in os.listdir(os.path.join(outdir, "frames")) if f.endswith(".vtu"))
    res = []
    for f in (frames[0], frames[-1]):
        a = read_vtu(os.path.join(outdir, "frames", f))
        rho = mat["density"]
        vy, vol = a["velocity"][1::3], a["volume"]
        res.append((sum(rho * v * w for v, w in zip(vy, vol)), sum(abs(rho * v * w) for v, w in zip(vy, vol))))
    return res[0][0], res[1][0], res[0][1]


def momentum(ex, work, horizon, lammps_form=""):
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
        rows = thermo_rows(log, "Step v_py c_pa c_kea", last=True)
        p0, p1, pa = rows[1][0], rows[201][0], rows[1][1]
        print(f"{'LAMMPS ' + name:24s}{p0:18.6e}{p1:16.6e}{pa:20.6e}{(p1 - p0) / pa:12.3e}", flush=True)
    if not horizon:
        return
    for name, base, change in [("lps.yaml", "lps.yaml", {}), ("ves.yaml lambda_1=0", "ves.yaml", {VES_FRACTION_KEY: 0.0}),
                               ("ves.yaml", "ves.yaml", {}), ("eps.yaml", "eps.yaml", {})]:
        p0, p1, pa = horizon_momentum(horizon, work, base, change)
        print(f"{'Horizon ' + name:24s}{p0:18.6e}{p1:16.6e}{pa:20.6e}{(p1 - p0) / pa:12.3e}", flush=True)
    if lammps_form:
        p0, p1, pa = horizon_momentum(lammps_form, work, "ves.yaml", {VES_FRACTION_KEY: 0.0}, {"HORIZON_LAMMPS_ASYM": "1"})
        print(f"{'Horizon, LAMMPS form, l=0':24s}{p0:18.6e}{p1:16.6e}{pa:20.6e}{(p1 - p0) / pa:12.3e}", flush=True)


# Horizon's deck keys of the two models (docs/models/*.md on branch models-eps).
VES_FRACTION_KEY = "lambda_1"
VES_TIME_KEY = "tau_1"
EPS_YIELD_KEY = "yield_stress"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--horizon", default="", help="the horizon executable (leave out: LAMMPS alone)")
    ap.add_argument("--only", choices=["limits", "momentum", "shear"], default=None)
    ap.add_argument("--lammps-form", default="", help="a Horizon built with lammps_asymmetry.patch")
    args = ap.parse_args()
    ex = examples_dir()
    work = tempfile.mkdtemp(prefix="ves_eps_checks_")
    horizon = os.path.abspath(args.horizon) if args.horizon else ""
    if args.only in (None, "limits"):
        limits(ex, work, horizon, os.path.abspath(args.lammps_form) if args.lammps_form else "")
    if args.only in (None, "momentum"):
        momentum(ex, work, horizon, os.path.abspath(args.lammps_form) if args.lammps_form else "")
    if args.only in (None, "shear"):
        shear(work, horizon)
    shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()
