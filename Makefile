# Bouguer's front door. Every target installs missing Debian packages first (idempotent).
BUILD ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)

.PHONY: all deps configure build demo test bench convergence clean

all: build

deps:
	@bash scripts/install-deps.sh

configure: deps
	@cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null

build: configure
	@cmake --build $(BUILD) -j $(JOBS)

# Until the renderer lands (#3): the colours of the standard illuminants.
demo: build
	@bash scripts/demo.sh $(BUILD)

test: build
	@ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)

bench: build
	@bash scripts/bench.sh $(BUILD)

# Samples and seconds each spectral mode needs to reach mean ΔE00 < 1 (several minutes).
convergence: build
	@bash scripts/convergence.sh $(BUILD)

clean:
	rm -rf $(BUILD) out
