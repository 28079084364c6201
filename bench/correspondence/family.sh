#!/bin/bash
# The correspondence family's decks for checking bits and timing a change of its law code
# (issue 30, ps30): a copper bar, 2-D plane stress (480 particles) or 3-D (512), hitting a
# rigid wall at 227 m/s for 4 us, with each stress law of `correspondence` (affine pass;
# Peridigm's hourglass force: the general pass; a thermal strain: the general pass with
# the thermal split) and of `bond_associated_correspondence` (3-D, semi-Lagrangian, 2-D
# plane stress). Prints per deck: state_crc32, steps and loop_time_s (one thread).
#   bench/correspondence/family.sh BIN [OUTDIR] [REGEX]
# Compare the crc column of two binaries to show a change kept the bits.
set -u
bin=$1
out=${2:-/tmp/correspondence_family}
only=${3:-.}
mkdir -p "$out"
deck() {  # name dim model law extra-material-lines extra-top-level-lines
  local name=$1 dim=$2 model=$3 law=$4 mat=$5 top=$6 f="$out/$1.yaml"
  if [ "$dim" = 2 ]; then
    printf 'dimension: 2\nplane: stress\nthickness: 1.0e-3\n' > "$f"
    box='{min: [-0.003, 0.0002], max: [0.003, 0.02]}'; v='[0, -227]'; c='[0, -10]'
  else
    printf 'dimension: 3\n' > "$f"
    box='{min: [-0.002, 0.0002, -0.001], max: [0.002, 0.008, 0.001]}'; v='[0, -227, 0]'; c='[0, -10, 0]'
  fi
  cat >> "$f" <<DECK
spacing: 0.5e-3
horizon_factor: 3
materials:
  copper:
    model: $model
    density: 8930
    bulk_modulus: 1.3e11
    shear_modulus: 4.3e10
    stress_law: $law
    yield_stress: 2.0e8
    hardening_modulus: 1.0e8
$(printf "$mat")
bodies:
  - {name: bar, material: copper, shape: {box: $box}}
initial_conditions:
  - {region: all, velocity: $v}
contact:
  short_range: false
  indenters:
    - {name: wall, center: $c, radius: 10, stiffness: 1.0e22}
solver: {type: explicit, end_time: 4.0e-6, safety_factor: 0.5}
output: {directory: $out/run, frames: 1}
$(printf "$top")
DECK
}
hg='    stabilization: 0.02\n    stabilization_form: peridigm'
th='    thermal: {conductivity: 400, specific_heat: 385, expansion: 1.7e-5, reference_temperature: 293}'
for law in linear_elastic neo_hookean j2; do
  deck ps_${law}_0 2 correspondence $law '    stabilization: 0' ''
  deck ps_${law}_0.5 2 correspondence $law '    stabilization: 0.5' ''
done
deck ps_j2_peridigm 2 correspondence j2 "$hg" ''
deck ps_neo_peridigm 2 correspondence neo_hookean "$hg" ''
for law in linear_elastic j2 hypoelastic_j2; do deck g3_$law 3 correspondence $law "$hg" ''; done
deck th_ps_j2_0.5 2 correspondence j2 "    stabilization: 0.5\n$th" 'thermal:\n  initial_temperature: 600'
deck th_ps_neo_hookean_0 2 correspondence neo_hookean "    stabilization: 0\n$th" 'thermal:\n  initial_temperature: 600'
deck th_g3_j2 3 correspondence j2 "$hg\n$th" 'thermal:\n  initial_temperature: 600'
deck th_g3_hypoelastic_j2 3 correspondence hypoelastic_j2 "$hg\n$th" 'thermal:\n  initial_temperature: 600'
for law in linear_elastic neo_hookean j2 hypoelastic hypoelastic_j2; do
  deck ba_$law 3 bond_associated_correspondence $law '' ''
done
deck ba_semi 3 bond_associated_correspondence hypoelastic_j2 '    kinematics: semi_lagrangian\n    rotation_update: peridigm' ''
deck baps_j2 2 bond_associated_correspondence j2 '' ''
deck baps_neo_hookean 2 bond_associated_correspondence neo_hookean '' ''
for f in "$out"/*.yaml; do
  name=$(basename "$f" .yaml)
  [[ $name =~ $only ]] || continue
  rm -rf "$out/run"
  if OMP_NUM_THREADS=1 "$bin" run -q --threads 1 "$f" -o "$out/run" > "$out/$name.log" 2>&1; then
    python3 -c "import json; d = json.load(open('$out/run/summary.json')); print('$name', d['state_crc32'], d['steps'], d['loop_time_s'])"
  else
    echo "$name FAILED: $(tail -1 "$out/$name.log")"
  fi
done
