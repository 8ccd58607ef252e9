# rattle: the two commands a person needs are `make demo` and `make test`.
# Each installs the Debian packages listed in scripts/packages.txt when missing, configures and builds
# into build/ (Release, -O2, -ffp-contract=off; executables in build/bin/), then runs. `make demo`
# builds only rattle-demo (and the libraries it links); `make test` builds everything the tests need.
# `make bench` also installs scripts/packages-bench.txt (Box2D, Chipmunk, gnuplot), builds
# build/bin/rattle-bench and runs the benchmark's standard matrix (bench/README.md).

JOBS ?= $(shell nproc 2>/dev/null || echo 2)
BUILD_DIR ?= build
SANITIZE_DIR ?= build-sanitize
CMAKE_FLAGS ?=
DETERMINISM_DIR ?= build-determinism
FUZZ_DIR ?= build-fuzz
# Seconds each fuzz target runs in `make fuzz`.
FUZZ_SECONDS ?= 60
# Extra arguments for bench/run_matrix.py, e.g. BENCH_FLAGS=--quick for a small matrix.
BENCH_FLAGS ?=

.PHONY: all deps configure build demo test test-sanitize test-determinism fuzz bench bench-build replays update-goldens clean help
.PHONY: soak soak-short

all: build

help:
	@echo "make demo           build rattle-demo only and run the RTS demo for 600 ticks (frames in out/demo/,"
	@echo "                    replacing the frame_NNNNNN.png files of an earlier run there)"
	@echo "make test           build and run every test"
	@echo "make test-sanitize  the same tests built with ASan+UBSan in $(SANITIZE_DIR)/"
	@echo "make test-determinism  build rattle-trace, rattle-replay and rattle-demo with g++ -O0/-O2/-O3,"
	@echo "                    ASan+UBSan, clang++ -O2 and for aarch64 (run under qemu-user); check that every"
	@echo "                    build prints the same per-tick state hashes, verifies the replays and plays a"
	@echo "                    networked game against the g++ -O2 build without a desync"
	@echo "make fuzz           build the libFuzzer targets with clang++ in $(FUZZ_DIR)/ and run each for"
	@echo "                    FUZZ_SECONDS (default 60) seconds; fails on any finding (fuzz/README.md)"
	@echo "make soak           rattle-soak: every mode on the pile, crowd, piston and gas scenes for 3 simulated"
	@echo "                    minutes each, judged against issue 27's targets (about 30-40 min; tools/soak/)"
	@echo "make soak-short     the same for 20 simulated seconds, N = 300 (under 3 min)"
	@echo "make bench          build rattle-bench, run the standard matrix against Box2D and Chipmunk,"
	@echo "                    write bench/RESULTS.md, bench/results.csv, bench/scaling.csv, bench/figures/"
	@echo "make bench-build    build $(BUILD_DIR)/bin/rattle-bench only (installs Box2D and Chipmunk when missing);"
	@echo "                    runs nothing"
	@echo "make replays        record assets/replays/*.replay again (scripts/record-replays.sh)"
	@echo "make update-goldens render the golden frames of assets/golden/frames.txt again (on purpose only)"
	@echo "make clean          remove build trees and out/"

deps:
	@bash scripts/install-deps.sh

configure: deps
	@echo "configuring $(BUILD_DIR)/ (CMake, Release)"
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) > /dev/null

build: configure
	@echo "building everything in $(BUILD_DIR)/ (the libraries, the programs and the tests)"
	@cmake --build $(BUILD_DIR) -j $(JOBS)

# The RTS arena for 600 ticks (20 s of game time), a PNG frame every 10 ticks in out/demo/. Only the
# rattle-demo target: the test suite takes most of a full build, and `make test` builds it.
# rattle-demo itself removes the frame_NNNNNN.png files an earlier run left in out/demo/.
demo: configure
	@echo "building rattle-demo in $(BUILD_DIR)/ (the tests are built by make test)"
	@cmake --build $(BUILD_DIR) --target rattle-demo -j $(JOBS)
	@mkdir -p out/demo
	@echo "running the demo: 600 ticks, a frame every 10 into out/demo/ (earlier frame_NNNNNN.png files there are removed)"
	$(BUILD_DIR)/bin/rattle-demo --ticks 600 --every 10 --frames out/demo

# The tests write scratch files under GoogleTest's TempDir(): one folder per build (TEST_TMPDIR), so that
# make test and make test-sanitize run at once do not write over each other's files.
test: build
	@mkdir -p $(BUILD_DIR)/test-tmp
	@cd $(BUILD_DIR) && TEST_TMPDIR=$(abspath $(BUILD_DIR))/test-tmp ctest --output-on-failure -j $(JOBS)

test-sanitize: deps
	@cmake -S . -B $(SANITIZE_DIR) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRATTLE_SANITIZE=ON $(CMAKE_FLAGS) > /dev/null
	@cmake --build $(SANITIZE_DIR) -j $(JOBS)
	@mkdir -p $(SANITIZE_DIR)/test-tmp
	@cd $(SANITIZE_DIR) && ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  TEST_TMPDIR=$(abspath $(SANITIZE_DIR))/test-tmp ctest --output-on-failure -j $(JOBS)

# rattle-trace, rattle-replay and rattle-demo built with g++ -O0/-O2/-O3, g++ ASan+UBSan (in
# $(SANITIZE_DIR)), clang++ -O2 and aarch64-linux-gnu-g++ (run under qemu-user), one build directory each
# under $(DETERMINISM_DIR)/; fails unless every build prints the same trace, verifies every replay and
# plays a networked game against the g++ -O2 build to the same final hash (tools/determinism/README.md).
test-determinism: deps
	@bash scripts/install-deps.sh scripts/packages-clang.txt
	@bash scripts/install-deps.sh scripts/packages-aarch64.txt
	@CMAKE_FLAGS="$(CMAKE_FLAGS)" bash tools/determinism/run_builds.sh --out $(DETERMINISM_DIR) \
	  --sanitize-dir $(SANITIZE_DIR) --jobs $(JOBS)

# The libFuzzer targets of fuzz/ (clang++, ASan+UBSan), each run for FUZZ_SECONDS from the seeds in
# fuzz/corpus/; findings go to $(FUZZ_DIR)/findings/ and make this fail.
fuzz: deps
	@bash scripts/install-deps.sh scripts/packages-clang.txt
	@cmake -S . -B $(FUZZ_DIR) -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DRATTLE_BUILD_FUZZ=ON \
	  -DRATTLE_BUILD_TESTS=OFF -DRATTLE_BUILD_EXAMPLES=OFF $(CMAKE_FLAGS) > /dev/null
	@cmake --build $(FUZZ_DIR) --target rattle_fuzzers -j $(JOBS)
	@bash fuzz/run.sh --build $(FUZZ_DIR) --seconds $(FUZZ_SECONDS)

# rattle-soak (tools/soak/README.md): exits 1 while any of issue 27's targets is not met.
soak: configure
	@cmake --build $(BUILD_DIR) --target rattle-soak -j $(JOBS)
	$(BUILD_DIR)/bin/rattle-soak

soak-short: configure
	@cmake --build $(BUILD_DIR) --target rattle-soak -j $(JOBS)
	$(BUILD_DIR)/bin/rattle-soak --seconds 20 --n 300 --max-seconds 12

# rattle-bench alone (RATTLE_BUILD_BENCH is off in a plain configure), to run one scene by hand.
bench-build: deps
	@bash scripts/install-deps.sh scripts/packages-bench.txt
	@echo "configuring $(BUILD_DIR)/ with RATTLE_BUILD_BENCH=ON"
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release -DRATTLE_BUILD_BENCH=ON $(CMAKE_FLAGS) > /dev/null
	@echo "building rattle-bench in $(BUILD_DIR)/"
	@cmake --build $(BUILD_DIR) --target rattle-bench -j $(JOBS)

bench: bench-build
	python3 bench/run_matrix.py --bench $(BUILD_DIR)/bin/rattle-bench $(BENCH_FLAGS)

# The recorded replays the tests verify and render (replay/README.md). After `make replays`, run
# `make update-goldens` as well and look at the new frames before committing them.
replays: build
	@bash scripts/record-replays.sh

# Golden frames are written here and nowhere else: the tests only read them.
update-goldens: build
	@bash scripts/update-goldens.sh

clean:
	rm -rf $(BUILD_DIR) $(SANITIZE_DIR) $(FUZZ_DIR) $(DETERMINISM_DIR) out
