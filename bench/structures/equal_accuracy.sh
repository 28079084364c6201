#!/usr/bin/env bash
# Thin plate at equal accuracy: O'Grady's bond-pair plate (n x n spacings) against a 3-D
# LPS plate with L particles through the thickness (10 L x 10 L x L), the plate of
# bench/structures/lps_plate.sh (simply supported square steel plate, a = 0.5 m,
# h = 50 mm, a/h = 10, uniform pressure 1e5 Pa, nu = 1/3, horizon 3 spacings).
# References: Kirchhoff (Navier series, 0.00406235 q a^4/D) for the bond-pair plate, and
# Mindlin's plate (first-order shear deformation, shear factor 5/6; the Navier series with
# the shear term 1/(k G h alpha^2) added, Reddy, Theory and Analysis of Elastic Plates and
# Shells, 2nd ed., sec. 10.1) for the 3-D plate, which has the shear deflection Kirchhoff
# lacks (5 % at a/h = 10). Static: Newton (bond-pair Cholesky on the analytic tangent; LPS
# matrix-free CG, tolerance 1e-6), CPU seconds of the whole run. Explicit: CPU per step
# from the difference of a 10- and a 110-step run, and the stable step.
# The thickness may be set by PLATE_H (m; default 0.05, a/h = 10).
# One thread. Usage, from the repository root after a build:
#   bench/structures/equal_accuracy.sh "bond-pair n list" "LPS layer list" [horizon binary]
#   e.g. bench/structures/equal_accuracy.sh "40 80" "4 6"
set -euo pipefail
ns=${1:-40 80}
layers=${2:-4}
bin=${3:-build/horizon}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
py() { python3 -c "print($1)"; }
a=0.5; h=${PLATE_H:-0.05}; q=1.0e5; E=200.0e9
source "$(dirname "${BASH_SOURCE[0]}")/plate_decks.sh"
bp_deck() {  # $1 n, $2 solver, $3 out
  plate_bp_deck "$a" "$h" "$(py "$a/$1")" "$E" "$q" "$2" "$3"
}
lps_deck() {  # $1 layers, $2 solver, $3 out
  plate_lps_deck "$a" "$h" "$(py "$h/$1")" "$E" "$q" "$2" "$3"
}
cpu_run() {  # args: horizon arguments; prints CPU seconds
  python3 - "$bin" "$@" <<'PY'
import os, resource, subprocess, sys
subprocess.run(sys.argv[1:2] + ["run", "-q"] + sys.argv[2:], env=dict(os.environ, OMP_NUM_THREADS="1"), check=True,
               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
r = resource.getrusage(resource.RUSAGE_CHILDREN)
print(r.ru_utime + r.ru_stime)
PY
}
case_run() {  # $1 kind (bp | lps), $2 n or layers
  local c=$1_$2 gen=${1}_deck
  $gen "$2" "{type: static, method: newton, linear_solver: $([ "$1" = bp ] && echo cholesky || echo matrix_free), tolerance: 1.0e-6, max_iterations: 10}" "$work/${c}_s" > "$work/${c}_s.yaml"
  $gen "$2" "{type: explicit, end_time: 1.0, safety_factor: 0.8}" "$work/${c}_e" > "$work/${c}_e.yaml"
  local ts t10 t60 dt
  ts=$(cpu_run "$work/${c}_s.yaml")
  cpu_run --end-time 1e-12 "$work/${c}_e.yaml" > /dev/null
  dt=$(python3 -c "import json; print(json.load(open('$work/${c}_e/summary.json'))['time_step'])")
  t10=$(cpu_run --end-time "$(py "9.5*$dt")" "$work/${c}_e.yaml")
  t60=$(cpu_run --end-time "$(py "109.5*$dt")" "$work/${c}_e.yaml")
  echo "$1 $2 $ts $(py "($t60-$t10)/100") $dt"
}
{
  for n in $ns; do case_run bp "$n"; done
  for l in $layers; do case_run lps "$l"; done
} > "$work/rows.txt"
python3 - "$work" "$a" "$h" "$q" "$E" <<'PY'
import json, math, os, sys
work, a, h, q, E = sys.argv[1], *map(float, sys.argv[2:])
nu = 1/3; D = E*h**3/(12*(1-nu*nu)); G = E/(2*(1+nu)); k = 5/6
navier = 0.00406235*q*a**4/D
mindlin = 0.0
for m in range(1, 400, 2):
    for n in range(1, 400, 2):
        al2 = math.pi**2*(m*m + n*n)/a**2
        s = math.sin(m*math.pi/2)*math.sin(n*math.pi/2)
        mindlin += 16*q/(math.pi**2*m*n)*s*(1/(D*al2*al2) + 1/(k*G*h*al2))
sys.path.insert(0, os.environ["PLATE_DECKS_DIR"])
from plate_centre import centre_w as centre_w_of
def centre_w(out):
    return centre_w_of(out, a)
print(f"a = {a} m, h = {h} m, q = {q} Pa: Kirchhoff (Navier) w_c = {navier:.4e} m, Mindlin w_c = {mindlin:.4e} m ({mindlin/navier:.4f} of Navier)")
for line in open(work + "/rows.txt"):
    kind, size, ts, per, dt = line.split()
    c = f"{kind}_{size}"
    s = json.load(open(f"{work}/{c}_s/summary.json"))
    w = centre_w(f"{work}/{c}_s")
    name = f"bond_pair n = {size}" if kind == "bp" else f"LPS {size} layers"
    ref = w/navier if kind == "bp" else w/mindlin
    print(f"{name:18s} particles {s['particles']:7d} | static {s['status']}, CPU {float(ts):7.2f} s, w_c/Navier {w/navier:.4f}, "
          f"w_c/{'Navier' if kind == 'bp' else 'Mindlin'} {ref:.4f} | explicit dt {float(dt):.3e} s, {float(per)*1e3:.3f} ms CPU/step")
PY
