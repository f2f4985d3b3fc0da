#!/usr/bin/env bash
# Builds the libFuzzer targets into $FUZZ_BUILD (default fuzz/build) with clang and runs each for
# $FUZZ_SECONDS seconds (default 60), one after the other. `make fuzz` calls this.
#   FUZZ_TARGETS="yaml_scene constellation" FUZZ_SECONDS=300 bash fuzz/run.sh
# New inputs go to $FUZZ_BUILD/corpus/<target> (the seeds in fuzz/corpus/<target> are only read);
# a crash, leak, timeout or out-of-memory leaves its input in $FUZZ_BUILD/artifacts/<target>/ and
# makes the script exit 1 after all targets ran. Each campaign's log is kept as
# $FUZZ_BUILD/logs/<target>-<UTC time>.log (and copied to $FUZZ_BUILD/<target>.log), and
# fuzz/plateau.py says whether its coverage reached the plateau of fuzz/README.md.
#   FUZZ_MERGE=1       after each campaign, minimise seeds + grown corpus into a fresh
#                      $FUZZ_BUILD/merged/<target>/ (libFuzzer -merge=1): the seeds first, then
#                      only the grown inputs that add features; what to commit to fuzz/corpus/.
#   FUZZ_NO_BUILD=1    run the targets already built (e.g. while another target still builds).
#   FUZZ_TIMEOUT=60    libFuzzer's -timeout in seconds (default 10). It counts wall-clock time:
#                      under `nice -n 19` on a loaded machine a pipeline input of 0.7 s of CPU took
#                      8.7 s, so raise it there (a real hang still shows as a timeout).
# Run it as `nice -n 19 bash fuzz/run.sh` on a shared machine.
set -euo pipefail
cd "$(dirname "$0")/.."
FUZZ_BUILD=${FUZZ_BUILD:-fuzz/build}
FUZZ_SECONDS=${FUZZ_SECONDS:-60}
FUZZ_TARGETS=${FUZZ_TARGETS:-yaml_scene gazebo_world visibility_file constellation mesh_file urdf_robot pipeline exporter}
JOBS=${JOBS:-2}
FUZZ_TIMEOUT=${FUZZ_TIMEOUT:-10}

# ccache (when installed) makes a rebuild after a small change cheap: the targets compile the main
# build's library with the sanitizers. CMAKE_CXX_COMPILER_LAUNCHER= (empty) turns it off.
if [ -z "${CMAKE_CXX_COMPILER_LAUNCHER+set}" ] && command -v ccache >/dev/null; then
  CMAKE_CXX_COMPILER_LAUNCHER=ccache
fi
if [ -z "${FUZZ_NO_BUILD:-}" ]; then
  CXX=${FUZZ_CXX:-clang++} cmake -S fuzz -B "$FUZZ_BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DCMAKE_CXX_COMPILER_LAUNCHER="${CMAKE_CXX_COMPILER_LAUNCHER:-}" >/dev/null
  # FUZZ_TARGETS names the executables to build too: one target need not wait for the others.
  cmake --build "$FUZZ_BUILD" -j"$JOBS" --target $(printf '%s_fuzzer ' $FUZZ_TARGETS)
fi
if [ -n "${FUZZ_BUILD_ONLY:-}" ]; then exit 0; fi

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
failed=()
for target in $FUZZ_TARGETS; do
  corpus="$FUZZ_BUILD/corpus/$target"
  artifacts="$FUZZ_BUILD/artifacts/$target"
  mkdir -p "$corpus" "$artifacts"
  dict=()
  if [ -f "fuzz/$target.dict" ]; then dict=(-dict="fuzz/$target.dict"); fi
  mkdir -p "$FUZZ_BUILD/logs"
  log="$FUZZ_BUILD/logs/$target-$(date -u +%Y%m%dT%H%M%S).log"
  echo "== $target: ${FUZZ_SECONDS} s (log: $log)"
  if ! "$FUZZ_BUILD/${target}_fuzzer" "$corpus" "fuzz/corpus/$target" "${dict[@]}" \
      -max_total_time="$FUZZ_SECONDS" -timeout="$FUZZ_TIMEOUT" -rss_limit_mb=2048 -max_len=65536 \
      -print_final_stats=1 -artifact_prefix="$artifacts/" 2>"$log"; then
    failed+=("$target")
    tail -n 60 "$log"
  fi
  cp "$log" "$FUZZ_BUILD/$target.log"
  grep -E "^(#[0-9]+ +DONE|stat::number_of_executed_units|stat::peak_rss_mb)" "$log" || true
  python3 fuzz/plateau.py "$log" || true
  if [ -n "${FUZZ_MERGE:-}" ]; then
    merged="$FUZZ_BUILD/merged/$target"
    rm -rf "$merged" && mkdir -p "$merged"
    cp "fuzz/corpus/$target"/* "$merged/"
    "$FUZZ_BUILD/${target}_fuzzer" -merge=1 "$merged" "$corpus" -timeout="$FUZZ_TIMEOUT" -rss_limit_mb=2048 \
        -max_len=65536 2>"$FUZZ_BUILD/logs/$target-merge.log" ||
      { tail -n 20 "$FUZZ_BUILD/logs/$target-merge.log"; failed+=("$target (merge)"); }
    echo "merged: $(ls "$merged" | wc -l) files, $(du -sh "$merged" | cut -f1) in $merged"
  fi
done
if [ "${#failed[@]}" -gt 0 ]; then
  echo "fuzz: failures in ${failed[*]} (inputs in $FUZZ_BUILD/artifacts/)"
  exit 1
fi
echo "fuzz: no failure in $FUZZ_TARGETS"
