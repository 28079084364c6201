#!/usr/bin/env bash
# Cost of a thin plate: O'Grady's bond-pair plate (model bond_pair, one node through the
# thickness) against a 3-D LPS plate resolved through the thickness with 4 particles at
# the same in-plane spacing. A simply supported square steel plate, a = 40 spacings,
# h = 4 spacings (a/h = 10), uniform pressure q, nu = 1/3, horizon 3 spacings.
#   - static: Newton (bond_pair: Cholesky on the analytic tangent; LPS: $LPS_SOLVER,
#     default matrix_free), the centre deflection against Navier's 0.00406235 q a^4/D;
#   - explicit: $STEPS steps of each (no damping), loop seconds per step and per
#     particle-step, and the stable step (summary.json).
# One thread. Usage, from the repository root after a build:
#   bench/structures/lps_plate.sh [spacing] [horizon binary]
set -euo pipefail
dx=${1:-0.0125}
bin=${2:-build/horizon}
steps=${STEPS:-50}
lps_solver=${LPS_SOLVER:-matrix_free}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
py() { python3 -c "print($1)"; }
a=$(py "40*$dx"); h=$(py "4*$dx"); q=1.0e5
E=200.0e9
source "$(dirname "${BASH_SOURCE[0]}")/plate_decks.sh"
bp_deck() { plate_bp_deck "$a" "$h" "$dx" "$E" "$q" "$1" "$2"; }  # $1 solver map, $2 output directory
lps_deck() { plate_lps_deck "$a" "$h" "$dx" "$E" "$q" "$1" "$2"; }
bp_deck "{type: static, method: newton, linear_solver: cholesky, tolerance: 1.0e-8}" "$work/bp_static" > "$work/bp_static.yaml"
lps_deck "{type: static, method: newton, linear_solver: $lps_solver, tolerance: 1.0e-6, max_iterations: 10}" "$work/lps_static" > "$work/lps_static.yaml"
bp_deck "{type: explicit, end_time: 1.0, safety_factor: 0.8}" "$work/bp_explicit" > "$work/bp_explicit.yaml"
lps_deck "{type: explicit, end_time: 1.0, safety_factor: 0.8}" "$work/lps_explicit" > "$work/lps_explicit.yaml"
for c in bp lps; do
  OMP_NUM_THREADS=1 "$bin" run -q "$work/${c}_static.yaml" > /dev/null
  dt=$(OMP_NUM_THREADS=1 "$bin" run -q --end-time 1e-12 "$work/${c}_explicit.yaml" > /dev/null 2>&1; python3 -c "import json; print(json.load(open('$work/${c}_explicit/summary.json'))['time_step'])")
  OMP_NUM_THREADS=1 "$bin" run -q --end-time "$(py "($steps-0.5)*$dt")" "$work/${c}_explicit.yaml" > /dev/null
done
python3 - "$work" "$a" "$h" "$q" "$E" <<'PY'
import json, math, os, sys
work, a, h, q, E = sys.argv[1], *map(float, sys.argv[2:])
nu = 1/3
D = E*h**3/(12*(1-nu*nu))
navier = 0.00406235*q*a**4/D
sys.path.insert(0, os.environ["PLATE_DECKS_DIR"])
from plate_centre import centre_w as centre_w_of
def centre_w(out):
    return centre_w_of(out, a)
print(f"plate a = {a} m, h = {h} m (a/h = {a/h:.0f}), q = {q} Pa; Navier w_c = {navier:.4e} m")
for c, name in (("bp", "bond_pair plate"), ("lps", "3-D LPS, 4 layers")):
    s = json.load(open(f"{work}/{c}_static/summary.json"))
    e = json.load(open(f"{work}/{c}_explicit/summary.json"))
    w = centre_w(f"{work}/{c}_static")
    per = e["loop_time_s"]/max(e["steps"], 1)
    print(f"{name:20s} particles {s['particles']:7d} bonds {s['bonds']:9d} | static {s['status']}, wall {s['wall_time_s']:.2f} s, "
          f"w_c/w_Navier {w/navier:.4f} | explicit dt {e['time_step']:.3e} s, {per*1e3:.3f} ms/step, "
          f"{per/s['particles']*1e9:.1f} ns/particle-step")
PY
