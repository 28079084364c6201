# The two decks of the thin-plate benchmarks (lps_plate.sh, explicit_step.sh,
# equal_accuracy.sh), sourced by them: a simply supported square steel plate of side a and
# thickness h under a uniform pressure q, nu = 1/3, horizon 3 spacings.
# Both print a deck; arguments: a h dx E q solver-map output-directory.
PLATE_DECKS_DIR=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
export PLATE_DECKS_DIR  # plate_centre.py, for the scripts' Python
plate_py() { python3 -c "print($1)"; }

# O'Grady's bond-pair plate (model bond_pair), one node through the thickness.
plate_bp_deck() {
  local a=$1 h=$2 dx=$3 E=$4 q=$5 solver=$6 out=$7
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
solver: $solver
output: {directory: $out, frames: 1}
DECK
}

# The 3-D LPS plate: particles at cell centres, h/dx layers through the thickness; simply
# supported along the bottom edges (w = 0 on the bottom layer's edge rows), the pressure
# as a traction on the top layer; in-plane rigid motions held at a corner (3-2-1).
plate_lps_deck() {
  local a=$1 h=$2 dx=$3 E=$4 q=$5 solver=$6 out=$7
  cat <<DECK
dimension: 3
spacing: $dx
horizon_factor: 3
materials:
  steel: {model: lps, density: 7800, youngs_modulus: $E, poissons_ratio: 0.3333333333333333}
bodies:
  - {name: plate, material: steel, shape: {box: {min: [0.0, 0.0, 0.0], max: [$a, $a, $h]}}}
regions:
  top: {box: {min: [-1, -1, $(plate_py "$h-$dx")], max: [$(plate_py "$a+1"), $(plate_py "$a+1"), $h]}}
  edge_x0: {box: {min: [-1, -1, -1], max: [$dx, $(plate_py "$a+1"), $dx]}}
  edge_x1: {box: {min: [$(plate_py "$a-$dx"), -1, -1], max: [$(plate_py "$a+1"), $(plate_py "$a+1"), $dx]}}
  edge_y0: {box: {min: [-1, -1, -1], max: [$(plate_py "$a+1"), $dx, $dx]}}
  edge_y1: {box: {min: [-1, $(plate_py "$a-$dx"), -1], max: [$(plate_py "$a+1"), $(plate_py "$a+1"), $dx]}}
  corner: {box: {min: [-1, -1, -1], max: [$dx, $dx, $dx]}}
  corner_x: {box: {min: [$(plate_py "$a-$dx"), -1, -1], max: [$(plate_py "$a+1"), $dx, $dx]}}
loads:
  - {region: top, traction: [0, 0, -$q], normal: z}
  - {region: edge_x0, displacement: [null, null, 0]}
  - {region: edge_x1, displacement: [null, null, 0]}
  - {region: edge_y0, displacement: [null, null, 0]}
  - {region: edge_y1, displacement: [null, null, 0]}
  - {region: corner, displacement: [0, 0, null]}
  - {region: corner_x, displacement: [null, 0, null]}
solver: $solver
output: {directory: $out, frames: 1}
DECK
}
