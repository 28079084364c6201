#!/usr/bin/env bash
# The cylinder of bench/clouds/cylinder.py twice: its points jittered (every bond its own
# length, as Peridigm's fragmenting_cylinder example and any mesh's centroids) and on
# regular rings (jitter 0), the same deck otherwise. Prints, for each, the run's wall time,
# its CPU time (user + system), the explicit loop's CPU time, and the peak resident memory
# (/usr/bin/time -v), medians of REPEAT runs, and the ratios jittered / regular.
#
#   bench/clouds/run.sh [BUILD]        # BUILD: build folder with horizon (default: build)
#   LAYERS=20 REPEAT=3 THREADS=2 bench/clouds/run.sh build
#
# LAYERS=100 (the default) is the full 100 mm tube, 70,500 points; fewer layers give a
# shorter tube of the same wall for routine checks. docs/benchmarks.md has the results.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
build="${1:-build}"
case "$build" in /*) ;; *) build="$root/$build" ;; esac
horizon="$build/horizon"
[ -x "$horizon" ] || { echo "no $horizon: build it first (cmake --build $build --target horizon)" >&2; exit 1; }
layers="${LAYERS:-100}"
repeat="${REPEAT:-1}"
threads="${THREADS:-2}"
steps="${STEPS:-100}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

echo "horizon: $("$horizon" --version), $horizon; $layers layers, $steps steps, $threads threads, $repeat runs each"
for jitter in 0 0.001; do
  python3 "$here/cylinder.py" "$work/j$jitter" --jitter "$jitter" --layers "$layers" --steps "$steps" >/dev/null
done
for r in $(seq "$repeat"); do
  for jitter in 0 0.001; do  # alternating, so that the machine's load falls on both alike
    d="$work/j$jitter"
    /usr/bin/time -v "$horizon" run "$d/cylinder.yaml" -q --threads "$threads" -o "$d/out$r" \
      >/dev/null 2>"$d/time$r.txt"
  done
done
python3 - "$work" "$repeat" <<'PY'
import json, re, statistics, sys
work, repeat = sys.argv[1], int(sys.argv[2])
def field(text, name):
    """A value of /usr/bin/time -v: a number, or a wall time h:mm:ss or m:ss.ss, in seconds."""
    line = next(x for x in text.splitlines() if x.strip().startswith(name))
    value = line.rsplit(": ", 1)[1]
    return sum(float(x) * 60 ** i for i, x in enumerate(reversed(value.split(":"))))
rows = {}
for jitter in ("0", "0.001"):
    runs = []
    for r in range(1, repeat + 1):
        t = open(f"{work}/j{jitter}/time{r}.txt").read()
        s = json.load(open(f"{work}/j{jitter}/out{r}/summary.json"))
        runs.append(dict(wall=field(t, "Elapsed (wall clock) time"),
                         cpu=field(t, "User time (seconds)") + field(t, "System time (seconds)"),
                         loop_cpu=s["loop_cpu_time_s"], rss=field(t, "Maximum resident set size") / 1024,
                         bonds=s.get("bonds", 0), damage=s["damage"]["mean"]))
    med = {k: statistics.median(x[k] for x in runs) for k in ("wall", "cpu", "loop_cpu", "rss")}
    med["damage"] = runs[0]["damage"]
    rows[jitter] = med
    print(f"jitter {jitter:>5}: wall {med['wall']:8.2f} s, CPU {med['cpu']:8.2f} s, loop CPU {med['loop_cpu']:8.2f} s, "
          f"peak {med['rss']:8.1f} MiB, mean damage {med['damage']:.6f}")
a, b = rows["0.001"], rows["0"]
print(f"jittered / regular: wall {a['wall'] / b['wall']:.2f}x, CPU {a['cpu'] / b['cpu']:.2f}x, "
      f"loop CPU {a['loop_cpu'] / b['loop_cpu']:.2f}x, peak memory {a['rss'] / b['rss']:.2f}x")
PY
