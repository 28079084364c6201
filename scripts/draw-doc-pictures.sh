#!/usr/bin/env bash
# Draws the pictures of README.md and docs/images with `horizon plot` and `horizon render`
# (docs/input.md "Pictures"), from runs of the examples. Usage:
#   scripts/draw-doc-pictures.sh [OUT_DIR] [THREADS]      (default: out/pictures, 2)
# On 2026-11-28 they were drawn on a shared 2-core machine, so the runs marked COARSE use
# --coarsen (fewer particles, as the captions in docs/verification.md say); on a larger
# machine drop --coarsen to draw the full-size figures, and set FULL=1 for the runs
# only a larger machine can do. Runs that already have a history.csv are not
# repeated.
set -euo pipefail
cd "$(dirname "$0")/.."
H=${HORIZON:-build/horizon}
OUT=${1:-out/pictures}
THREADS=${2:-2}
IMG=docs/images
mkdir -p "$OUT"

run() {  # run NAME DECK [options]
  local name=$1; shift
  [ -f "$OUT/$name/history.csv" ] || "$H" run "$@" -o "$OUT/$name" --threads "$THREADS" -q
}

# README: crack branching in glass (full size, the `make demo` run).
run glass_branching examples/glass_branching.yaml
"$H" render "$OUT/glass_branching" --field damage -o "$IMG/glass_branching_damage.png"

# Load-displacement, force and relaxation curves (full size).
run notched_beam examples/notched_beam.yaml
"$H" plot "$OUT/notched_beam" --x load:displacement_uy --x-scale -1 --y load:displacement_fy --y-scale -1 \
  --title "Notched beam, three-point bending" -o "$IMG/notched_beam_load_displacement.png"
run plastic_necking_bar examples/plastic_necking_bar.yaml
"$H" plot "$OUT/plastic_necking_bar" --x time --y right:velocity_fx --title "Necking bar" \
  -o "$IMG/plastic_necking_bar_force.png"
"$H" render "$OUT/plastic_necking_bar" --field plastic_strain --slice z=0.0025 -o "$IMG/plastic_necking_bar.png"
run viscoelastic_relaxation examples/viscoelastic_relaxation.yaml
"$H" plot "$OUT/viscoelastic_relaxation" --x time --y right:velocity_fx --title "Viscoelastic relaxation" \
  -o "$IMG/viscoelastic_relaxation_force.png"

# Plates and shells (full size).
run plate_navier examples/plate_navier.yaml
"$H" render "$OUT/plate_navier" --field deflection --width 800 -o "$IMG/plate_navier_deflection.png"
run pinched_tube examples/pinched_tube.yaml
"$H" render "$OUT/pinched_tube" --field displacement -o "$IMG/pinched_tube.png"
run double_torsion examples/double_torsion.yaml
"$H" render "$OUT/double_torsion/frames/frame_00032.vtu" --field damage -o "$IMG/double_torsion_damage.png"
run plate_with_hole examples/plate_with_hole.yaml
"$H" render "$OUT/plate_with_hole" --field stress_yy -o "$IMG/plate_with_hole_stress_yy.png"

# Thermal shock (full size).
run thermal_shock examples/thermal_shock.yaml
"$H" render "$OUT/thermal_shock" --field damage -o "$IMG/thermal_shock.png"
"$H" render "$OUT/thermal_shock" --field temperature -o "$IMG/thermal_shock_temperature.png"

# Taylor bar: COARSE, --coarsen 1.4 (6,372 particles, README), its mid-plane.
run taylor_bar examples/taylor_bar.yaml --coarsen 1.4
"$H" render "$OUT/taylor_bar" --field equivalent_plastic_strain --slice z=0 -o "$IMG/taylor_bar.png"

# Edge-on impact at 35 m/s (full size, 22,176 particles).
run edge_on_impact_35 examples/edge_on_impact_35.yaml
"$H" render "$OUT/edge_on_impact_35" --field damage -o "$IMG/edge_on_impact_35_damage.png"

# Kalthoff-Winkler, Tupek's model, p = 0: COARSE, --coarsen 2 (36,450 particles).
run kalthoff_winkler examples/kalthoff_winkler.yaml --coarsen 2
"$H" render "$OUT/kalthoff_winkler" --field damage -o "$IMG/kalthoff_winkler_damage.png"

# Kalthoff-Winkler with PMB bonds (full size, 147,968 particles: 19 s of CPU).
run kalthoff_winkler_pmb examples/kalthoff_winkler_pmb.yaml
"$H" render "$OUT/kalthoff_winkler_pmb" --field damage -o "$IMG/kalthoff_winkler_pmb_damage.png"

# Rigid projectiles (docs/verification.md "Rigid projectiles"): the filtered deceleration
# of the reduced-size examples, the documented runs (4 to 7 s of CPU each), drawn by
# scripts/perforation_figures.py through `horizon plot`.
run plate_perforation examples/plate_perforation.yaml
run plate_perforation_coupled examples/plate_perforation_coupled.yaml
HORIZON_PLOT=(--horizon "$H" --png "$IMG/accel")
python3 scripts/perforation_figures.py --name ball "$OUT/plate_perforation" "$OUT/plate_perforation_coupled" \
  "${HORIZON_PLOT[@]}" --title "Sphere at 500 m/s through a 12.5 mm plate: peridynamics" \
  "Sphere at 500 m/s through a 12.5 mm plate: PD core in hex8 elements" > /dev/null
run ogive_cube examples/ogive_cube.yaml
run ogive_cube_quadratic examples/ogive_cube_quadratic.yaml
python3 scripts/perforation_figures.py --name nose "$OUT/ogive_cube" "$OUT/ogive_cube_quadratic" \
  "${HORIZON_PLOT[@]}" --title "Ogive at 700 m/s into an aluminium cube (half size): linear penalty" \
  "Ogive at 700 m/s into an aluminium cube (half size): quadratic penalty" > /dev/null

# The Taylor bar finer than full size (docs/verification.md "Taylor bar"): 28,421
# particles, 10,853 adaptive steps to 68.8 us (694 s of CPU on 2026-11-29).
run taylor_bar_085 examples/taylor_bar.yaml --coarsen 0.85 --end-time 6.88e-5
"$H" render "$OUT/taylor_bar_085" --field equivalent_plastic_strain --slice z=0 -o "$IMG/taylor_bar_085.png"

# Full size, minutes of CPU each (2026-11-29 on one thread: 164 s, 113 s, 613 s): at
# --coarsen 2 to 4 these runs show damage the full-size runs do not (docs/verification.md,
# "The pictures"), so they are drawn from the full-size runs.
run kalthoff_winkler_projectile examples/kalthoff_winkler_projectile.yaml
"$H" render "$OUT/kalthoff_winkler_projectile" --field damage -o "$IMG/kalthoff_winkler_projectile_damage.png"
# p = 2 (the thesis's eq. 6.3) at delta/spacing 4 (docs/verification.md).
sed 's/, failure_length_exponent: 0//; s/^spacing: .*/spacing: 0.0004625/; s/max: \[0.00039, 0.0245\]/max: [0.00048, 0.0245]/' \
  examples/kalthoff_winkler.yaml > "$OUT/kw_p2h4.yaml"
run kw_p2h4 "$OUT/kw_p2h4.yaml"
"$H" render "$OUT/kw_p2h4" --field damage -o "$IMG/kalthoff_winkler_p2_damage.png"
run edge_on_impact examples/edge_on_impact.yaml
"$H" render "$OUT/edge_on_impact" --field damage -o "$IMG/edge_on_impact_damage.png"

# With FULL=1 only: the 3-D plate (2.13 million particles, 243.7 million bonds) takes 3.5
# GiB of memory, 3.8 GB of frames and about 10 min of CPU on one thread (569 s on
# 2026-11-29); at --coarsen 3 and 4 it shows a crack from the far edge that the
# full-size run does not.
if [ "${FULL:-0}" = 1 ]; then
  # In 3-D, seen from above (the projection along z), at the full run's 58.8 µs.
  run kalthoff_winkler_3d examples/kalthoff_winkler_3d.yaml --end-time 5.88e-5
  "$H" render "$OUT/kalthoff_winkler_3d" --field damage -o "$IMG/kalthoff_winkler_3d.png"
fi

# Ballistic limit: the table of docs/verification.md ("Ballistic plate"; the runs take
# 2 min of CPU each: python3 scripts/ballistic_limit.py --png draws the same plot).
mkdir -p "$OUT/ballistic_plate"
printf 'impact_velocity,residual_velocity\n200,0\n350,192.6\n500,338.2\n650,467.6\n800,589.8\n' \
  > "$OUT/ballistic_plate/residual.csv"
"$H" plot "$OUT/ballistic_plate/residual.csv" --x impact_velocity --y residual_velocity \
  --x-label "Impact velocity (m/s)" --y-label "Residual velocity (m/s)" --title "Steel sphere on a 6 mm 6061-T6 plate" \
  -o "$IMG/ballistic_plate.png"
