#!/usr/bin/env bash
# Issue 30's device check, in one call of the device machine (H200, nvcc, CMake, ninja,
# 16 cores; none of the Debian libraries the rest of Horizon needs):
#   1. configures with -DHORIZON_CUDA=ON -DHORIZON_GPU_ONLY=ON (the CUDA backend, its test
#      and benchmark from the portable kernel headers alone; cmake/cuda.cmake),
#   2. builds them, 3. runs `ctest -L gpu` (the CUDA backend against the host's portable
#   rows: PMB, LPS and Tupek's nonlinear solid (log strain and m = 1/2), without and with
#   loads (a clamped end, a held velocity, a body force and their work), mean damage,
#   kinetic energy and the loads' work within 1e-9, the nonlinear solid's dissipation too
#   and its stable step (the adaptive step's, a device minimum) within 1e-12; it prints
#   whether the bits agree, which they should for PMB, LPS and m = 1/2: the same rows,
#   lanes and order, -fmad=false; the log strain's log and the stable step's exp may round
#   differently in the device's library),
#   4. runs the GPU benchmark (bench/gpu/bench_cuda.cpp): PMB, LPS and the nonlinear solid
#      at 1e6 particles, PMB at 1e7, with the card's copy bandwidth measured in the same run.
# Every stage has its own time limit (460 s in all); the whole finishes within 8 minutes. Eight logs go to
# $OUT (the device tool's folder that comes back) when it is set, else to the build folder.
#
#   bench/gpu/device_check.sh            (from the repository root, on the device machine)
#   SIZES_LARGE=0 bench/gpu/device_check.sh    (skips the 1e7-particle run)
#
# The driver's `solver.backend: cuda` (driver/backends.cpp) is the flat backend with its
# arrays on the device (cuda::FlatRun); it needs the whole build, which needs the Debian
# libraries the device machine lacks, so the check goes through FlatRun directly: the flat
# backend gives the CPU backend's bits (tests/regression/test_backend.cpp, on any
# machine), and gpu_cuda_flat asks the device for the flat rows' answer.
# Built here with nvcc 13.0 on a machine without a GPU (the tests and benchmarks skip,
# exit 77); it has never run on a device.
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD:-/tmp/horizon-gpu}
logs=${OUT:-$build}
mkdir -p "$build" "$logs"
start=$(date +%s)
status=0
stage() {  # stage NAME SECONDS COMMAND...: runs it with a limit, logs it, remembers a failure
  local name=$1 limit=$2
  shift 2
  echo "== $name ($(($(date +%s) - start)) s in)"
  timeout "$limit" "$@" 2>&1 | tee "$logs/$name.log"
  local rc=${PIPESTATUS[0]}
  [ "$rc" -eq 0 ] || { echo "== $name: exit status $rc"; status=1; }
  return "$rc"
}

echo "== device"
nvidia-smi --query-gpu=name,memory.total,driver_version,clocks.max.sm --format=csv 2>&1 | tee "$logs/device.log"
nvcc --version 2>&1 | tail -2 | tee -a "$logs/device.log"
nproc | tee -a "$logs/device.log"
generator=
command -v ninja >/dev/null && generator="-G Ninja"

stage configure 45 cmake -S "$root" -B "$build" $generator -DCMAKE_BUILD_TYPE=Release -DHORIZON_CUDA=ON \
  -DHORIZON_GPU_ONLY=ON -DCMAKE_CUDA_ARCHITECTURES=90 || exit 1
stage build 120 cmake --build "$build" -j "$(nproc)" || exit 1
stage test 75 ctest --test-dir "$build" -L gpu --output-on-failure -V
stage bench_pmb_1e6 40 "$build/bench_cuda" pmb 100 100 100 100
stage bench_lps_1e6 40 "$build/bench_cuda" lps 100 100 100 100
stage bench_tupek_1e6 40 "$build/bench_cuda" tupek 100 100 100 100
if [ "${SIZES_LARGE:-1}" != 0 ]; then
  stage bench_pmb_1e7 100 "$build/bench_cuda" pmb 216 216 216 20
fi
echo "== done in $(($(date +%s) - start)) s, status $status"
grep -h "bench_cuda\|PASSED\|FAILED\|SKIPPED" "$logs"/*.log
exit $status
