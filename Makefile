# Bouguer's front door. Every target installs missing Debian packages first (idempotent).
BUILD ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)

FUZZ_BUILD ?= build-fuzz
FUZZ_SECONDS ?= 180
FUZZ_TARGETS ?=
FUZZ_LONG_SECONDS ?= 3600
ASAN_BUILD ?= build-asan

.PHONY: all deps configure build demo test test-long bench convergence estimators hard-scenes denoised-milk choose fuzz fuzz-long test-asan clean blender-addon

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

# The paper's scenes in full spectrum and in its RGB approach, side by side with their CIEDE2000 map (out/).
demo: build
	@bash scripts/demo.sh $(BUILD)

# Every test but those labelled `long` (under 5 minutes on 2 loaded cores).
test: build
	@ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS) -LE long

# The tests labelled `long`: high sample counts that a small test cannot replace (minutes).
test-long: build
	@ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS) -L long

bench: build
	@bash scripts/bench.sh $(BUILD)

# Samples and seconds each spectral mode needs to reach mean ΔE00 < 1 (several minutes).
convergence: build
	@bash scripts/convergence.sh $(BUILD)

# Seconds path and bdpt need to reach mean ΔE00 < 2 and < 1 on the caustic scenes (tens of minutes).
estimators: build
	@bash bench/estimators.sh $(BUILD)

# #37's four hard scenes: time to mean ΔE00 < 1, this build against the one #37 was filed against
# (c4d0b2d, built once in build-base-c4d0b2d/; about 40 minutes on 2 cores).
hard-scenes: build
	@python3 bench/hard_scenes.py $(BUILD)/bouguer

# The glass of whole milk at 240x180 in 10 minutes on 2 cores, noisy and --denoise'd, against references
# of its centre and of its edge (about 90 minutes on 2 cores; Debian's python3, with numpy).
denoised-milk: build
	@/usr/bin/python3 bench/denoised_milk.py $(BUILD)/bouguer

# What --integrator auto rests on: each estimator's cost per ray, and auto's choice on four showcases.
choose: build
	@bash bench/choose.sh $(BUILD)

# The readers under libFuzzer, ASan and UBSan (clang; tests/fuzz): each harness for FUZZ_SECONDS on
# its corpus, one after another; FUZZ_TARGETS picks some (e.g. FUZZ_TARGETS="ply_ascii exr").
fuzz:
	@bash scripts/fuzz.sh $(FUZZ_BUILD) $(FUZZ_SECONDS) $(FUZZ_TARGETS)

# Every harness for FUZZ_LONG_SECONDS (an hour) each, as many at once as there are cores, then the
# summary table (target, seconds, executions, corpus, findings) for docs/limits.md.
fuzz-long:
	@bash scripts/fuzz-long.sh $(FUZZ_BUILD) $(FUZZ_LONG_SECONDS) $(FUZZ_TARGETS)

# The whole suite under ASan and UBSan (gcc, RelWithDebInfo -O1) in ASAN_BUILD, without `long` tests.
test-asan:
	@bash scripts/test-asan.sh $(ASAN_BUILD)

# The Blender add-on as a zip for Blender's Preferences > Add-ons > Install (docs/blender.md).
blender-addon:
	@mkdir -p $(BUILD)
	@/usr/bin/python3 scripts/make-blender-addon.py blender/bouguer_blender $(BUILD)/bouguer_blender.zip

clean:
	rm -rf $(BUILD) $(FUZZ_BUILD) $(ASAN_BUILD) out
