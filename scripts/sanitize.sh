#!/usr/bin/env bash
# Builds vantage and its tests with AddressSanitizer + UndefinedBehaviorSanitizer into build-asan/
# and runs the whole test suite there (STYLE.md: "an ASan/UBSan preset"). Any sanitizer report
# fails the test that triggered it (halt_on_error; leaks are checked at exit).
#   scripts/sanitize.sh              # build + ctest, prints the time of each
#   BUILD=build-asan JOBS=2 CTEST_ARGS="-R cli" scripts/sanitize.sh
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD=${BUILD:-build-asan}
JOBS=${JOBS:-2}

start=$(date +%s)
cmake -S . -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DVANTAGE_SANITIZE=ON -DVANTAGE_BUILD_BENCH=OFF
cmake --build "$BUILD" -j"$JOBS"
built=$(date +%s)

# The vantage binary run by the CLI tests inherits these too.
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
status=0
(cd "$BUILD" && ctest --output-on-failure -j"$JOBS" ${CTEST_ARGS:-}) || status=$?
done_at=$(date +%s)
echo "sanitize: build $((built - start)) s, tests $((done_at - built)) s, total $((done_at - start)) s"
exit "$status"
