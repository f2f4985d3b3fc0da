# The two commands of the README: `make run` and `make test`. Both install the Debian packages
# first (scripts/install-deps.sh, idempotent) and build into build/ with two jobs.
BUILD ?= build
JOBS ?= 2
EXAMPLE ?= examples/scenes/bin_picking_cell.yaml
OUT ?= out/example

PREFIX ?= /usr/local

.PHONY: deps build tool run test sanitize install bench paper clean

deps:
	bash scripts/install-deps.sh

# Everything: the library, the tool, the tests and the benchmarks (the compiler's output goes to
# $(BUILD)/build.log; warnings and the time taken are printed).
build: deps
	@BUILD=$(BUILD) JOBS=$(JOBS) bash scripts/build.sh

# Only the tool (and the Python module): the newcomer's first run does not wait for the tests.
tool: deps
	@BUILD=$(BUILD) JOBS=$(JOBS) bash scripts/build.sh tool

run: tool
	@BUILD=$(BUILD) EXAMPLE=$(EXAMPLE) OUT=$(OUT) bash scripts/run_example.sh

# The whole suite (what CI runs: .ci/run).
test: build
	@start=$$(date +%s); cd $(BUILD) && ctest --output-on-failure -j$(JOBS); status=$$?; \
	  echo "tests: done in $$(( $$(date +%s) - start )) s"; exit $$status

# The suites again under ASan + UBSan (scripts/sanitize.sh, build-asan/): every suite, or with
# SCOPE=hostile those labelled `hostile` (the readers' and the CLI's hostile input). Its build is
# twice the Release one, so it stays out of `make test` (CI's 30 minutes on 2 cores).
SCOPE ?= all
sanitize: deps
	@SCOPE=$(SCOPE) JOBS=$(JOBS) bash scripts/sanitize.sh

install: tool
	cmake --install $(BUILD) --prefix $(PREFIX)

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
