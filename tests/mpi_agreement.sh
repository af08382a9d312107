#!/usr/bin/env bash
# Issue 26: under mpiexec every rank agrees before anything collective and exits with the same
# code, within seconds, and one message is printed. Two reproducers:
#   1. a report target that rank 0 refuses (a directory of the user's): exit 2, the user's file
#      untouched (rank 1 used to wait in PETSc for ever);
#   2. a failure at commit, after the collective work: a file of the user's appears in the
#      target while the run computes; exit 2, the file untouched, no rank left behind;
#   3. SIGTERM to mpiexec while the ranks compute: no rank left behind, the previous report
#      whole; a staging directory is removed by the ranks' signal handler or, when mpiexec
#      follows its SIGTERM with a SIGKILL before they finish, by the next run (it stays marked
#      as mfv's to the end: StagedDirectory removes markers last).
# Usage: mpi_agreement.sh <mpiexec> <mfv>
set -u
mpiexec=$1
mfv=$2
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
# Hang limits, scaled for a sanitized build (tests/CMakeLists.txt sets MFV_MPI_TIME_SCALE).
scale=${MFV_MPI_TIME_SCALE:-1}
case "$scale" in '' | *[!0-9]*) fail "MFV_MPI_TIME_SCALE must be a whole number, got '$scale'" ;; esac
short=$((60 * scale)) long=$((120 * scale))

# 1. Refused target.
mkdir "$work/mine"
echo "my thesis" > "$work/mine/thesis.txt"
start=$(date +%s)
timeout "$short" "$mpiexec" -n 2 --oversubscribe "$mfv" study laplace-tanh -m fem -n 5,9 \
  -p solver=petsc -r "$work/mine" > "$work/out1" 2> "$work/err1"
rc=$?
[ $rc -eq 124 ] && fail "refused target: no exit within ${short} s (hung)"
[ $rc -eq 2 ] || { cat "$work/err1"; fail "refused target: exit $rc, expected 2"; }
[ "$(cat "$work/mine/thesis.txt")" = "my thesis" ] || fail "refused target: the user's file changed"
n=$(grep -c "input error" "$work/err1")
[ "$n" -eq 1 ] || { cat "$work/err1"; fail "refused target: $n error messages, expected one"; }
echo "refused target: exit 2 in $(( $(date +%s) - start )) s, one message"

# 2. Failure at commit: an earlier mfv report as the target; a file of the user's is put into
# it while the study runs.
"$mfv" study laplace-tanh -m fem -n 5,9 -r "$work/rep" > /dev/null 2>&1 || fail "setup report"
( timeout "$long" "$mpiexec" -n 2 --oversubscribe "$mfv" study cantilever -m fem -n 5,9,17,33,65 \
    -p solver=petsc -r "$work/rep" > "$work/out2" 2> "$work/err2"; echo $? > "$work/rc2" ) &
for _ in $(seq 1 $((600 * scale))); do
  ls -d "$work"/.rep.staging-* > /dev/null 2>&1 && break
  sleep 0.05
done
echo "added while mfv ran" > "$work/rep/notes.txt"
wait
rc=$(cat "$work/rc2")
[ "$rc" -eq 124 ] && fail "commit failure: no exit within ${long} s (hung)"
[ "$rc" -eq 2 ] || { cat "$work/err2"; fail "commit failure: exit $rc, expected 2"; }
[ "$(cat "$work/rep/notes.txt")" = "added while mfv ran" ] || fail "commit failure: the user's file changed"
ls -d "$work"/.rep.staging-* > /dev/null 2>&1 && fail "commit failure: a staging directory was left"
n=$(grep -c "input error" "$work/err2")
[ "$n" -eq 1 ] || { cat "$work/err2"; fail "commit failure: $n error messages, expected one"; }
echo "commit failure: exit 2, one message, the user's file kept"

# 3. SIGTERM to mpiexec, six times at different moments of the run.
rm -f "$work/rep/notes.txt"
"$mfv" study laplace-tanh -m fem -n 5,9 -r "$work/rep" > /dev/null 2>&1 || fail "setup report 2"
for delay in 0.05 0.1 0.2 0.4 0.6 0.8; do
  timeout "$long" "$mpiexec" -n 2 --oversubscribe "$mfv" study cantilever -m fem -n 5,9,17,33,65 \
    -p solver=petsc -r "$work/rep" > /dev/null 2>&1 &
  pid=$!
  for _ in $(seq 1 $((600 * scale))); do
    ls -d "$work"/.rep.staging-* > /dev/null 2>&1 && break
    sleep 0.05
  done
  sleep "$delay"
  # timeout's child is mpiexec; timeout passes the signal on.
  kill -TERM "$pid"
  wait "$pid"
  rc=$?
  # Whole means one report or the other: the previous one, or the new one when the run
  # committed before the signal came (it may then still exit non-zero, killed while ending).
  if grep -q cantilever "$work/rep/index.md" 2> /dev/null; then
    "$mfv" study laplace-tanh -m fem -n 5,9 -r "$work/rep" > /dev/null 2>&1 || fail "setup report again"
  elif ! grep -q laplace-tanh "$work/rep/index.md" 2> /dev/null; then
    fail "SIGTERM after ${delay} s (exit $rc): neither the previous report nor the new one is whole"
  fi
  for _ in $(seq 1 $((100 * scale))); do pgrep -f "$work/rep" > /dev/null || break; sleep 0.1; done
  pgrep -af "$work/rep" && fail "SIGTERM after ${delay} s: a rank still runs $((10 * scale)) s later"
done
left=$(ls -d "$work"/.rep.staging-* 2> /dev/null | wc -l)
"$mfv" study laplace-tanh -m fem -n 5,9 -r "$work/rep" > /dev/null 2>&1 || fail "run after SIGTERM"
if ls -d "$work"/.rep.staging-* > /dev/null 2>&1; then
  ls -laR "$work"/.rep.staging-*
  fail "SIGTERM: a staging directory outlived the next run"
fi
echo "SIGTERM to mpiexec: previous report whole, no rank left, $left staging dir(s) left for the next run, which removed them"
echo PASS
