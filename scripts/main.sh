#!/usr/bin/env bash
# The main job: install missing Debian packages, build Release, run the default verification
# suite and leave its report in runs/default/ (runs/default-full/ with --full).
# Exit status: 0 all cases inside their bands and the baseline, 1 a regression, 2 bad input.
set -euo pipefail
cd "$(dirname "$0")/.."

full=()
run=default
for arg in "$@"; do
  case "$arg" in
    --full) full=(--full); run=default-full ;;
    *) echo "usage: scripts/main.sh [--full]" >&2; exit 2 ;;
  esac
done

scripts/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release
# Idle OpenMP threads sleep instead of spinning: on a loaded machine spinning threads burn
# the CPU seconds the report records (issue 28 measured the spread; docs/benchmarks.md). A caller's own
# setting wins.
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}"
build/release/apps/mfv verify suites/default.toml "${full[@]}" --report "runs/$run"
