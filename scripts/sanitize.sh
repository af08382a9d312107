#!/usr/bin/env bash
# Builds the unit and command tests with AddressSanitizer and UndefinedBehaviorSanitizer
# (plus float-cast-overflow, no recovery) in build/sanitize and runs `ctest -L unit` there.
# Any sanitizer report aborts the test that triggered it, so a clean run means no report.
# Usage: scripts/sanitize.sh [extra ctest arguments, e.g. -R Dispersion]
# Slow on two cores (every translation unit rebuilt at -O1 with instrumentation).
set -euo pipefail
cd "$(dirname "$0")/.."

# Every test executable of tests/CMakeLists.txt whose tests carry the unit label: a list typed
# by hand went stale (binaries left from an older build ran against new sources' suites), so
# it is read from the file; test_examples (the examples, excluded below) and test_convergence
# (label convergence) are left out.
mapfile -t targets < <(grep -oP 'add_executable\(\K(test_\w+)' tests/CMakeLists.txt |
                         grep -vx -e test_examples -e test_convergence)
targets+=(mfv)
cmake --preset sanitize >/dev/null
cmake --build build/sanitize --target "${targets[@]}"

# One OpenMP thread: the sanitizers' reports stay readable and the run stays deterministic.
export OMP_NUM_THREADS=1
export ASAN_OPTIONS="abort_on_error=1:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# PETSc/MPI tests initialize Open MPI, whose process-lifetime allocations are not mfv's.
export LSAN_OPTIONS="suppressions=$PWD/scripts/lsan.supp"
# The default-suite cases are regression tests; `-L unit` keeps to the unit and command tests.
# The examples (label unit;example) are not built here, so they are excluded by name.
ctest --test-dir build/sanitize -L unit -E '^example/' --output-on-failure -j 2 "$@"
