#!/usr/bin/env bash
# Time to solution of the static solvers against explicit dynamics run to rest, on the 3-D
# LPS block of examples/block_tension_static.yaml at a given particle count (docs/
# benchmarks.md, "Static solvers"). Usage, from the repository root after a build:
#   bench/static/run.sh [build dir] [cells along x: 74 for 101 306 particles] [methods...]
# methods: explicit newton_mf newton_cg newton_cholesky adr tangent (default: all but
# newton_cholesky, which needs O(n^2) flops in 3-D: use it at 20 or 40 cells).
# Every run uses 2 threads; results go to out/bench_static/<cells>/<method>/summary.json
# and a table on stdout.
set -euo pipefail
build=${1:-build}
cells=${2:-74}
shift 2 || true
methods=("$@")
[ ${#methods[@]} -eq 0 ] && methods=(tangent explicit newton_mf newton_cg adr)
h=$(python3 -c "print(0.02/$cells)")
root=out/bench_static/$cells
mkdir -p "$root"
declare -A solver=(
  [explicit]="{type: explicit, end_time: 4.0e-5, safety_factor: 0.8, damping: 1.6e6}"
  [newton_mf]="{type: static, method: newton, linear_solver: matrix_free, tolerance: 1.0e-6}"
  [newton_cg]="{type: static, method: newton, linear_solver: cg, tolerance: 1.0e-6}"
  [newton_cholesky]="{type: static, method: newton, linear_solver: cholesky, tolerance: 1.0e-6}"
  [adr]="{type: static, method: adr, tolerance: 1.0e-6}"
)
for m in "${methods[@]}"; do
  deck=$root/$m.yaml
  if [ "$m" = tangent ]; then
    bench/static/block_deck.sh "$h" "{type: static}" "$root/tangent" > "$deck"
    "$build"/bench/bench_static "$deck" | tee "$root/tangent.txt"
    continue
  fi
  bench/static/block_deck.sh "$h" "${solver[$m]}" "$root/$m" > "$deck"
  # Explicit dynamics runs the free block (tractions only): mass-proportional damping
  # damps rigid motion too, so a body on 3-2-1 supports would creep to its pinned
  # position far more slowly than it comes to rest; the free block's rest state is the
  # static solution up to a rigid translation (bench/static/compare_frames.py).
  [ "$m" = explicit ] && sed -i '/region: pin\|region: roller\|region: guide/d' "$deck"
  /usr/bin/time -f "%e s wall, %M KB peak" "$build"/horizon run "$deck" --threads 2 --quiet 2> "$root/$m.time" || true
  python3 - "$root/$m/summary.json" "$m" "$(tail -1 "$root/$m.time")" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
s = j.get("solver", {})
print(f"{sys.argv[2]:16s} {j['particles']} particles  status {j['status']}  wall {j['wall_time_s']:.1f} s  "
      f"steps {j['steps']}  iterations {s.get('iterations', '-')}  CG {s.get('linear_iterations', '-')}  "
      f"tangent {s.get('tangent_bytes_per_bond', 0):.0f} B/bond  kinetic/strain "
      f"{j['energy']['kinetic'] / max(j['energy']['strain'], 1e-300):.1e}  ({sys.argv[3]})")
PY
done
