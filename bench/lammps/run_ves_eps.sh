#!/usr/bin/env bash
# Horizon against LAMMPS PERI on LAMMPS's own viscoelastic and elastic-plastic examples
# (examples/peri/in.peri.ves and in.peri.eps; Horizon: bench/lammps/ves.yaml, eps.yaml),
# one thread each, both measured in this one run: time per step, bond evaluations per
# second, peak memory, mean damage and kinetic energy at steps 250, 500, 750, 1000, and
# the speed ratio. The last line reads `ves_speedup=X eps_speedup=Y`.
#
#   bench/lammps/run_ves_eps.sh [build-dir]    (default: build; REPEAT=3 runs of each code)
#   LAMMPS_ONLY=1 bench/lammps/run_ves_eps.sh  (LAMMPS alone, no Horizon run)
#   MODELS=ves bench/lammps/run_ves_eps.sh     (one model)
#
# Installs LAMMPS (Debian packages lammps and lammps-examples) when it is missing.
# bench/lammps/ves_eps_checks.py runs the control cases that explain the differences;
# docs/benchmarks.md ("the viscoelastic and elastic-plastic examples") records the results and how to read them.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build}
mkdir -p "$build" && build=$(cd "$build" && pwd)

. "$here/lammps_setup.sh"
lammps_setup in.peri.ves

extra=()
if [ -n "${LAMMPS_ONLY:-}" ]; then
  extra+=(--lammps-only)
elif [ ! -x "$build/horizon" ]; then
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
  cmake --build "$build" --target horizon
fi

echo "date:    $(date -u +%Y-%m-%dT%H:%MZ)"
echo "cpu:     $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'), $(nproc) cores"
echo "load:    $(cut -d' ' -f1-3 /proc/loadavg) (1, 5, 15 min)"
echo "lammps:  $(lmp -h | grep -m1 'Large-scale' | sed 's/^ *//'), $(command -v lmp)"
[ -z "${LAMMPS_ONLY:-}" ] && echo "horizon: $("$build/horizon" --version), $build/horizon"
echo "decks:   $examples/in.peri.{ves,eps} and $here/{ves,eps}.yaml"
python3 "$here/compare.py" --horizon "$build/horizon" --examples "$examples" --repeat "${REPEAT:-3}" \
  --models "${MODELS:-ves,eps}" "${extra[@]}"
