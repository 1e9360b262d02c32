#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer
# (gcc; any UB aborts the test that hits it). Configures build-asan/ with
# -DLDAEC_SANITIZE=ON, builds everything, runs ctest.
#   scripts/sanitize.sh [ctest arguments, e.g. -R lang]
# Leak detection is on (the language suite, JIT runs included, reports no
# leak); docs/hardening.md has the last results.
set -euo pipefail
cd "$(dirname "$0")/.."
build=build-asan
cmake -S . -B $build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DLDAEC_SANITIZE=ON -DLDAEC_FUZZ_COUNT=500
cmake --build $build -j2
# ASan frames are several times larger than plain ones: the recursion
# limits (docs/frontend.md, Limits) are set for an 8 MiB stack of the plain
# build, so the sanitized one gets a larger stack rather than other limits.
ulimit -s 65536
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:detect_stack_use_after_return=0
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir $build --output-on-failure -j2 "$@"
