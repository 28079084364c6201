#!/usr/bin/env bash
# Writes the deck of the 3-D LPS block of examples/block_tension_static.yaml (20 x 10 x 10
# mm steel, 20 MPa on the end layers, horizon 3 spacings, partial volumes, 3-2-1 supports)
# at spacing $1 [m], solver line $2 (YAML flow map), output directory $3, to stdout.
# Regions are one lattice layer or cell thick at any spacing.
set -euo pipefail
h=$1; solver=$2; out=$3
py() { python3 -c "print($1)"; }
cat <<DECK
dimension: 3
spacing: $h
horizon: $(py "3*$h")
partial_volume: true
materials:
  steel: {model: lps, density: 8000, youngs_modulus: 200.0e9, poissons_ratio: 0.3}
bodies:
  - name: block
    material: steel
    shape: {box: {min: [0, 0, 0], max: [0.02, 0.01, 0.01]}}
regions:
  left:   {box: {min: [0, 0, 0], max: [$(py "1.2*$h"), 0.01, 0.01]}}
  right:  {box: {min: [$(py "0.02-1.2*$h"), 0, 0], max: [0.02, 0.01, 0.01]}}
  pin:    {box: {min: [0, 0, 0], max: [$h, $h, $h]}}
  roller: {box: {min: [$(py "0.02-$h"), 0, 0], max: [0.02, $h, $h]}}
  guide:  {box: {min: [0, $(py "0.01-$h"), 0], max: [$h, 0.01, $h]}}
loads:
  - {region: left,   traction: [-2.0e7, 0, 0]}
  - {region: right,  traction: [2.0e7, 0, 0]}
  - {region: pin,    displacement: [0, 0, 0]}
  - {region: roller, displacement: [null, 0, 0]}
  - {region: guide,  displacement: [null, null, 0]}
solver: $solver
output: {directory: $out, frames: 1}
DECK
