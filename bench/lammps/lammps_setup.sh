# Sourced by the side-by-side scripts of bench/lammps: installs LAMMPS (Debian packages
# lammps and lammps-examples) and PyYAML (python3-yaml) when it is missing and sets `examples` to the folder of
# LAMMPS's examples/peri decks. $1: a deck of that folder that must exist (in.peri.pmb).
lammps_examples_dir() {
  local f
  f=$(dpkg -L lammps-examples 2>/dev/null | grep "/peri/${1//./\\.}\$" | head -n 1 || true)
  [ -z "$f" ] && f=$(find /usr/share -path "*examples/peri/$1" 2>/dev/null | head -n 1 || true)
  [ -n "$f" ] && dirname "$f"
}

lammps_setup() {
  if ! command -v lmp >/dev/null 2>&1 || [ -z "$(lammps_examples_dir "$1")" ]; then
    echo "installing LAMMPS (Debian packages lammps, lammps-examples)"
    local sudo=""
    [ "$(id -u)" -ne 0 ] && sudo=sudo
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq lammps lammps-examples >/dev/null
  fi
  # block.py reads and writes the decks with PyYAML (Debian's python3-yaml).
  if ! python3 -c 'import yaml' >/dev/null 2>&1; then
    local sudo=""
    [ "$(id -u)" -ne 0 ] && sudo=sudo
    echo "installing python3-yaml (Debian package)"
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq python3-yaml >/dev/null
  fi
  examples=$(lammps_examples_dir "$1")
  [ -n "$examples" ] || { echo "LAMMPS's examples/peri not found" >&2; exit 1; }
}

# Builds $build/horizon when it is missing ($root: the repository) and prints the run's
# header: date, CPU, load, both programs (and HORIZON_KERNEL_PATH when it forces a path).
horizon_build_and_header() {
  if [ ! -x "$build/horizon" ]; then
    cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release
    cmake --build "$build" --target horizon
  fi

  echo "date:    $(date -u +%Y-%m-%dT%H:%MZ)"
  echo "cpu:     $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'), $(nproc) cores"
  echo "load:    $(cut -d' ' -f1-3 /proc/loadavg) (1, 5, 15 min)"
  echo "lammps:  $(lmp -h | grep -m1 'Large-scale' | sed 's/^ *//'), $(command -v lmp)"
  echo "horizon: $("$build/horizon" --version), $build/horizon${HORIZON_KERNEL_PATH:+ (HORIZON_KERNEL_PATH=$HORIZON_KERNEL_PATH)}"
}
