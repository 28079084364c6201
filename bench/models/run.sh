#!/usr/bin/env bash
# Per-model cost of the explicit force pass (issue 31, scope 3): one deck, only the model
# changed. A cube of 30^3 particles (spacing 1 mm, horizon 3.015 spacings, E = 200 GPa,
# nu = 1/4 where the model takes two constants) expanding from its centre
# (v = 5000/s * x: every bond stretches at the same rate, the outer bonds break from
# step ~50 on at s0 = 0.01), 100 steps of the stable time step (safety 0.8), one thread.
# For each model of the registry that runs on a solid (bond_pair models beams, plates and
# shells: skipped), the loop's CPU time (summary.json loop_cpu_time_s, user + system of
# the time loop: less sensitive than wall time to a shared machine) per directed bond and
# step, median of $REPEAT runs, and its ratio to the LPS's median. Usage, from the
# repository root after a build:
#   bench/models/run.sh [horizon binary]          (REPEAT=3, STEPS=100, N=30, MODELS="pmb lps ...")
# MODELS may also name correspondence_j2, correspondence_neo_hookean and
# correspondence_hypoelastic_j2 (correspondence with those stress laws; not in the default
# list).
# BACKENDS="cpu flat" runs each model with each explicit backend (solver.backend), the
# backends' runs interleaved within each repeat; a row is named model@backend (cpu: model).
# docs/benchmarks.md ("Every model on one deck") records the results.
set -euo pipefail
bin=$(realpath "${1:-build/horizon}")
repeat=${REPEAT:-3}
steps=${STEPS:-100}
n=${N:-30}
backends=${BACKENDS:-cpu}
models=${MODELS:-"pmb lps elastic_plastic viscoelastic microplastic nonlinear_solid correspondence extended_correspondence"}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
half=$(python3 -c "print(($n - 1) * 0.5e-3 + 1e-9)")

# The model's own lines of the material (its parameters and damage law).
model_lines() {
  case "$1" in
    pmb) echo "    youngs_modulus: 200.0e9
    damage: {critical_stretch: 0.01}" ;;
    microplastic) echo "    youngs_modulus: 200.0e9
    yield_stretch: 0.004
    damage: {critical_stretch: 0.01}" ;;
    lps | correspondence | pals) echo "    youngs_modulus: 200.0e9
    poissons_ratio: 0.25
    damage: {critical_stretch: 0.01}" ;;
    elastic_plastic) echo "    youngs_modulus: 200.0e9
    poissons_ratio: 0.25
    yield_stress: 1.0e9
    hardening_modulus: 2.0e9
    damage: {critical_stretch: 0.01}" ;;
    viscoelastic) echo "    youngs_modulus: 200.0e9
    poissons_ratio: 0.25
    lambda_1: 0.5
    tau_1: 1.0e-6
    damage: {critical_stretch: 0.01}" ;;
    nonlinear_solid) echo "    youngs_modulus: 200.0e9
    poissons_ratio: 0.25
    damage: {law: energy, fracture_energy: 2000}" ;;
    correspondence_j2) echo "    youngs_modulus: 200.0e9
    poissons_ratio: 0.25
    stress_law: j2
    yield_stress: 1.0e9
    hardening_modulus: 2.0e9
    damage: {critical_stretch: 0.01}" ;;
    correspondence_hypoelastic_j2) echo "    youngs_modulus: 200.0e9
    poissons_ratio: 0.25
    stress_law: hypoelastic_j2
    yield_stress: 1.0e9
    hardening_modulus: 2.0e9
    damage: {critical_stretch: 0.01}" ;;
    correspondence_neo_hookean) echo "    youngs_modulus: 200.0e9
    poissons_ratio: 0.25
    stress_law: neo_hookean
    damage: {critical_stretch: 0.01}" ;;
    extended_correspondence) echo "    youngs_modulus: 200.0e9
    poissons_ratio: 0.25
    stress_law: j2
    yield_stress: 1.0e9
    hardening_modulus: 2.0e9
    stabilization: 0.1
    damage: {critical_stretch: 0.01}" ;;
    *) echo "bench/models/run.sh: no deck lines for model '$1'" >&2; exit 2 ;;
  esac
}

# The registry's model of a bench entry: correspondence_<law> is the correspondence model
# with that stress law (the default is linear_elastic).
model_of() {
  case "$1" in
    correspondence_*) echo correspondence ;;
    *) echo "$1" ;;
  esac
}

deck() {  # $1 model
  cat <<YAML
dimension: 3
spacing: 1.0e-3
horizon: 3.015e-3
materials:
  solid:
    model: $(model_of "$1")
    density: 7800
$(model_lines "$1")
bodies:
  - {name: cube, material: solid, shape: {box: {min: [-$half, -$half, -$half], max: [$half, $half, $half]}}}
initial_conditions:
  - {region: all, velocity: ["5000*x", "5000*y", "5000*z"]}
solver: {type: explicit, end_time: 1.0, safety_factor: 0.8}
output: {directory: $work/out_$1, frames: 1}
YAML
}

echo "date:    $(date -u +%Y-%m-%dT%H:%MZ)"
echo "cpu:     $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'), $(nproc) cores"
echo "load:    $(cut -d' ' -f1-3 /proc/loadavg) (1, 5, 15 min)"
echo "horizon: $("$bin" --version), $bin; commit $(git -C "$(dirname "$0")" rev-parse --short HEAD 2>/dev/null || echo '?')"
echo "deck:    ${n}^3 cube, $steps steps, one thread, CPU time of the loop, median of $repeat"
results="$work/results.txt"
: > "$results"
for m in $models; do
  deck "$m" > "$work/$m.yaml"
  # The stable time step of this model on this deck (a run of one step reports it).
  OMP_NUM_THREADS=1 "$bin" run -q --end-time 1e-300 "$work/$m.yaml" > /dev/null
  dt=$(python3 -c "import json; print(json.load(open('$work/out_$m/summary.json'))['time_step'])")
  end=$(python3 -c "print(($steps - 0.5) * $dt)")
  declare -A per=()
  for r in $(seq "$repeat"); do
    for b in $backends; do
      OMP_NUM_THREADS=1 "$bin" run -q --threads 1 --backend "$b" --end-time "$end" "$work/$m.yaml" > /dev/null 2>&1
      per[$b]+=" $(python3 - "$work/out_$m/summary.json" "$steps" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert d["steps"] == int(sys.argv[2]), d["steps"]
print(d["loop_cpu_time_s"] / (d["bonds"] * d["steps"]) * 1e9, d["bonds"], d["damage"].get("mean", 0) if isinstance(d["damage"], dict) else 0)
PY
)"
    done
  done
  for b in $backends; do
    name=$m
    [ "$b" = cpu ] || name="$m@$b"
    echo "$name ${per[$b]}" >> "$results"
  done
  unset per
done
python3 - "$results" <<'PY'
import statistics, sys
rows = []
for line in open(sys.argv[1]):
    f = line.split()
    name, vals = f[0], f[1:]
    ns = [float(vals[i]) for i in range(0, len(vals), 3)]
    rows.append((name, statistics.median(ns), int(vals[1]), float(vals[2]), ns))
lps = next((r[1] for r in rows if r[0] == "lps"), None)
print(f"{'model':26s} {'ns/bond-step':>12s} {'x LPS':>6s} {'bonds':>9s} {'damage':>8s}  runs")
for name, med, bonds, dmg, ns in rows:
    ratio = f"{med / lps:6.2f}" if lps else "     -"
    print(f"{name:26s} {med:12.1f} {ratio} {bonds:9d} {dmg:8.4f}  {', '.join(f'{x:.1f}' for x in ns)}")
PY
