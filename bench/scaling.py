#!/usr/bin/env python3
"""Kernel figures for docs/benchmarks.md, from bench_kernels (Google Benchmark) and one
`horizon run`:

- growth: PMB force-pass time per step on 3-D blocks of 1e4, 1e5 and 1e6 particles
  (horizon = 3 spacings), 1 thread, and the fitted exponent of time ~ N^p;
- threads: the speed-up from 1 to 2 threads on the 1e5 and 1e6 blocks (1.2e7 and
  1.2e8 directed bonds), the results being bit-identical (tests/unit/test_threads.cpp);
- the limit: a STREAM triad measures the memory bandwidth, and the PMB pass's bytes
  per bond times bonds per second over it says how close the loop is to the bound;
- memory: peak resident memory of a 1e6-particle PMB run per directed bond.

    python3 bench/scaling.py build        (build: the CMake build directory)
"""
import json
import math
import os
import subprocess
import sys
import tempfile

# Bytes the PMB pass must move per directed bond when nothing is cached: the neighbour
# index (4), the kind index (4), the intact flag (1); per particle (amortised over its
# ~118 bonds) the packed position it gathers once per row and the results it writes
# (32 + 24 + 3 * 8 = 80 bytes, about 0.7 per bond). Neighbours' positions are reused
# from cache by the rows around them; the kind table (36-200 kinds of 64 bytes) stays
# in L1/L2.
PER_BOND_BYTES = 4 + 4 + 1
PER_PARTICLE_BYTES = 32 + 24 + 8 + 8 + 8


def bench(build, filt, reps):
    out = subprocess.run(
        [os.path.join(build, "bench", "bench_kernels"), f"--benchmark_filter={filt}",
         f"--benchmark_repetitions={reps}", "--benchmark_report_aggregates_only=true",
         "--benchmark_format=json"], stdout=subprocess.PIPE, text=True, check=True).stdout
    runs = {}
    for b in json.loads(out)["benchmarks"]:
        if b.get("aggregate_name") != "median":
            continue
        runs[b["run_name"]] = b
    return runs


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else "build"
    reps = int(os.environ.get("REPEAT", "5"))
    r = bench(build, "BM_PmbForce|BM_PmbHalfBonds|BM_Lps|BM_NeighborSearch|BM_Triad", reps)

    def t(name):  # seconds per iteration (median)
        b = r[name]
        scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}[b["time_unit"]]
        return b["real_time"] * scale

    print(f"{'benchmark':44s}{'time':>12s}{'bonds/s':>12s}{'ns/bond':>9s}  path")
    for name, b in r.items():
        if "Triad" in name:
            print(f"{name:44s}{1e3 * t(name):10.2f}ms{'':12s}{'':9s}  {b['bytes_per_s'] / 1e9:.2f} GB/s")
            continue
        bps = b.get("bonds_per_s", 0)
        print(f"{name:44s}{1e3 * t(name):10.2f}ms{bps:12.4g}{1e9 / bps if bps else 0:9.2f}  {b.get('label', '')}")

    sizes = [(22, "BM_PmbForce/22/1/min_time:1.000/real_time"), (47, "BM_PmbForce/47/1/min_time:1.000/real_time"),
             (100, "BM_PmbForce/100/1/min_time:1.000/real_time")]
    xs = [math.log(r[n]["particles"]) for _, n in sizes]
    ys = [math.log(t(n)) for _, n in sizes]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    p = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sum((x - mx) ** 2 for x in xs)
    print(f"\ngrowth: time per PMB force pass ~ N^{p:.3f} over N = "
          + ", ".join(f"{r[n]['particles']:.4g}" for _, n in sizes)
          + " (" + ", ".join(f"{1e9 * t(n) / r[n]['bonds']:.2f}" for _, n in sizes) + " ns/bond)")
    for n in (47, 100):
        one, two = t(f"BM_PmbForce/{n}/1/min_time:1.000/real_time"), t(f"BM_PmbForce/{n}/2/min_time:1.000/real_time")
        print(f"threads: PMB block n={n} ({r[f'BM_PmbForce/{n}/1/min_time:1.000/real_time']['bonds']:.3g} bonds): "
              f"1 -> 2 threads x{one / two:.2f}")
    for name in ("BM_LpsStep/47", "BM_NeighborSearch/47"):
        print(f"threads: {name}: 1 -> 2 threads x{t(name + '/1/real_time') / t(name + '/2/real_time'):.2f}")

    print(f"storage: PMB pass on the 1e5 block, 1 thread: rows at both ends {1e3 * t('BM_PmbForce/47/1/min_time:1.000/real_time'):.1f} ms "
          f"({r['BM_PmbForce/47/1/min_time:1.000/real_time'].get('label', 'vector')}), {1e3 * t('BM_PmbForceScalar/47/1/real_time'):.1f} ms (scalar); bonds once {1e3 * t('BM_PmbHalfBonds/47/1/real_time'):.1f} ms "
          f"(scalar), on 2 threads {1e3 * t('BM_PmbHalfBonds/47/2/real_time'):.1f} ms (atomics)")
    big = r["BM_PmbForce/100/1/min_time:1.000/real_time"]
    bw = r["BM_Triad/1/real_time"]["bytes_per_s"]
    per_bond = PER_BOND_BYTES + PER_PARTICLE_BYTES * big["particles"] / big["bonds"]
    moved = per_bond * big["bonds_per_s"]
    print(f"limit: PMB pass on 1e6 particles moves {per_bond:.2f} B/bond x {big['bonds_per_s']:.3g} bonds/s = "
          f"{moved / 1e9:.2f} GB/s; triad bandwidth (1 thread) {bw / 1e9:.2f} GB/s: {100 * moved / bw:.0f}% of the "
          f"bandwidth bound")

    with tempfile.TemporaryDirectory() as tmp:
        deck = os.path.join(os.path.dirname(os.path.abspath(__file__)), "scaling", "block_1e6.yaml")
        subprocess.run([os.path.join(build, "horizon"), "run", deck, "--threads", "1", "--quiet", "--output", tmp],
                       check=True)
        s = json.load(open(os.path.join(tmp, "summary.json")))
        print(f"memory: {s['particles']} particles, {s['bonds']} directed bonds, peak resident "
              f"{s['peak_memory_bytes'] / 2**20:.0f} MiB = {s['peak_memory_bytes'] / s['bonds']:.2f} bytes per bond")


if __name__ == "__main__":
    main()
