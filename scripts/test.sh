#!/usr/bin/env bash
# Every test: install missing Debian packages, build Release (tests, examples, benchmarks)
# and run ctest: unit, convergence, example and the default suite's regression cases.
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/setup.sh
cmake --preset release >/dev/null
cmake --build --preset release
ctest --preset release "$@"
