#!/usr/bin/env bash
# plugin/installed (tests/CMakeLists.txt): mfv as a library for code outside its tree.
#  1. install the build into a fresh prefix;
#  2. configure and build examples/plugin/ as its own project against it (find_package);
#  3. the installed mfv lists the plugin's kernel and problem;
#  4. the plugin's kernel passes every kernel, approximation and patch conformance test
#     (test_core with MFV_PLUGINS);
#  5. its problem runs on its kernel into a report.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR WORK_DIR TEST_CORE
set -euo pipefail
build=$1 src=$2 work=$3 test_core=$4
rm -rf "$work"
mkdir -p "$work"
prefix=$work/prefix
echo "1. cmake --install $build --prefix $prefix"
cmake --install "$build" --prefix "$prefix" > "$work/install.log"
echo "   $(find "$prefix" -type f | wc -l) files, $(du -sh "$prefix" | cut -f1)"

echo "2. examples/plugin/ against the installation"
generator=()
command -v ninja > /dev/null && generator=(-G Ninja)
cmake -S "$src/examples/plugin" -B "$work/plugin" "${generator[@]}" \
      -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release > "$work/configure.log"
cmake --build "$work/plugin" > "$work/build.log"
lib=$work/plugin/libmfv_example_plugin.so
test -f "$lib"

echo "3. the installed mfv lists what the plugin adds"
# (to a file, not a pipe into grep -q: grep would close the pipe at its match and mfv's
# next write fail, a failure under pipefail)
"$prefix/bin/mfv" --plugin "$lib" list kernels > "$work/kernels.txt"
grep -q johnson-quadratic "$work/kernels.txt"
"$prefix/bin/mfv" --plugin "$lib" list problems > "$work/problems.txt"
grep -q sine-bar "$work/problems.txt"

echo "4. conformance of the plugin's kernel"
MFV_PLUGINS=$lib "$test_core" --gtest_brief=1 \
    --gtest_filter='*Conformance*:*PatchTest*:*KernelApproximation*:*KernelPatch*' \
    > "$work/conformance.log" 2>&1 || { tail -40 "$work/conformance.log"; exit 1; }
MFV_PLUGINS=$lib "$test_core" --gtest_list_tests \
    --gtest_filter='*Conformance*:*PatchTest*:*KernelApproximation*:*KernelPatch*' > "$work/tests.txt"
n=$(grep -c 'johnson' "$work/tests.txt" || true)
echo "   $n conformance tests on johnson-quadratic, all passed"
test "$n" -ge 4

echo "5. a report"
"$prefix/bin/mfv" --plugin "$lib" study sine-bar -m efg -p kernel=johnson-quadratic \
    -n 11 -n 21 -n 41 -r "$work/report" > "$work/study.log"
grep -q sine-bar "$work/report/index.md"
grep -i "rate" "$work/study.log" | head -3
echo "passed"
