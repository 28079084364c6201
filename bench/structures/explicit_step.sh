#!/usr/bin/env bash
# Steady-state cost of one explicit step: O'Grady's bond-pair plate (model bond_pair,
# 41 x 41 nodes, a = 0.5 m, h = 50 mm, spacing 12.5 mm, horizon 3 spacings, simply
# supported, uniform pressure) against the 3-D LPS plate of the same in-plane spacing
# with 4 particles through the thickness (40 x 40 x 4), the two decks of
# bench/structures/lps_plate.sh. Each deck runs $SHORT and $LONG steps; the per-step
# cost is (cpu_long - cpu_short) / (LONG - SHORT), cpu the process's user + system CPU
# time (less sensitive than wall time to a loaded machine), which removes the set-up and
# the start-up (first force pass with energies, frame 0). Median of $REPEAT. One thread. Usage, from the repository root after a build:
#   bench/structures/explicit_step.sh [horizon binary] [spacing]
set -euo pipefail
bin=${1:-build/horizon}
dx=${2:-0.0125}
short=${SHORT:-50}
long=${LONG:-550}
repeat=${REPEAT:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
py() { python3 -c "print($1)"; }
a=$(py "40*$dx"); h=$(py "4*$dx"); q=1.0e5; E=200.0e9
source "$(dirname "${BASH_SOURCE[0]}")/plate_decks.sh"
plate_bp_deck "$a" "$h" "$dx" "$E" "$q" "{type: explicit, end_time: 1.0, safety_factor: 0.8}" "$work/bp" > "$work/bp.yaml"
plate_lps_deck "$a" "$h" "$dx" "$E" "$q" "{type: explicit, end_time: 1.0, safety_factor: 0.8}" "$work/lps" > "$work/lps.yaml"
loop() {  # $1 case, $2 steps: CPU seconds of the run, particles
  local dt
  dt=$(python3 -c "import json; print(json.load(open('$work/$1/summary.json'))['time_step'])")
  python3 - "$bin" "$(py "($2-0.5)*$dt")" "$work/$1.yaml" <<'PY'
import os, resource, subprocess, sys
env = dict(os.environ, OMP_NUM_THREADS="1")
subprocess.run([sys.argv[1], "run", "-q", "--end-time", sys.argv[2], sys.argv[3]], env=env, check=True,
               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
r = resource.getrusage(resource.RUSAGE_CHILDREN)
print(r.ru_utime + r.ru_stime)
PY
  python3 -c "import json; d=json.load(open('$work/$1/summary.json')); assert d['steps']==$2, d['steps']; print(d['particles'])"
}
for c in bp lps; do
  OMP_NUM_THREADS=1 "$bin" run -q --end-time 1e-12 "$work/$c.yaml" > /dev/null
  per=()
  for r in $(seq "$repeat"); do
    { read -r t1; read -r n; } < <(loop "$c" "$short")
    { read -r t2; read -r n; } < <(loop "$c" "$long")
    per+=("$(py "($t2-$t1)/($long-$short)")")
  done
  python3 - "$c" "$n" "${per[@]}" <<'PY'
import sys, statistics
c, n, per = sys.argv[1], int(sys.argv[2]), [float(x) for x in sys.argv[3:]]
m = statistics.median(per)
name = {"bp": "bond_pair plate", "lps": "3-D LPS, 4 layers"}[c]
print(f"{name:20s} particles {n:6d}: {m*1e3:.3f} ms/step, {m/n*1e9:.0f} ns/particle-step "
      f"(runs: {', '.join(f'{p*1e3:.3f}' for p in per)} ms)")
PY
done
