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
