#!/usr/bin/env python3
"""MPI figures for docs/benchmarks.md: one rank against the serial build, ranks x threads
strong scaling, and halo traffic per rank at 1-16 ranks (oversubscribed).

    python3 bench/mpi/run.py [--serial build/horizon] [--mpi build/horizon-mpi] [--reps 5]

Prints markdown tables; every run's summary.json state_crc32 must agree (the final state,
bit for bit)."""
import argparse, json, os, statistics, subprocess, tempfile

ap = argparse.ArgumentParser()
ap.add_argument("--serial", default="build/horizon")
ap.add_argument("--mpi", default="build/horizon-mpi")
ap.add_argument("--deck", default="bench/mpi/lammps_fine.yaml")
ap.add_argument("--mpi-base", default="", help="another horizon-mpi (e.g. the main branch's) to run beside, under mpirun -n 1")
ap.add_argument("--reps", type=int, default=5)
ap.add_argument("--part", default="all", choices=["all", "cost", "scaling", "halo"])
a = ap.parse_args()
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMP_WAIT_POLICY="passive")
tmp = tempfile.mkdtemp(prefix="horizon_mpi_bench_")
crcs = set()


def run(cmd, extra=()):
    out = os.path.join(tmp, "run")
    subprocess.run(cmd + ["run", a.deck, "-q", "-o", out] + list(extra), check=True, env=env)
    s = json.load(open(os.path.join(out, "summary.json")))
    if "--end-time" not in extra:
        crcs.add(s["state_crc32"])
    return s


def med(xs):
    return statistics.median(xs)


if a.part in ("all", "cost"):
    # The variants run in turn, rep after rep, so that the machine's load drifts over all
    # of them alike. "bound" is mpirun's default for 1-2 ranks (each rank bound to one
    # core); "--bind-to none" lets the kernel move the rank to an idle core.
    variants = (("serial", [a.serial]),
                ("MPI program alone (singleton)", [a.mpi]),
                ("mpirun -n 1 (bound to a core)", ["mpirun", "-n", "1", a.mpi]),
                ("mpirun -n 1 --bind-to none", ["mpirun", "-n", "1", "--bind-to", "none", a.mpi]))
    if a.mpi_base:
        variants += (("mpirun -n 1, " + a.mpi_base, ["mpirun", "-n", "1", a.mpi_base]),)
    res = {name: [] for name, _ in variants}
    for _ in range(a.reps):
        for name, cmd in variants:
            res[name].append(run(cmd, ["--threads", "1"]))
    base = med([x["loop_cpu_time_s"] for x in res["serial"]])
    print("| program | loop wall [s] (median of %d) | loop CPU [s] | CPU vs serial |" % a.reps)
    print("|---|---|---|---|")
    for name, _ in variants:
        r = res[name]
        cpu = med([x["loop_cpu_time_s"] for x in r])
        print("| %s | %.3f | %.3f | %+.1f %% |" % (name, med([x["loop_time_s"] for x in r]), cpu, 100 * (cpu / base - 1)))

if a.part in ("all", "scaling"):
    print("\n| ranks x threads | loop wall [s] (median of %d) | speed-up |" % a.reps)
    print("|---|---|---|")
    base = None
    for ranks, threads in ((1, 1), (1, 2), (2, 1), (2, 2)):
        r = [run(["mpirun", "--oversubscribe", "--mca", "mpi_yield_when_idle", "1", "-n", str(ranks), a.mpi], ["--threads", str(threads)]) for _ in range(a.reps)]
        t = med([x["loop_time_s"] for x in r])
        base = base or t
        print("| %d x %d | %.3f | %.2f |" % (ranks, threads, t, base / t))

if a.part in ("all", "halo"):
    print("\n| ranks | particles per rank (mean) | messages per rank per step (mean, max) | bytes per rank per step (mean, max) | ghost re-selections |")
    print("|---|---|---|---|---|")
    for ranks in (1, 2, 4, 8, 16):
        s = run(["mpirun", "--oversubscribe", "-n", str(ranks), a.mpi], ["--threads", "1", "--end-time", "5e-6"])
        h = s["halo"]
        m = [x["messages_per_step"] for x in h]
        b = [x["bytes_per_step"] for x in h]
        p = [x["particles"] for x in h]
        print("| %d | %.0f | %.2f, %.0f | %.0f, %.0f | %d |" % (ranks, statistics.mean(p), statistics.mean(m), max(m),
                                                            statistics.mean(b), max(b), h[0]["ghost_rebuilds"]))

print("\nfinal-state CRC-32 of the full-length runs: %s (%s)" % (sorted(crcs), "all equal" if len(crcs) <= 1 else "DIFFER"))
