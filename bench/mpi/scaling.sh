#!/usr/bin/env bash
# Threads, ranks and LAMMPS PERI on one machine with many cores (docs/benchmarks.md
# "Sixteen cores"): bench/mpi/lammps_quarter.yaml (206,025 particles, 200 steps) with
#   - the serial program at 1, 2, 4, ... CORES threads,
#   - the MPI program at 1, 2, 4, ... CORES ranks of one thread and at CORES/4 ranks x 4,
#   - LAMMPS PERI on the same problem: LAMMPS's examples/peri/in.peri.pmb rewritten to the
#     quarter spacing (lattice, horizon, micromodulus x 256, volume, neighbour skin, time
#     step, 200 steps) at CORES ranks, and 20 steps on one rank (its loop time x 10).
# Prints one line per run: loop wall time, loop CPU time, state_crc32 (the same for every
# Horizon run).
#
#   bench/mpi/scaling.sh [build-dir] [cores]      (defaults: build, nproc)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build}
cores=${2:-$(nproc)}
deck=$here/lammps_quarter.yaml
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_WAIT_POLICY=passive

line() {  # line LABEL DIR
  python3 - "$1" "$2/summary.json" <<'EOF'
import json, sys
s = json.load(open(sys.argv[2]))
print("%-22s loop %.3f s  cpu %.3f s  crc %s" % (sys.argv[1], s["loop_time_s"], s["loop_cpu_time_s"], s["state_crc32"]))
EOF
}

echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'), $(nproc) cores"
t=1
while [ "$t" -le "$cores" ]; do
  "$build/horizon" run "$deck" -q -o "$tmp/t$t" --threads "$t" && line "threads $t" "$tmp/t$t"
  t=$((t * 2))
done
if [ -x "$build/horizon-mpi" ] && command -v mpirun >/dev/null; then
  for rt in $(r=1; while [ $r -le "$cores" ]; do echo "${r}x1"; r=$((r * 2)); done) "$((cores / 4))x4"; do
    r=${rt%x*}; th=${rt#*x}
    [ "$r" -ge 1 ] || continue
    mpirun -n "$r" --bind-to none "$build/horizon-mpi" run "$deck" -q -o "$tmp/m$rt" --threads "$th" && line "ranks x threads $rt" "$tmp/m$rt"
  done
fi
. "$root/bench/lammps/lammps_setup.sh"
lammps_setup in.peri.pmb
sed -e 's/^neighbor .*/neighbor        0.00025 bin/' -e 's/^lattice .*/lattice         sc 0.000125/' \
    -e 's/1.6863e22 0.0015001 0.0005 0.25/4.316928e24 0.000375025 0.0005 0.25/' \
    -e 's/volume 1.25e-10/volume 1.953125e-12/' -e 's/^timestep .*/timestep        2.5e-8/' \
    -e 's/^run .*/run             200/' "$examples/in.peri.pmb" > "$tmp/in.quarter"
sed 's/^run .*/run             20/' "$tmp/in.quarter" > "$tmp/in.quarter20"
(cd "$tmp" && mpirun -n "$cores" --bind-to none lmp -in in.quarter -log log.n >/dev/null && grep -h "Loop time" log.n)
(cd "$tmp" && lmp -in in.quarter20 -log log.1 >/dev/null && grep -h "Loop time" log.1)
