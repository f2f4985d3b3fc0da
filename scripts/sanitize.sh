#!/usr/bin/env bash
# Builds vantage and its tests with AddressSanitizer + UndefinedBehaviorSanitizer into build-asan/
# and runs them there (STYLE.md: "an ASan/UBSan preset"). Any sanitizer report fails the test that
# triggered it (halt_on_error; leaks are checked at exit).
#   scripts/sanitize.sh                 # the whole suite (`make sanitize`)
#   SCOPE=hostile scripts/sanitize.sh   # the suites labelled `hostile` (`make sanitize
#                                       # SCOPE=hostile`): those that feed the readers and the CLI
#                                       # broken and hostile input
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build-asan}
JOBS=${JOBS:-2}
SCOPE=${SCOPE:-all}

start=$(date +%s)
# -O1 -g1: what the sanitizers need for a readable stack (line tables), at a fraction of the
# compile time of -O2 -g on the two cores of CI.
# The configure log goes inside the build folder: beside it, it landed in the repository once.
mkdir -p "$BUILD"
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
      -DVANTAGE_SANITIZE=ON -DVANTAGE_BUILD_BENCH=OFF >"$BUILD/configure.log" 2>&1 ||
  { cat "$BUILD/configure.log"; exit 1; }
targets=()
labels=()
if [ "$SCOPE" = hostile ]; then
  targets=(--target hostile_tests)
  labels=(-L hostile)
fi
# The build runs sanitized tools too (tests/cad's STEP fixtures are written by OpenCASCADE), so the
# options hold from here on. The vantage binary run by the CLI tests inherits them.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export LSAN_OPTIONS=${LSAN_OPTIONS:-suppressions=$PWD/scripts/lsan.supp:print_suppressions=0}
echo "sanitize: building $SCOPE with ASan + UBSan into $BUILD/ (log: $BUILD/build.log) ..."
if ! cmake --build "$BUILD" -j"$JOBS" "${targets[@]}" -- --no-print-directory >"$BUILD/build.log" 2>&1; then
  grep -E "error|Error" "$BUILD/build.log" | head -40 || true
  echo "sanitize: build FAILED — $BUILD/build.log" >&2
  exit 1
fi
grep -E "warning:" "$BUILD/build.log" | sort -u | head -20 || true
built=$(date +%s)

status=0
(cd "$BUILD" && ctest --output-on-failure -j"$JOBS" "${labels[@]}" ${CTEST_ARGS:-}) || status=$?
done_at=$(date +%s)
echo "sanitize: build $((built - start)) s, tests $((done_at - built)) s, total $((done_at - start)) s"
exit "$status"
