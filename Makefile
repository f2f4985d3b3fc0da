# The two commands of the README: `make run` and `make test`. Both install the Debian packages
# first (scripts/install-deps.sh, idempotent) and build into build/ with two jobs.
BUILD ?= build
JOBS ?= 2
EXAMPLE ?= examples/scenes/bin_picking_cell.yaml
OUT ?= out/example

.PHONY: deps build run test bench paper clean

deps:
	bash scripts/install-deps.sh

build: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release
	cmake --build $(BUILD) -j$(JOBS)

run: build
	BUILD=$(BUILD) EXAMPLE=$(EXAMPLE) OUT=$(OUT) bash scripts/run_example.sh

# The whole suite, then the same suite built with ASan + UBSan (scripts/sanitize.sh, build-asan/).
test: build
	cd $(BUILD) && ctest --output-on-failure -j$(JOBS)
	JOBS=$(JOBS) bash scripts/sanitize.sh

bench: build
	bash scripts/bench_e2e.sh

paper: build
	bash bench/paper.sh

clean:
	rm -rf $(BUILD) out

# libFuzzer targets of the input readers (fuzz/), built with clang into fuzz/build; each runs for
# FUZZ_SECONDS seconds. Fails when one finds a crash (inputs in fuzz/build/artifacts/).
FUZZ_SECONDS ?= 60
FUZZ_BUILD ?= fuzz/build

.PHONY: fuzz
fuzz: deps
	FUZZ_SECONDS=$(FUZZ_SECONDS) FUZZ_BUILD=$(FUZZ_BUILD) JOBS=$(JOBS) bash fuzz/run.sh
