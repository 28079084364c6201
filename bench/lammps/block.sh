#!/usr/bin/env bash
# Horizon against LAMMPS PERI on a static 17^3 block (485,402 directed bonds, 200 steps,
# one thread each, both measured in this one run): ns per directed bond-step and the ratio,
# per model (block.py says how the decks are made). The last line reads
# `block_pmb=X block_lps=Y ...`.
#
#   bench/lammps/block.sh [build-dir]      (MODELS=pmb,lps[,ves,eps]; REPEAT=3 runs of each code)
#
# Installs LAMMPS (Debian packages lammps and lammps-examples) when it is missing.
# docs/benchmarks.md records the results.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build}
mkdir -p "$build" && build=$(cd "$build" && pwd)

. "$here/lammps_setup.sh"
lammps_setup in.peri.pmb

horizon_build_and_header
python3 "$here/block.py" --horizon "$build/horizon" --examples "$examples" --repeat "${REPEAT:-3}" \
  --models "${MODELS:-pmb,lps}"
