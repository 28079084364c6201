#!/usr/bin/env bash
# Horizon against LAMMPS PERI on LAMMPS's own examples (examples/peri/in.peri.pmb and
# in.peri.lps), one thread each, both measured in this one run: time per step, bond
# evaluations per second, peak memory, mean damage and kinetic energy at steps 250,
# 500, 750, 1000, and the speed ratio. The last line reads `pmb_speedup=X lps_speedup=Y`.
#
#   bench/lammps/run.sh [build-dir]        (default: build; REPEAT=3 runs of each code)
#
# Installs LAMMPS (Debian packages lammps and lammps-examples) when it is missing.
# docs/benchmarks.md records the results and how to read them.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build}
mkdir -p "$build" && build=$(cd "$build" && pwd)

. "$here/lammps_setup.sh"
lammps_setup in.peri.pmb

horizon_build_and_header
echo "decks:   $examples/in.peri.{pmb,lps} and $here/{pmb,lps}.yaml"
python3 "$here/compare.py" --horizon "$build/horizon" --examples "$examples" --repeat "${REPEAT:-3}"
