#!/usr/bin/env bash
# The main job: install missing Debian packages, build Release, run the default verification
# suite and leave its report in reports/default/ (reports/default-full/ with --full).
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
build/release/apps/mfv verify suites/default.toml "${full[@]}" --report "reports/$run"
