#!/usr/bin/env bash
# The observed orders of accuracy of every method × kernel on a manufactured problem (issue 46):
# one Markdown table per problem, methods as rows, kernels as columns, each cell "L2 / gradient"
# of the finest pair with the verdict's first word against the method's declared order
# (at formal order "=", above "+", below "-", does not converge "x", none declared "?").
# A method that refuses a kernel or the problem leaves the cell "–".
# Usage: scripts/mms_order_table.sh [mfv] [problem nodes...]
set -euo pipefail
cd "$(dirname "$0")/.."
M=${1:-build/release/apps/mfv}
kernels=(cubic-spline quartic-spline quintic-spline wendland-c2 wendland-c4 wendland-c6 gaussian cubic-window)
methods=(fem efg efg-ci efg-ni kbm-ci kbm-ni kbm-si "kbm-si:vci=quadratic" rkpm wavelet sph rlm sph-galerkin xefg)
table() {
  local problem=$1; shift
  local nodes=("$@")
  local n=()
  for x in "${nodes[@]}"; do n+=(-n "$x"); done
  printf '\n### %s (%s)\n\n| method |' "$problem" "${nodes[*]}"
  for k in "${kernels[@]}"; do printf ' %s |' "$k"; done
  printf '\n|:--|'; for k in "${kernels[@]}"; do printf -- '--:|'; done; printf '\n'
  for m in "${methods[@]}"; do
    local name=${m%%:*} extra=""
    [[ $m == *:* ]] && extra=${m#*:}
    printf '| %s |' "$m"
    for k in "${kernels[@]}"; do
      local p="kernel=$k"; [[ -n $extra ]] && p="$p,$extra"
      [[ $name == fem ]] && p=""
      local line
      line=$(OMP_WAIT_POLICY=passive timeout 300 "$M" study "$problem" -m "$name" ${p:+-p "$p"} "${n[@]}" 2>/dev/null \
             | grep '^order of accuracy' || true)
      if [[ -z $line ]]; then printf ' – |'; continue; fi
      python3 - "$line" <<'PY'
import re, sys
s = sys.argv[1]
obs = re.findall(r'(?:L2|H1-semi|energy) (-?[0-9.]+|–)(?: against [0-9.]+)? \(least squares [^)]*\): ([a-z]+)', s)
mark = {'at': '=', 'above': '+', 'below': '-', 'does': 'x', 'no': '?'}
cells = [f"{v}{mark.get(w, '?')}" for v, w in obs]
print(' ' + ' / '.join(cells) + ' |', end='')
PY
      [[ $name == fem ]] && { for _ in "${kernels[@]:1}"; do printf ' (same) |'; done; break; }
    done
    printf '\n'
  done
}
if [[ $# -ge 3 ]]; then
  table "${@:2}"
else
  table mms-poisson-1d 11 21 41 81 161
  table mms-elasticity-2d 5 9 17 33
fi
