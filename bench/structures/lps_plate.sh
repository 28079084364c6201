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
bp_deck() {  # $1 solver map, $2 output directory
cat <<DECK
dimension: 2
structure:
  type: plate
  supports:
    - {axis: x, at: 0.0, kind: simply_supported}
    - {axis: x, at: $a, kind: simply_supported}
    - {axis: y, at: 0.0, kind: simply_supported}
    - {axis: y, at: $a, kind: simply_supported}
thickness: $h
spacing: $dx
horizon_factor: 3
lattice_origin: [0.0, 0.0]
materials:
  steel: {model: bond_pair, density: 7800, youngs_modulus: $E, poissons_ratio: 0.3333333333333333}
bodies:
  - {name: plate, material: steel, shape: {box: {min: [0.0, 0.0], max: [$a, $a]}}}
loads:
  - {region: all, pressure: [0, 0, -$q]}
solver: $1
output: {directory: $2, frames: 1}
DECK
}
# The 3-D plate: particles at cell centres, 4 layers through h; simply supported along
# the bottom edges (w = 0 on the bottom layer's edge rows), pressure as a traction on
# the top layer; in-plane rigid motions held at a corner (3-2-1).
lps_deck() {
cat <<DECK
dimension: 3
spacing: $dx
horizon_factor: 3
materials:
  steel: {model: lps, density: 7800, youngs_modulus: $E, poissons_ratio: 0.3333333333333333}
bodies:
  - {name: plate, material: steel, shape: {box: {min: [0.0, 0.0, 0.0], max: [$a, $a, $h]}}}
regions:
  top: {box: {min: [-1, -1, $(py "$h-$dx")], max: [$(py "$a+1"), $(py "$a+1"), $h]}}
  edge_x0: {box: {min: [-1, -1, -1], max: [$dx, $(py "$a+1"), $dx]}}
  edge_x1: {box: {min: [$(py "$a-$dx"), -1, -1], max: [$(py "$a+1"), $(py "$a+1"), $dx]}}
  edge_y0: {box: {min: [-1, -1, -1], max: [$(py "$a+1"), $dx, $dx]}}
  edge_y1: {box: {min: [-1, $(py "$a-$dx"), -1], max: [$(py "$a+1"), $(py "$a+1"), $dx]}}
  corner: {box: {min: [-1, -1, -1], max: [$dx, $dx, $dx]}}
  corner_x: {box: {min: [$(py "$a-$dx"), -1, -1], max: [$(py "$a+1"), $dx, $dx]}}
loads:
  - {region: top, traction: [0, 0, -$q], normal: z}
  - {region: edge_x0, displacement: [null, null, 0]}
  - {region: edge_x1, displacement: [null, null, 0]}
  - {region: edge_y0, displacement: [null, null, 0]}
  - {region: edge_y1, displacement: [null, null, 0]}
  - {region: corner, displacement: [0, 0, null]}
  - {region: corner_x, displacement: [null, 0, null]}
solver: $1
output: {directory: $2, frames: 1}
DECK
}
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
import json, sys, math, glob, re, struct
work, a, h, q, E = sys.argv[1], *map(float, sys.argv[2:])
nu = 1/3
D = E*h**3/(12*(1-nu*nu))
navier = 0.00406235*q*a**4/D
def centre_w(out):
    f = sorted(glob.glob(out + "/frames/*.vtu"))[-1]
    data = open(f, "rb").read()
    he = data.index(b"<AppendedData"); start = data.index(b"_", he) + 1; head = data[:he].decode()
    def arr(name, nc):
        m = re.search(r'Name="%s" NumberOfComponents="%d"[^>]*offset="(\d+)"' % (name, nc), head)
        off = int(m.group(1)); nb = struct.unpack_from("<Q", data, start + off)[0]
        v = struct.unpack_from("<%dd" % (nb // 8), data, start + off + 8)
        return [v[i:i+nc] for i in range(0, len(v), nc)]
    X = arr("Points", 3); u = arr("displacement", 3)
    best = min(range(len(X)), key=lambda i: (X[i][0]-a/2)**2 + (X[i][1]-a/2)**2)
    xc, yc = X[best][0], X[best][1]
    ws = [u[i][2] for i in range(len(X)) if abs(X[i][0]-xc) < 1e-9 and abs(X[i][1]-yc) < 1e-9]
    return -sum(ws)/len(ws)
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
