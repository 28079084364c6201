#!/usr/bin/env python3
"""Horizon against LAMMPS PERI on LAMMPS's own examples (examples/peri/in.peri.pmb and
in.peri.lps; with `--models ves,eps` in.peri.ves and in.peri.eps), one thread each, in one
run of this script (bench/lammps/run.sh and run_ves_eps.sh call it).

For each model it runs LAMMPS and Horizon alternately, `--repeat` times each, and prints
the wall time per step (median of the runs' loop times), directed bond evaluations per
second, peak resident memory, the mean damage and kinetic energy at steps 250, 500, 750
and 1000 of both codes with their relative difference, and the speed ratio; the last
line is `pmb_speedup=X lps_speedup=Y` (`ves_speedup=X eps_speedup=Y` for those models).
`--lammps-only` runs and reports LAMMPS alone (for a model Horizon does not have yet).

LAMMPS's deck is copied unchanged except for its output: `thermo 250` with the mean of
`compute damage/atom` and `compute ke`. LAMMPS (units si, atom_style peri, where the mass
is the density) reports sum 1/2 rho v^2; Horizon reports sum 1/2 rho V v^2 [J]. The
LAMMPS figure is multiplied by the particle volume, 1.25e-10 m^3 (the same for every
particle), to compare them in joules.
"""
import argparse
import csv
import json
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

VOLUME = 1.25e-10  # m^3, `set group all volume 1.25e-10`
STEPS = (250, 500, 750, 1000)  # the default of --steps


def run_measured(cmd, cwd, env=None):
    """Runs cmd; returns (stdout+stderr text, wall seconds)."""
    start = time.perf_counter()
    proc = subprocess.run(cmd, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        sys.exit(f"command failed ({proc.returncode}): {' '.join(cmd)}\n{proc.stdout[-3000:]}")
    return proc.stdout, wall


def peak_rss(cmd, cwd, env=None):
    """Peak RSS of one command, measured in a child Python so that no other run mixes in."""
    probe = ("import resource,subprocess,sys;"
             "p=subprocess.run(sys.argv[1:],stdout=subprocess.DEVNULL,stderr=subprocess.DEVNULL);"
             "print(resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss*1024 if p.returncode==0 else -1)")
    out = subprocess.run([sys.executable, "-c", probe] + cmd, cwd=cwd, env=env, stdout=subprocess.PIPE, text=True)
    return int(out.stdout.strip() or -1)


def lammps_deck(src, dst):
    text = open(src).read()
    out = []
    for line in text.splitlines():
        if re.match(r"^\s*thermo\s+\d+", line):
            out += ["compute         dmean all reduce ave c_1",
                    "compute         kea all ke",
                    "thermo_style    custom step c_kea c_dmean",
                    "thermo          250",
                    "thermo_modify   format float %.10g"]
        else:
            out.append(line)
    if not any("compute         1 all damage/atom" in l or re.match(r"^\s*compute\s+1\s+all\s+damage/atom", l)
               for l in out):
        sys.exit(f"{src}: expected `compute 1 all damage/atom`")
    open(dst, "w").write("\n".join(out) + "\n")


def parse_lammps(log):
    loop = re.search(r"Loop time of ([0-9.eE+-]+) on 1 procs for (\d+) steps", log)
    cpu = re.search(r"([0-9.]+)% CPU use", log)
    bonds = re.search(r"total # of bonds = (\d+)", log)
    rows = {}
    block = log[log.index("Step c_kea c_dmean"):]
    for line in block.splitlines()[1:]:
        parts = line.split()
        if len(parts) != 3 or not parts[0].isdigit():
            break
        rows[int(parts[0])] = (float(parts[1]) * VOLUME, float(parts[2]))
    loop_s = float(loop.group(1))
    return loop_s, int(loop.group(2)), int(bonds.group(1)), rows, loop_s * float(cpu.group(1)) / 100


def parse_horizon_cpu(outdir):
    return json.load(open(os.path.join(outdir, "summary.json")))["loop_cpu_time_s"]


def parse_horizon(outdir):
    summary = json.load(open(os.path.join(outdir, "summary.json")))
    rows = {}
    with open(os.path.join(outdir, "history.csv")) as f:
        for r in csv.DictReader(f):
            rows[int(r["step"])] = (float(r["kinetic_energy"]), float(r["damage_mean"]))
    return summary["loop_time_s"], summary["steps"], summary["bonds"], rows


def report_lammps_only(model, deck, lmp_cmd, work, env, repeat, steps):
    times, cpu = [], []
    for r in range(repeat):
        log, _ = run_measured(lmp_cmd, work, env)
        loop, nsteps, bonds, rows, loop_cpu = parse_lammps(log)
        times.append(loop / nsteps)
        cpu.append(loop_cpu / nsteps)
        print(f"# {model} run {r + 1}: LAMMPS {1e3 * times[-1]:.3f} ms/step", flush=True)
    mem = peak_rss(lmp_cmd, work, env)
    lt = statistics.median(times)
    print(f"\n== {model.upper()}: {os.path.basename(deck)} (LAMMPS alone), 1 thread, median of {repeat}")
    print(f"{'time per step [ms]':24s}{1e3 * lt:16.3f}   (runs: {', '.join(f'{1e3 * t:.3f}' for t in times)})")
    print(f"{'CPU time per step [ms]':24s}{1e3 * statistics.median(cpu):16.3f}")
    print(f"{'directed bonds':24s}{bonds:16d}")
    print(f"{'bond evaluations/s':24s}{bonds / lt:16.4g}")
    print(f"{'peak memory [MiB]':24s}{mem / 2**20:16.1f}")
    print(f"{'step':>6s}{'KE LAMMPS [J]':>16s}{'damage LAMMPS':>15s}")
    for st in steps:
        print(f"{st:6d}{rows[st][0]:16.6e}{rows[st][1]:15.6f}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--horizon", required=True, help="the horizon executable")
    ap.add_argument("--lammps", default="lmp")
    ap.add_argument("--examples", required=True, help="LAMMPS's examples/peri folder")
    ap.add_argument("--decks", default=os.path.dirname(os.path.abspath(__file__)))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--models", default="pmb,lps")
    ap.add_argument("--steps", default=",".join(map(str, STEPS)), help="steps to report (multiples of 250)")
    ap.add_argument("--lammps-only", action="store_true", help="run and report LAMMPS alone")
    args = ap.parse_args()
    steps = [int(x) for x in args.steps.split(",")]

    work = tempfile.mkdtemp(prefix="horizon_vs_lammps_")
    env = dict(os.environ, OMP_NUM_THREADS="1")
    speedups = {}
    for model in args.models.split(","):
        deck = os.path.join(work, f"in.peri.{model}")
        lammps_deck(os.path.join(args.examples, f"in.peri.{model}"), deck)
        hdeck = os.path.join(args.decks, f"{model}.yaml")
        lmp_cmd = [args.lammps, "-in", deck, "-log", "none", "-nocite"]
        hz_out = os.path.join(work, f"horizon_{model}")
        hz_cmd = [args.horizon, "run", hdeck, "--threads", "1", "--quiet", "--output", hz_out]
        l_times, h_times, l_cpu, h_cpu = [], [], [], []
        if args.lammps_only:
            report_lammps_only(model, deck, lmp_cmd, work, env, args.repeat, steps)
            continue
        for r in range(args.repeat):
            log, _ = run_measured(lmp_cmd, work, env)
            l_loop, l_steps, l_bonds, l_rows, l_loop_cpu = parse_lammps(log)
            l_times.append(l_loop / l_steps)
            l_cpu.append(l_loop_cpu / l_steps)
            run_measured(hz_cmd, work, env)
            h_loop, h_steps, h_bonds, h_rows = parse_horizon(hz_out)
            h_times.append(h_loop / h_steps)
            h_cpu.append(parse_horizon_cpu(hz_out) / h_steps)
            print(f"# {model} run {r + 1}: LAMMPS {1e3 * l_times[-1]:.3f} ms/step, "
                  f"Horizon {1e3 * h_times[-1]:.3f} ms/step", flush=True)
        l_mem = peak_rss(lmp_cmd, work, env)
        h_mem = peak_rss(hz_cmd, work, env)
        lt, ht = statistics.median(l_times), statistics.median(h_times)
        speedups[model] = lt / ht
        print(f"\n== {model.upper()}: {os.path.basename(deck)} (LAMMPS) vs {os.path.relpath(hdeck)} (Horizon), "
              f"1 thread, median of {args.repeat}")
        print(f"{'':24s}{'LAMMPS':>16s}{'Horizon':>16s}")
        print(f"{'time per step [ms]':24s}{1e3 * lt:16.3f}{1e3 * ht:16.3f}")
        lc, hc = statistics.median(l_cpu), statistics.median(h_cpu)
        print(f"{'CPU time per step [ms]':24s}{1e3 * lc:16.3f}{1e3 * hc:16.3f}")
        print(f"{'directed bonds':24s}{l_bonds:16d}{h_bonds:16d}")
        print(f"{'bond evaluations/s':24s}{l_bonds / lt:16.4g}{h_bonds / ht:16.4g}")
        print(f"{'peak memory [MiB]':24s}{l_mem / 2**20:16.1f}{h_mem / 2**20:16.1f}")
        print(f"{'step':>6s}{'KE LAMMPS [J]':>16s}{'KE Horizon [J]':>16s}{'diff':>9s}"
              f"{'damage LAMMPS':>15s}{'damage Horizon':>16s}{'diff':>9s}")
        worst = 0.0
        for st in steps:
            lk, ld = l_rows[st]
            hk, hd = h_rows[st]
            dk, dd = (hk - lk) / lk, (hd - ld) / ld
            worst = max(worst, abs(dk), abs(dd))
            print(f"{st:6d}{lk:16.6e}{hk:16.6e}{100 * dk:8.3f}%{ld:15.6f}{hd:16.6f}{100 * dd:8.3f}%")
        print(f"largest difference {100 * worst:.3f}% ({'within' if worst <= 0.02 else 'OUTSIDE'} 2%)")
        print(f"speed ratio LAMMPS/Horizon: {speedups[model]:.2f} "
              f"(per-run ratios {', '.join(f'{a / b:.2f}' for a, b in zip(l_times, h_times))}); "
              f"in CPU time {lc / hc:.2f}")
    shutil.rmtree(work, ignore_errors=True)
    if speedups:
        print(" ".join(f"{m}_speedup={speedups[m]:.2f}" for m in speedups))


if __name__ == "__main__":
    main()
