#!/bin/sh
# The backward-Euler heat step alone (solver.type heat) on examples/thermal_shock.yaml's
# plate (20,000 particles, horizon 3 spacings, four convective edges): 20 steps of 0.01 s,
# about 10x the explicit heat solver's stable step. Prints the wall time, the lowest
# temperature and the heat content (the same to ~1e-13 whatever solves the step) and the
# conjugate-gradient iterations of the last step (docs/benchmarks.md, "Backward-Euler heat
# step"). Usage: bench/heat/implicit_step.sh BINARY [RUNS]   (one thread; MPI: prefix with
# `mpirun -n N` by setting LAUNCH, e.g. LAUNCH="mpirun -n 2" BINARY=build/horizon-mpi)
set -e
bin=${1:-build/horizon}
runs=${2:-3}
dir=$(mktemp -d)
root=$(dirname "$0")/../..
grep -v '^#' "$root/examples/thermal_shock.yaml" |
  sed -e 's|^solver:.*|solver: {type: heat, end_time: 0.2, time_step: 0.01}|' \
      -e 's|^  time_scale: 5000|  integration: implicit|' -e 's|expansion: 7.5e-6, ||' -e 's|frames: 20|frames: 1|' \
      > "$dir/deck.yaml"
for k in $(seq "$runs"); do
  $LAUNCH "$bin" run "$dir/deck.yaml" -q -o "$dir/out" --threads 1
  python3 -c "
import json; j = json.load(open('$dir/out/summary.json')); t = j['thermal']
print(f\"wall {j['wall_time_s']:.2f} s  T_min {t['temperature_min']:.12f}  content {t['heat_content']:.12f}  cg {t.get('cg_iterations_last_step', '-')}\")"
done
rm -rf "$dir"
