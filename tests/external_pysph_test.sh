#!/usr/bin/env bash
# PySPH through solvers/pysph (issue 30): a 25 × 3 rod pulse runs, every frame is read back and
# the velocity errors at L/c and 2L/c are finite numbers, the energy drift of the adapter's
# account is small; the solver line names PySPH's run.
# Usage: external_pysph_test.sh <mfv>
set -u
mfv=$1
fail() { echo "FAIL: $*"; exit 1; }
/usr/bin/python3 -c "import pysph.sph.solid_mech.basic" 2> /dev/null ||
  fail "PySPH is not installed (scripts/setup.sh installs python3-pysph)"
out=$("$mfv" run rod-pulse -m external:pysph -n 25 2>&1) || { echo "$out"; fail "exit $?"; }
echo "$out"
for k in "L/c" "2L/c"; do
  e=$(echo "$out" | awk -v key="velocity error at $k" 'index($0, key" ") == 1 && NF == 5 {print $NF}')
  python3 -c "import math, sys; sys.exit(0 if math.isfinite(float('$e')) and float('$e') > 0 else 1)" ||
    fail "velocity error at $k is '$e', not a positive number"
done
echo "$out" | grep -q "^solver    /usr/bin/python3 .*pysph_adapter.py <case directory>: .* 208 frames" ||
  fail "no solver line with 208 frames"
# The adapter's energy account (frames/energy.csv): PySPH's forces' work balances its kinetic
# energy to well under the drift bound (0.25 % measured at 61 × 6).
d=$(echo "$out" | awk '/^energy drift / {print $NF}')
python3 -c "import sys; sys.exit(0 if 0 <= float('$d') < 0.05 else 1)" ||
  fail "energy drift is '$d', not a number below 0.05"
echo PASS
