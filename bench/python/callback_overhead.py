"""Overhead of a Python callback on a run: the demo deck (examples/glass_branching.yaml)
stepped by the Python module with no callback and with a callback every N steps, against
the same run from the command line. Median wall time of the stepping loop over several
runs (the machine is shared: medians, not means).

    PYTHONPATH=build/python /usr/bin/python3 bench/python/callback_overhead.py \
        --coarsen 2 --end-time 10e-6 --repeats 5 --every 1 100
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

import horizon


def loop_time(deck, every, args, out):
    sim = horizon.Simulation(deck, output_dir=out, coarsen=args.coarsen, end_time=args.end_time,
                             threads=args.threads)
    calls = [0, 0.0]

    def callback(s):
        t = time.perf_counter()
        calls[0] += 1
        float(s.damage.max())   # a typical look at the state: one reduction over a NumPy view
        calls[1] += time.perf_counter() - t

    t0 = time.perf_counter()
    if every:
        sim.run(callback=callback, every=every)
    else:
        sim.run()
    return time.perf_counter() - t0, sim.steps, calls


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--deck", default="examples/glass_branching.yaml")
    p.add_argument("--coarsen", type=float, default=2)
    p.add_argument("--end-time", type=float, default=10e-6)
    p.add_argument("--threads", type=int, default=0)
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--every", type=int, nargs="+", default=[1, 100])
    a = p.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        cases = [0] + a.every
        times = {c: [] for c in cases}
        inside = {c: [] for c in cases}
        for r in range(a.repeats):
            for c in cases:   # interleaved, so that load changes hit every case alike
                t, steps, calls = loop_time(a.deck, c, a, os.path.join(tmp, "run_%d" % c))
                times[c].append(t)
                if calls[0]:
                    inside[c].append(calls[1] / calls[0])
        base = statistics.median(times[0])
        print("deck %s, coarsen %g, end time %g s, %d steps, %d repeats" % (a.deck, a.coarsen, a.end_time, steps,
                                                                          a.repeats))
        print("%-22s %12s %10s %18s" % ("case", "median [s]", "overhead", "in callback [us]"))
        for c in cases:
            m = statistics.median(times[c])
            name = "no callback" if c == 0 else "callback every %d" % c
            per = "%.1f" % (1e6 * statistics.median(inside[c])) if inside[c] else "-"
            print("%-22s %12.4f %9.2f%% %18s" % (name, m, 100 * (m / base - 1), per))


if __name__ == "__main__":
    sys.exit(main())
