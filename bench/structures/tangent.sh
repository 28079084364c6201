#!/usr/bin/env bash
# The Newton tangent of the bond-pair plate (model bond_pair): analytic (Model::stiffness)
# against finite differences, on examples/plate_navier.yaml (n = 80, 6561 nodes, delta =
# 3 dx, one load step, Cholesky). Runs each case $1 times (default 3), interleaved, one
# thread, and prints per run the wall time, the tangent seconds and the solve seconds of
# summary.json, then the medians. Usage, from the repository root after a build:
#   bench/structures/tangent.sh [repeats] [horizon binary]
set -euo pipefail
repeats=${1:-3}
bin=${2:-build/horizon}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for t in analytic finite_difference; do
  sed -E "s/tangent: [a-z_]+/tangent: $t/; s#out_plate_navier#$work/out_$t#" examples/plate_navier.yaml > "$work/$t.yaml"
done
for r in $(seq "$repeats"); do
  for t in analytic finite_difference; do
    OMP_NUM_THREADS=1 "$bin" run --quiet "$work/$t.yaml" > /dev/null
    python3 - "$work/out_$t/summary.json" "$t" >> "$work/rows.txt" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
v = s["solver"]
print(sys.argv[2], s["wall_time_s"], v["tangent_seconds"], v["solve_seconds"], v["iterations"])
PY
  done
done
cat "$work/rows.txt"
python3 - "$work/rows.txt" <<'PY'
import statistics, sys
rows = [l.split() for l in open(sys.argv[1])]
for t in ("analytic", "finite_difference"):
    r = [x for x in rows if x[0] == t]
    print(f"{t:18s} median wall {statistics.median(float(x[1]) for x in r):.3f} s, "
          f"tangent {statistics.median(float(x[2]) for x in r):.3f} s, "
          f"solve {statistics.median(float(x[3]) for x in r):.3f} s, Newton iterations {r[0][4]}")
PY
