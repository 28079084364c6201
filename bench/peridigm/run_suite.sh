#!/usr/bin/env bash
# Peridigm's own test suite through Horizon's importer (docs/peridigm.md, "Peridigm's
# suite"): every deck (YAML or XML) of a Peridigm checkout's test/ and examples/ folders
# runs unchanged, and each Exodus file it writes is compared with the deck's
# <Output Filename>_gold.e under the folder's .comp tolerances (compare_exodus.py:
# Horizon's reading of exodiff's command files; exodiff is not in Debian).
#
#   bench/peridigm/run_suite.sh PERIDIGM_CHECKOUT [WORK_DIR]
#
# Environment: HORIZON (default build/horizon), HORIZON_MPI (default build/horizon-mpi),
# TIME_LIMIT seconds per deck and rank count (default 120), NP4=0 to skip the 4-rank runs
# (run, where the deck's folder has an np4 folder, for decks that ran on 1 rank), ONLY=regex
# to run the decks whose path matches.
#
# Each deck runs as Peridigm's own test scripts run it (test/.../npN/*.py: `cd npN;
# mpiexec -np N Peridigm ../deck.xml`): from a scratch folder holding links to the files
# of the deck's npN/ folder (its np1/mesh.g, its np4/mesh.g.4.0..3), so that a mesh the
# deck names relative to the working directory is found there (docs/peridigm.md, "File
# names"). A deck file inside an npN/ folder (a copy some folders hold; Peridigm's scripts
# run the deck above it) runs from a folder linking its own folder's files.
#
# Prints one Markdown table row per deck and rank count:
#   | deck | ranks | result | detail | wall s |
# result: match (every compared variable within tolerance), differs (the largest excess:
# variable, values, node, step), refused (Horizon's error for the deck), missing (the deck
# names an input file that exists nowhere in the checkout: Peridigm's snapshot lacks it,
# e.g. a mesh its scripts or Cubit generate, or a name no file has), fails (the run stopped
# with an error), timeout, runs (no gold to compare). A summary follows.
set -u
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
[ $# -ge 1 ] || { echo "usage: $0 PERIDIGM_CHECKOUT [WORK_DIR]" >&2; exit 2; }
checkout=$(cd "$1" && pwd) || exit 2
work=${2:-$(mktemp -d /tmp/peridigm_suite.XXXXXX)}
mkdir -p "$work"; work=$(cd "$work" && pwd)
horizon=${HORIZON:-$root/build/horizon}
horizon_mpi=${HORIZON_MPI:-$root/build/horizon-mpi}
limit=${TIME_LIMIT:-120}
np4=${NP4:-1}
only=${ONLY:-}
compare="$here/compare_exodus.py"
python=/usr/bin/python3  # Debian's, with python3-netcdf4
[ -x "$horizon" ] || { echo "no Horizon binary at $horizon (set HORIZON)" >&2; exit 2; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMP_NUM_THREADS=${OMP_NUM_THREADS:-1}

# Decks: YAML files whose top key is Peridigm, XML files that are a ParameterList.
mapfile -t decks < <(cd "$checkout" && find test examples \( -name '*.yaml' -o -name '*.xml' \) 2>/dev/null |
  sort | while read -r f; do grep -qE '^Peridigm:|<ParameterList' "$f" && echo "$f"; done)

n_total=0; n_runs=0; n_match=0; n_refused=0; n_missing=0; n_differs=0; n_fails=0; n_timeout=0; n_copies=0
one_line() { tr '\n' ' ' | sed -e 's/|/\\|/g' -e 's/  */ /g' | cut -c1-300; }

# A git symbolic link that the checkout holds as a plain file (a snapshot or a clone with
# core.symlinks=false writes the link's target, e.g. `../Mesh.g`, as the file's whole text;
# Peridigm's npN/ folders link their serial mesh so): the file it points to; any other
# file: itself.
resolved() {
  local f=$1 target
  if [ -f "$f" ] && [ "$(stat -c %s "$f")" -lt 512 ]; then
    target=$(head -c 511 "$f")
    if [[ $target != *$'\n'* && $target != /* && -n $target && -f "$(dirname "$f")/$target" ]] &&
       ! grep -q '[^ -~]' <<<"$target"; then
      echo "$(dirname "$f")/$target"; return
    fi
  fi
  echo "$f"
}

# run DECK RANKS: one row.
run() {
  local deck=$1 ranks=$2
  local dir; dir=$(dirname "$checkout/$deck")
  local wd="$work/$(echo "$deck" | tr '/' '_')_np$ranks"
  rm -rf "$wd"; mkdir -p "$wd"
  # The working directory Peridigm's scripts give the deck: its npN/ folder (N = ranks),
  # or for a copy inside an npN/ folder, that folder.
  local from=""
  if [[ $dir =~ /np[0-9]+$ ]]; then from=$dir; elif [ -d "$dir/np$ranks" ]; then from="$dir/np$ranks"; fi
  if [ -n "$from" ]; then
    local f
    for f in "$from"/*; do [ -f "$f" ] && ln -s "$(resolved "$f")" "$wd/$(basename "$f")"; done
  fi
  # A copy in an npN/ folder whose files include such a link (ElasticBondAssociated...'s
  # np1/ and np4/ copies: `Mesh.g` is the text `../Mesh.g`) runs from a view of its folders
  # with the links followed, tree/ (the deck's parent's files) and tree/npN/ (its own), so
  # that the deck's names resolve as they do in a checkout with symbolic links.
  local deck_path="$checkout/$deck"
  if [[ $dir =~ /np[0-9]+$ ]]; then
    local f needs=""
    for f in "$dir"/*; do [ "$(resolved "$f")" != "$f" ] && needs=1; done
    if [ -n "$needs" ]; then
      local tree="$wd/tree" sub; sub=$(basename "$dir")
      mkdir -p "$tree/$sub"
      for f in "$(dirname "$dir")"/*; do [ -f "$f" ] && ln -s "$(resolved "$f")" "$tree/$(basename "$f")"; done
      for f in "$dir"/*; do [ -f "$f" ] && ln -s "$(resolved "$f")" "$tree/$sub/$(basename "$f")"; done
      deck_path="$tree/$sub/$(basename "$deck")"
    fi
  fi
  local result detail
  local start; start=$(date +%s.%N)
  # A folder that ships its mesh as a generator script (examples/fragmenting_cylinder:
  # fragmenting_cylinder_generate_mesh.py writes the .txt mesh and node set into the
  # directory it runs in) gets the mesh its user would make: the script runs in the
  # scratch folder first, which is the deck's working directory (docs/peridigm.md, "File
  # names"). Its wall time counts in the deck's.
  local gen
  for gen in "$dir"/*generate_mesh.py; do
    [ -f "$gen" ] && (cd "$wd" && "$python" "$gen" >generate.log 2>&1)
  done
  # check first: a refused deck is Horizon's error before any run
  if ! (cd "$wd" && timeout -k 10 "$limit" "$horizon" check "$deck_path" >check.log 2>&1); then
    result=refused
    detail=$(grep -m1 -i 'error' "$wd/check.log" | sed "s|$checkout/||g" | one_line)
    [ -n "$detail" ] || detail=$(tail -n 2 "$wd/check.log" | one_line)
    # An input file that exists nowhere in the checkout (nor as partitioned pieces).
    local missing
    missing=$(grep -m1 -oE "cannot open [^']*'[^']+'" "$wd/check.log" | sed -E "s/.*'([^']+)'$/\1/")
    if [ -n "$missing" ]; then
      missing=$(basename "$missing")
      if [ -z "$(find "$checkout" -name "$missing" -o -name "$missing.*.*" 2>/dev/null | head -n 1)" ]; then
        result=missing; detail="'$missing' exists nowhere in the checkout; $detail"
      fi
    fi
  else
    local cmd=("$horizon" run "$deck_path")
    [ "$ranks" -gt 1 ] && cmd=(mpiexec -n "$ranks" --oversubscribe "$horizon_mpi" run "$deck_path")
    (cd "$wd" && timeout -k 10 "$limit" "${cmd[@]}" >run.log 2>&1)
    local rc=$?
    if [ $rc -eq 124 ] || [ $rc -eq 137 ]; then  # 137: killed 10 s after the limit (a run that finishes its frame on SIGTERM)
      result=timeout; detail="over ${limit} s"
    elif [ $rc -ne 0 ]; then
      result=fails; detail=$(grep -m1 -iE 'error|^horizon: ' "$wd/run.log" | sed "s|$checkout/||g" | one_line)
      [ -n "$detail" ] || detail="exit $rc: $(tail -n 1 "$wd/run.log" | one_line)"
    else
      result=runs; detail="no gold"
      local worst="" e name gold comp out
      while read -r e; do
        name=$(basename "$e" .e)
        gold=""; comp=""
        for d in "$dir" "$(dirname "$dir")"; do
          [ -z "$gold" ] && [ -f "$d/${name}_gold.e" ] && gold="$d/${name}_gold.e"
          [ -z "$comp" ] && [ -f "$d/${name}.comp" ] && comp="$d/${name}.comp"
        done
        if [ -z "$comp" ] && [ -n "$gold" ]; then
          comp=$(ls "$(dirname "$gold")"/*.comp 2>/dev/null | head -n 1)
        fi
        [ -n "$gold" ] && [ -n "$comp" ] || continue
        # A copy in an npN/ folder is compared at the times of the gold of the deck above
        # it (its own Output Frequency may differ: compare_exodus.py --at-gold-times).
        local at=()
        [[ $dir =~ /np[0-9]+$ ]] && at=(--at-gold-times)
        out=$("$python" "$compare" "$e" "$gold" "$comp" "${at[@]}" 2>&1 | tail -n 1)
        case "$out" in
          match) [ "$result" = runs ] && { result=match; detail="$name"; } || { [ "$result" = match ] && detail="$detail, $name"; } ;;
          *) result=differs; worst="$name: $out" ;;
        esac
      done < <(find "$wd/out" -name '*.e' 2>/dev/null | sort)
      # A gold no output file is named after, of a deck whose Output lists write NAME_*.e:
      # Peridigm's script conjoins them into NAME.e first (Compression_QS_Explicit_
      # MultiFreqOutput: _QS.e and _Explicit.e); compare_exodus.py joins A.e+B.e itself.
      local g parts
      for g in "$dir"/*_gold.e; do
        [ -f "$g" ] || continue
        name=$(basename "$g" _gold.e)
        [ -n "$(find "$wd/out" -name "$name.e" 2>/dev/null | head -n 1)" ] && continue
        parts=$(find "$wd/out" -name "${name}_*.e" 2>/dev/null | sort | paste -sd+)
        [[ $parts == *+* ]] || continue
        comp="$dir/${name}.comp"; [ -f "$comp" ] || comp=$(ls "$dir"/*.comp 2>/dev/null | head -n 1)
        [ -n "$comp" ] || continue
        out=$("$python" "$compare" "$parts" "$g" "$comp" 2>&1 | tail -n 1)
        case "$out" in
          match) [ "$result" = runs ] && { result=match; detail="$name (joined)"; } || { [ "$result" = match ] && detail="$detail, $name (joined)"; } ;;
          *) result=differs; worst="$name (joined): $out" ;;
        esac
      done
      [ -n "$worst" ] && detail=$(echo "$worst" | one_line)
    fi
  fi
  local wall; wall=$(echo "$(date +%s.%N) - $start" | bc)
  local shown=$deck
  if [[ $dir =~ /np[0-9]+$ ]]; then shown="$deck (copy in ${dir##*/}/)"; [ "$ranks" = 1 ] && n_copies=$((n_copies + 1)); fi
  printf '| %s | %s | %s | %s | %.1f |\n' "$shown" "$ranks" "$result" "$detail" "$wall"
  n_total=$((n_total + 1))
  case $result in
    match) n_match=$((n_match + 1)); n_runs=$((n_runs + 1)) ;;
    differs) n_differs=$((n_differs + 1)); n_runs=$((n_runs + 1)) ;;
    runs) n_runs=$((n_runs + 1)) ;;
    refused) n_refused=$((n_refused + 1)) ;;
    missing) n_missing=$((n_missing + 1)) ;;
    fails) n_fails=$((n_fails + 1)) ;;
    timeout) n_timeout=$((n_timeout + 1)) ;;
  esac
  last_result=$result
}

echo "| deck | ranks | result | detail | wall s |"
echo "|---|---|---|---|---|"
for deck in "${decks[@]}"; do
  [ -n "$only" ] && ! [[ $deck =~ $only ]] && continue
  run "$deck" 1
  folder=$(dirname "$checkout/$deck")
  if [ "$np4" = 1 ] && [ -x "$horizon_mpi" ] && { [ -d "$folder/np4" ] || [[ $folder == */np4 ]]; } &&
     { [ "$last_result" = match ] || [ "$last_result" = differs ] || [ "$last_result" = runs ]; }; then
    run "$deck" 4
  fi
done
echo
echo "runs (rank counts x decks): $n_total; run to the end: $n_runs (match $n_match, differ $n_differs," \
     "no gold $((n_runs - n_match - n_differs))); refused $n_refused; missing input $n_missing; failed $n_fails;" \
     "timed out $n_timeout; deck files that are copies in npN/ folders: $n_copies"
echo "work directory: $work"
