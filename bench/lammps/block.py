#!/usr/bin/env python3
"""Horizon against LAMMPS PERI on a static block: the lattice of LAMMPS's examples/peri decks
(simple cubic, spacing 0.5 mm, horizon 3.0002 spacings) cut to a 17 x 17 x 17 block of
points, 485,402 directed bonds, at rest in its reference state for 200 steps, one thread.
Nothing moves and no bond breaks, so both codes time their bond loops alone (and their
short-range contact, which both evaluate on every family pair). This is the problem of
LAMMPS's own `bond_style bpm/peri` benchmark (examples/bpm/peri/benchmark: a periodic 16^3
block at the reference state, 200 steps, one rank), which Debian's LAMMPS does not ship:
docs/benchmarks.md carries its published ratios over the legacy peri/* styles.

LAMMPS's decks are examples/peri/in.peri.<model> with the cylinder's region replaced by
the block, the indenter (fix 2) removed and `run 200`; Horizon's are bench/lammps/<model>.yaml
with the same changes. For each model the two codes run alternately, --repeat times each;
printed: the median time per step (wall and CPU), ns per directed bond-step, the ratio, and
the kinetic energy and mean damage at step 200 (both 0). The last line reads
`block_pmb=X block_lps=Y ...` (LAMMPS / Horizon, wall time per step).

    bench/lammps/block.sh [build-dir]      (MODELS=pmb,lps,ves,eps REPEAT=3)
"""
import argparse
import os
import re
import shutil
import statistics
import sys
import tempfile

import yaml

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import compare  # noqa: E402  (the side-by-side helpers: runs, LAMMPS's log, Horizon's summary)

SIDE = 17          # points along each edge
STEPS = 200
SPACING = 0.0005   # m, `lattice sc 0.0005`
# The block in lattice units, half a spacing beyond the outer points (create_atoms takes
# the points inside it: 0 .. 16 along each axis).
REGION = f"region          target block -0.5 {SIDE - 0.5} -0.5 {SIDE - 0.5} -0.5 {SIDE - 0.5} units lattice"


def lammps_block_deck(src, dst):
    compare.lammps_deck(src, dst)  # its thermo output (KE and mean damage)
    out = []
    for line in open(dst).read().splitlines():
        if re.match(r"^\s*region\s+target\s+", line):
            out.append(REGION)
        elif re.match(r"^\s*fix\s+2\s+all\s+indent\b", line):
            continue
        elif re.match(r"^\s*run\s+\d+", line):
            out.append(f"run             {STEPS}")
        else:
            out.append(line)
    if REGION not in out:
        sys.exit(f"{src}: expected `region target ...`")
    open(dst, "w").write("\n".join(out) + "\n")


def horizon_block_deck(src, dst):
    d = yaml.safe_load(open(src))
    lo, hi = -0.5 * SPACING, (SIDE - 0.5) * SPACING
    d["bodies"] = [{"name": "block", "material": "target", "shape": {"box": {"min": [lo] * 3, "max": [hi] * 3}}}]
    d.get("contact", {}).pop("indenters", None)
    d["solver"]["end_time"] = float(f"{STEPS * float(d['solver']['time_step']):.6g}")
    d["output"] = {"directory": "out/lammps_block", "frames": 1, "history_every": STEPS, "damage_measure": "volume"}
    yaml.safe_dump(d, open(dst, "w"), sort_keys=False)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--horizon", required=True)
    ap.add_argument("--lammps", default="lmp")
    ap.add_argument("--examples", required=True, help="LAMMPS's examples/peri folder")
    ap.add_argument("--decks", default=os.path.dirname(os.path.abspath(__file__)))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--models", default="pmb,lps")
    args = ap.parse_args()

    work = tempfile.mkdtemp(prefix="horizon_block_")
    env = dict(os.environ, OMP_NUM_THREADS="1")
    ratios = {}
    for model in args.models.split(","):
        ldeck = os.path.join(work, f"in.block.{model}")
        lammps_block_deck(os.path.join(args.examples, f"in.peri.{model}"), ldeck)
        hdeck = os.path.join(work, f"block_{model}.yaml")
        horizon_block_deck(os.path.join(args.decks, f"{model}.yaml"), hdeck)
        lmp_cmd = [args.lammps, "-in", ldeck, "-log", "none", "-nocite"]
        hz_out = os.path.join(work, f"horizon_{model}")
        hz_cmd = [args.horizon, "run", hdeck, "--threads", "1", "--quiet", "--output", hz_out]
        lt, lc, ht, hc = [], [], [], []
        for r in range(args.repeat):
            log, _ = compare.run_measured(lmp_cmd, work, env)
            l_loop, l_steps, l_bonds, l_rows, l_cpu = compare.parse_lammps(log)
            lt.append(l_loop / l_steps)
            lc.append(l_cpu / l_steps)
            compare.run_measured(hz_cmd, work, env)
            h_loop, h_steps, h_bonds, h_rows = compare.parse_horizon(hz_out)
            ht.append(h_loop / h_steps)
            hc.append(compare.parse_horizon_cpu(hz_out) / h_steps)
            print(f"# {model} run {r + 1}: LAMMPS {1e3 * lt[-1]:.3f} ms/step, Horizon {1e3 * ht[-1]:.3f} ms/step",
                  flush=True)
        if l_bonds != h_bonds:
            sys.exit(f"{model}: LAMMPS has {l_bonds} directed bonds, Horizon {h_bonds}")
        L, H, Lc, Hc = (statistics.median(x) for x in (lt, ht, lc, hc))
        ratios[model] = L / H
        print(f"\n== {model.upper()}: static {SIDE}^3 block, {h_bonds} directed bonds, {STEPS} steps, "
              f"1 thread, median of {args.repeat}")
        print(f"{'':30s}{'LAMMPS':>12s}{'Horizon':>12s}{'ratio':>9s}")
        print(f"{'time per step [ms]':30s}{1e3 * L:12.3f}{1e3 * H:12.3f}{L / H:9.2f}")
        print(f"{'CPU time per step [ms]':30s}{1e3 * Lc:12.3f}{1e3 * Hc:12.3f}{Lc / Hc:9.2f}")
        print(f"{'ns per directed bond-step':30s}{1e9 * L / l_bonds:12.2f}{1e9 * H / h_bonds:12.2f}")
        print(f"{'CPU ns per directed bond-step':30s}{1e9 * Lc / l_bonds:12.2f}{1e9 * Hc / h_bonds:12.2f}")
        lk, ld = l_rows[STEPS]
        hk, hd = h_rows[STEPS]
        print(f"{'step 200: KE [J], damage':30s}  LAMMPS {lk:.3g}, {ld:.3g}; Horizon {hk:.3g}, {hd:.3g}")
        print(f"(per-run ratios {', '.join(f'{a / b:.2f}' for a, b in zip(lt, ht))})")
    shutil.rmtree(work, ignore_errors=True)
    print(" ".join(f"block_{m}={ratios[m]:.2f}" for m in ratios))


if __name__ == "__main__":
    main()
