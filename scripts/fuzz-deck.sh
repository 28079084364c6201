#!/usr/bin/env bash
# Fuzzes the deck reader and set-up (fuzz/fuzz_deck.cpp) with libFuzzer.
#   scripts/fuzz-deck.sh [SECONDS] [extra libFuzzer flags]
# Builds build-fuzz with clang (needs clang-14 and libfuzzer-14-dev), seeds a corpus in
# build-fuzz/corpus from every examples/*.yaml, the decks embedded in tests/ and
# tests/data/fuzz_regressions/, and runs at low priority. Crashes, hangs (-timeout) and
# out-of-memory inputs (-rss_limit_mb) land in build-fuzz/findings/; each one fixed is
# kept in tests/data/fuzz_regressions/ (docs/reliability.md).
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_TO_RUN=${1:-600}
shift || true
BUILD=build-fuzz
if [ ! -f $BUILD/build.ninja ]; then
  CXX=clang++-14 cmake -S . -B $BUILD -G Ninja -DCMAKE_BUILD_TYPE=Release -DHORIZON_FUZZ=ON
fi
nice -n 19 cmake --build $BUILD -j 2 --target fuzz_deck
mkdir -p $BUILD/corpus $BUILD/findings $BUILD/seeds
cp examples/*.yaml tests/data/fuzz_regressions/* $BUILD/seeds/ 2>/dev/null || true
# Decks embedded in the tests as raw strings: R"(...)" and R"deck(...)deck".
python3 - "$BUILD/seeds" <<'PY'
import glob, re, sys
n = 0
for f in glob.glob("tests/**/*.cpp", recursive=True):
    text = open(f, encoding="utf-8").read()
    for m in re.finditer(r'R"(\w*)\((.*?)\)\1"', text, re.S):
        if "dimension" in m.group(2):
            n += 1
            open(f"{sys.argv[1]}/test_deck_{n}.yaml", "w").write(m.group(2))
print(f"{n} decks from tests/")
PY
exec nice -n 19 $BUILD/fuzz_deck $BUILD/corpus $BUILD/seeds -dict=fuzz/deck.dict -max_len=8192 \
  -timeout=10 -rss_limit_mb=2048 -max_total_time="$SECONDS_TO_RUN" -print_final_stats=1 \
  -artifact_prefix=$BUILD/findings/ "$@"
