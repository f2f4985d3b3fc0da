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
#   mpi_case.sh MPIEXEC BIN mixed SCENE                ranks differing in each input that shapes
#                                                      an observation (scene, a mesh it includes,
#                                                      options, seed, build, command): each exit 2
#                                                      with one message naming the rank and what
#                                                      differs, never a hang, no output
#   mpi_case.sh MPIEXEC BIN killed SCENE               rank 1 killed mid-run: failure, no output
set -uo pipefail
MPIEXEC=$1 BIN=$2 CASE=$3
shift 3
# Open MPI in a container (root, more ranks than cores, no ptrace between processes, no binding),
# set here too so that the script runs outside CTest as it does inside.
export OMPI_ALLOW_RUN_AS_ROOT=${OMPI_ALLOW_RUN_AS_ROOT:-1}
export OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=${OMPI_ALLOW_RUN_AS_ROOT_CONFIRM:-1}
export OMPI_MCA_rmaps_base_oversubscribe=${OMPI_MCA_rmaps_base_oversubscribe:-1}
export OMPI_MCA_btl_vader_single_copy_mechanism=${OMPI_MCA_btl_vader_single_copy_mechanism:-none}
export OMPI_MCA_hwloc_base_binding_policy=${OMPI_MCA_hwloc_base_binding_policy:-none}
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
    grep -q "rank 1 of 2 was given other options than rank 0: rank 1 has '--seed 7', rank 0 has not" \
      "$WORK/err" || fail "no message"
    [ ! -e "$WORK/out" ] || fail "an output folder was left"
    ;;
  mixed)
    # Three copies of the scene's folder: a as given, b with the mesh it includes changed (the
    # scene's text the same), c with a bin wall moved 5 mm (the mesh the same).
    SCENE=$1
    MESH=$(sed -n 's/^ *mesh: {file: \([^,]*\),.*/\1/p' "$SCENE" | head -1)
    [ -n "$MESH" ] || fail "no mesh in $SCENE"
    for d in a b c; do
      mkdir -p "$WORK/$d"
      sed "s#file: $MESH#file: mesh.obj#" "$SCENE" >"$WORK/$d/scene.yaml"
      cp "$(dirname "$SCENE")/$MESH" "$WORK/$d/mesh.obj"
    done
    awk '/^v / && !done { $2 = $2 + 0.002; done = 1 } { print }' "$WORK/a/mesh.obj" >"$WORK/b/mesh.obj"
    sed -i 's/pose: {xyz: \[0, 0.145, 0.805\]}/pose: {xyz: [0, 0.15, 0.805]}/' "$WORK/c/scene.yaml"
    sed 's/^  seed: 1$/  seed: 2/' "$WORK/a/scene.yaml" >"$WORK/a/seed2.yaml"
    cmp -s "$WORK/a/mesh.obj" "$WORK/b/mesh.obj" && fail "the mesh was not changed"
    cmp -s "$WORK/a/scene.yaml" "$WORK/c/scene.yaml" && fail "the wall was not moved"
    cmp -s "$WORK/a/scene.yaml" "$WORK/a/seed2.yaml" && fail "the seed was not changed"
    A=$WORK/a/scene.yaml
    # mixed NAME EXPECTED RANK0_COMMAND... -- RANK1_COMMAND...: one job of two ranks.
    mixed() {
      local name=$1 expected=$2
      shift 2
      local first=() second=() seen=0
      for word in "$@"; do
        if [ "$word" = "--" ]; then seen=1; continue; fi
        if [ $seen -eq 0 ]; then first+=("$word"); else second+=("$word"); fi
      done
      rm -rf "$WORK/out" "$WORK/out.vis"
      timeout 300 "${MPI[@]}" -np 1 "${first[@]}" : -np 1 "${second[@]}" >/dev/null 2>"$WORK/err"
      local rc=$?
      [ "$rc" -ne 124 ] || fail "$name: the job hung"
      [ "$rc" -eq 2 ] || { cat "$WORK/err"; fail "$name: exit $rc, not 2"; }
      grep -qF "$expected" "$WORK/err" || { cat "$WORK/err"; fail "$name: no '$expected'"; }
      local lines
      lines=$(grep -c -e '\[error\]' -e '\[critical\]' "$WORK/err")  # mpirun adds its own words
      [ "$lines" -eq 1 ] || { cat "$WORK/err"; fail "$name: $lines messages, not one"; }
      [ ! -e "$WORK/out" ] && [ ! -e "$WORK/out.vis" ] || fail "$name: an output was left"
      echo "passed: $name: $(grep -e '\[error\]' "$WORK/err")"
    }
    OPT=("$BIN" -q optimize)
    OUT=(--out "$WORK/out")
    mixed scene_geometry "rank 1 of 2 traces another scene geometry than rank 0" \
      "${OPT[@]}" "$A" "${OUT[@]}" -- "${OPT[@]}" "$WORK/c/scene.yaml" "${OUT[@]}"
    mixed included_mesh "rank 1 of 2 traces another scene geometry than rank 0" \
      "${OPT[@]}" "$A" "${OUT[@]}" -- "${OPT[@]}" "$WORK/b/scene.yaml" "${OUT[@]}"
    mixed scene_seed "rank 1 of 2 has other candidates, R or observe options than rank 0" \
      "${OPT[@]}" "$A" "${OUT[@]}" -- "${OPT[@]}" "$WORK/a/seed2.yaml" "${OUT[@]}"
    mixed quality_filter "rank 1 has '--max-incidence 60', rank 0 has not" \
      "${OPT[@]}" "$A" "${OUT[@]}" -- "${OPT[@]}" "$A" --max-incidence 60 "${OUT[@]}"
    mixed quality_value "rank 1 has '--max-incidence 60', rank 0 has '--max-incidence 70'" \
      "${OPT[@]}" "$A" --max-incidence 70 "${OUT[@]}" -- "${OPT[@]}" "$A" --max-incidence 60 "${OUT[@]}"
    mixed refine_on_rank_0 "rank 0 has '--refine', rank 1 has not" \
      "${OPT[@]}" "$A" --refine "${OUT[@]}" -- "${OPT[@]}" "$A" "${OUT[@]}"
    mixed option_seed "rank 1 has '--seed 3', rank 0 has not" \
      "${OPT[@]}" "$A" "${OUT[@]}" -- "${OPT[@]}" "$A" --seed 3 "${OUT[@]}"
    mixed cell_size "rank 1 has '--cell-size 0.01', rank 0 has not" \
      "${OPT[@]}" "$A" "${OUT[@]}" -- "${OPT[@]}" "$A" --cell-size 0.01 "${OUT[@]}"
    mixed target "rank 1 has '--target table', rank 0 has not" \
      "${OPT[@]}" "$A" "${OUT[@]}" -- "${OPT[@]}" "$A" --target table "${OUT[@]}"
    mixed command "rank 1 has 'command observe', rank 0 has 'command optimize'" \
      "${OPT[@]}" "$A" "${OUT[@]}" -- "$BIN" -q observe "$A" --out "$WORK/out.vis"
    mixed observe_cull "rank 1 has '--no-cull', rank 0 has not" \
      "$BIN" -q observe "$A" --out "$WORK/out.vis" -- "$BIN" -q observe "$A" --no-cull --out "$WORK/out.vis"
    mixed build "rank 1 of 2 runs another vantage build than rank 0" \
      "${OPT[@]}" "$A" "${OUT[@]}" -- env VANTAGE_TEST_BUILD_ID=another "${OPT[@]}" "$A" "${OUT[@]}"
    # The same content at other paths, options in another order: one job, the one process's result.
    "$BIN" -q optimize "$A" --max-incidence 70 --seed 3 --threads 1 --out "$WORK/one" >/dev/null ||
      fail "one process: exit $?"
    timeout 300 "${MPI[@]}" -np 1 "${OPT[@]}" "$A" --seed 3 --max-incidence 70 --threads 1 \
      --out "$WORK/ranks" : -np 1 "${OPT[@]}" "$WORK/b/../a/scene.yaml" --max-incidence 70 \
      --seed 3 --threads 1 --out "$WORK/elsewhere" >/dev/null || fail "same content: exit $?"
    diff <(normalised "$WORK/one/report.json") <(normalised "$WORK/ranks/report.json") ||
      fail "report.json differs"
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
