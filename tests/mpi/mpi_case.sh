#!/usr/bin/env bash
# One MPI case of CTest (tests/CMakeLists.txt sets Open MPI's environment for containers):
#   mpi_case.sh MPIEXEC BIN report NP SCENE [ARGS...]  mpirun -np NP gives the single process's
#                                                      report.json (timings, seconds aside)
#   mpi_case.sh MPIEXEC BIN refine NP SCENE [ARGS...]  as report, with --refine: and every round's
#                                                      new poses were split over the ranks too
#   mpi_case.sh MPIEXEC BIN vis NP SCENE [ARGS...]     mpirun -np NP observe: the same .vis bytes
#   mpi_case.sh MPIEXEC BIN bad_rank SCENE             rank 1 has a missing scene: exit 2 naming
#                                                      rank 1, no output folder
#   mpi_case.sh MPIEXEC BIN disagree SCENE             rank 1 has another --seed: exit 2 naming it
#   mpi_case.sh MPIEXEC BIN killed SCENE               rank 1 killed mid-run: failure, no output
set -uo pipefail
MPIEXEC=$1 BIN=$2 CASE=$3
shift 3
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
MPI=("$MPIEXEC" --bind-to none)
fail() { echo "FAIL: $*"; exit 1; }
normalised() {
  jq -S 'del(.timings, .version) | walk(if type == "object" then del(.seconds) else . end)' "$1"
}
case "$CASE" in
  report)
    NP=$1; shift
    "$BIN" -q optimize "$@" --threads 1 --out "$WORK/one" >/dev/null ||
      fail "one process: exit $?"
    "${MPI[@]}" -np "$NP" "$BIN" -q optimize "$@" --threads 1 --out "$WORK/ranks" >/dev/null ||
      fail "mpirun -np $NP: exit $?"
    diff <(normalised "$WORK/one/report.json") <(normalised "$WORK/ranks/report.json") ||
      fail "report.json differs"
    cmp "$WORK/one/candidates.csv" "$WORK/ranks/candidates.csv" || fail "candidates.csv differs"
    ;;
  refine)
    NP=$1; shift
    "$BIN" -q optimize "$@" --refine --threads 1 --out "$WORK/one" >/dev/null ||
      fail "one process: exit $?"
    "${MPI[@]}" -np "$NP" "$BIN" optimize "$@" --refine --threads 1 --out "$WORK/ranks" \
      >/dev/null 2>"$WORK/log" || fail "mpirun -np $NP: exit $?"
    diff <(normalised "$WORK/one/report.json") <(normalised "$WORK/ranks/report.json") ||
      fail "report.json differs"
    cmp "$WORK/one/candidates.csv" "$WORK/ranks/candidates.csv" || fail "candidates.csv differs"
    # Rank 0 logs one split per traced batch: observe's, then each round that traced new poses.
    rounds=$(jq '.refinement.rounds' "$WORK/ranks/report.json")
    splits=$(grep -c "split: .* over $NP ranks" "$WORK/log")
    [ "$rounds" -ge 1 ] || fail "no refinement round"
    [ "$splits" -eq $((rounds + 1)) ] ||
      fail "$splits batches split over the ranks, not 1 + $rounds rounds"
    ;;
  vis)
    NP=$1; shift
    "$BIN" -q observe "$@" --out "$WORK/one.vis" >/dev/null || fail "one process: exit $?"
    "${MPI[@]}" -np "$NP" "$BIN" -q observe "$@" --out "$WORK/ranks.vis" >/dev/null ||
      fail "mpirun -np $NP: exit $?"
    cmp "$WORK/one.vis" "$WORK/ranks.vis" || fail ".vis differs"
    ;;
  bad_rank)
    # Rank 0 gets the scene, rank 1 a path that does not exist (MPMD: one job, two commands).
    "${MPI[@]}" -np 1 "$BIN" -q optimize "$1" --out "$WORK/out" : \
      -np 1 "$BIN" -q optimize "$WORK/missing.yaml" --out "$WORK/out" 2>"$WORK/err"
    rc=$?
    cat "$WORK/err"
    [ "$rc" -eq 2 ] || fail "exit $rc, not 2"
    grep -q "rank 1 of 2: .*missing.yaml" "$WORK/err" || fail "no message naming rank 1"
    [ ! -e "$WORK/out" ] || fail "an output folder was left"
    ;;
  disagree)
    # Rank 1 deploys other candidates (another seed): the job refuses to mix them.
    "${MPI[@]}" -np 1 "$BIN" -q optimize "$1" --out "$WORK/out" : \
      -np 1 "$BIN" -q optimize "$1" --seed 7 --out "$WORK/out" 2>"$WORK/err"
    rc=$?
    cat "$WORK/err"
    [ "$rc" -eq 2 ] || fail "exit $rc, not 2"
    grep -q "rank 1 of 2 has another scene, candidates or R" "$WORK/err" || fail "no message"
    [ ! -e "$WORK/out" ] || fail "an output folder was left"
    ;;
  killed)
    VANTAGE_TEST_KILL_RANK=1 "${MPI[@]}" -np 2 -x VANTAGE_TEST_KILL_RANK "$BIN" -q optimize "$1" \
      --out "$WORK/out" 2>"$WORK/err"
    rc=$?
    [ "$rc" -ne 0 ] || fail "exit 0 with a killed rank"
    [ ! -e "$WORK/out" ] || fail "an output folder was left"
    ls "$WORK" | grep -v '^err$' | grep -q . && fail "files left: $(ls "$WORK")"
    ;;
  *) fail "unknown case $CASE" ;;
esac
echo "ok: $CASE"
