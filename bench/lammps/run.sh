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

if [ ! -x "$build/horizon" ]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release
  cmake --build "$build" --target horizon
fi

echo "date:    $(date -u +%Y-%m-%dT%H:%MZ)"
echo "cpu:     $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'), $(nproc) cores"
echo "load:    $(cut -d' ' -f1-3 /proc/loadavg) (1, 5, 15 min)"
echo "lammps:  $(lmp -h | grep -m1 'Large-scale' | sed 's/^ *//'), $(command -v lmp)"
echo "horizon: $("$build/horizon" --version), $build/horizon${HORIZON_KERNEL_PATH:+ (HORIZON_KERNEL_PATH=$HORIZON_KERNEL_PATH)}"
echo "decks:   $examples/in.peri.{pmb,lps} and $here/{pmb,lps}.yaml"
python3 "$here/compare.py" --horizon "$build/horizon" --examples "$examples" --repeat "${REPEAT:-3}"
