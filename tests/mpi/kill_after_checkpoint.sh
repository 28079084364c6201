#!/bin/sh
# Starts `MPIEXEC -n RANKS HORIZON run DECK -q -o OUT`, waits for its first checkpoint
# (OUT/checkpoint.hzc), then kills every rank with SIGKILL, as a crashed node would, and
# waits for mpirun to notice. Used by tests/mpi/restart.cmake.
# kill_after_checkpoint.sh MPIEXEC RANKS HORIZON DECK OUT
set -u
mpiexec=$1 ranks=$2 horizon=$3 deck=$4 out=$5
"$mpiexec" --oversubscribe -n "$ranks" "$horizon" run "$deck" -q -o "$out" --threads 1 >"$out.log" 2>&1 &
launcher=$!
tries=0
while [ ! -f "$out/checkpoint.hzc" ]; do
  if ! kill -0 "$launcher" 2>/dev/null; then
    echo "the run ended before its first checkpoint" >&2
    cat "$out.log" >&2
    exit 1
  fi
  tries=$((tries + 1))
  if [ "$tries" -gt 6000 ]; then
    echo "no checkpoint after 300 s" >&2
    kill -9 "$launcher"
    exit 1
  fi
  sleep 0.05
done
# The ranks are mpirun's children (Open MPI starts local ranks itself).
ranks_pids=$(pgrep -P "$launcher")
if [ -z "$ranks_pids" ]; then
  echo "found no rank processes under mpirun $launcher" >&2
  exit 1
fi
kill -9 $ranks_pids
wait "$launcher"
rc=$?
if [ -f "$out/summary.json" ]; then
  echo "the run finished before it was killed (exit $rc): the test must kill it mid-run" >&2
  exit 1
fi
echo "killed ranks $ranks_pids; mpirun exit $rc"
exit 0
