# Horizon: the two commands of the quick start, and a few for developers.
BUILD ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?=

.PHONY: all deps build demo test test-mpi test-sanitize fuzz bench clean format

all: build

deps:
	@bash scripts/install-deps.sh

$(BUILD)/build.ninja:
	cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS)

build: deps $(BUILD)/build.ninja
	cmake --build $(BUILD) -j $(JOBS)

# The demo needs only the program: the tests and benchmarks are built by `make test`.
demo: deps $(BUILD)/build.ninja
	cmake --build $(BUILD) -j $(JOBS) --target horizon
	$(BUILD)/horizon run examples/glass_branching.yaml
	$(BUILD)/horizon render out/glass_branching --field damage -o out/glass_branching/damage.png

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# The MPI program's tests alone (horizon-mpi, built by `make build` beside horizon; also
# part of `make test`): mpirun --oversubscribe on 1 to 4 ranks (docs/design.md, "Running
# on several ranks").
test-mpi: build
	cd $(BUILD) && ctest -L mpi --output-on-failure

# AddressSanitizer + UndefinedBehaviorSanitizer build in build-asan, then the tests
# labelled unit and regression (every unit test, the command-line, output-fault and
# example smoke tests) under it; any report fails the test (docs/reliability.md).
ASAN_BUILD ?= build-asan
test-sanitize: deps
	cmake -S . -B $(ASAN_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release -DHORIZON_SANITIZE=ON -DHORIZON_MPI=OFF $(CMAKE_FLAGS)
	cmake --build $(ASAN_BUILD) -j $(JOBS) --target horizon test_unit test_regression
	cd $(ASAN_BUILD) && ASAN_OPTIONS=detect_leaks=1:abort_on_error=0 LSAN_OPTIONS=suppressions=$(CURDIR)/scripts/lsan.supp \
	  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 ctest -L '^(unit|regression)$$' --output-on-failure -j $(JOBS)

# The deck fuzzer (clang, libFuzzer): FUZZ_SECONDS of fuzzing from the seed corpus.
FUZZ_SECONDS ?= 600
fuzz:
	bash scripts/fuzz-deck.sh $(FUZZ_SECONDS)

bench: build
	$(BUILD)/bench/bench_kernels --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

clean:
	rm -rf $(BUILD) $(ASAN_BUILD) build-fuzz out
