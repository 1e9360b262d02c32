#!/usr/bin/env bash
# libFuzzer over the frontend and the analysis (tests/fuzz/FuzzFrontend.cpp),
# with ASan + UBSan, built by clang-14 into build-libfuzzer/ (only the fuzz
# target and the libraries it links: no LLVM codegen, no runtime).
#   scripts/fuzz-libfuzzer.sh [SECONDS] [extra libFuzzer flags]   default 600
# Seed corpus: every .lsd of the repository, copied to
# build-libfuzzer/fuzz/seeds; new inputs go to build-libfuzzer/fuzz/corpus,
# crashes to build-libfuzzer/fuzz/artifacts.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-600}
shift || true
build=build-libfuzzer
# clang-14 rejects one line of Debian's ANTLR 4.9 runtime headers
# (misc/InterpreterDataReader.h:20, `InterpreterData() {};`: "call to
# implicitly-deleted default constructor of 'dfa::Vocabulary'", a const
# vector member; gcc accepts it). We compile against a copy with that
# constructor defaulted (same layout; only the prebuilt runtime uses it).
headers=$PWD/$build/antlr4-runtime-clang
if [ ! -f "$headers/antlr4-runtime.h" ]; then
  mkdir -p $build
  cp -r /usr/include/antlr4-runtime "$headers"
  sed -i 's/InterpreterData() {};/InterpreterData() = default;/' \
    "$headers/misc/InterpreterDataReader.h"
fi
CC=clang-14 CXX=clang++-14 cmake -S . -B $build -G Ninja \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DLDAEC_LIBFUZZER=ON \
  -DANTLR4_INCLUDE_DIR="$headers"
cmake --build $build -j2 --target ldaec_fuzz_frontend
work=$build/fuzz
mkdir -p $work/seeds $work/corpus $work/artifacts
# Models made to run out of memory (RUN lines with --limit-as) take longer
# than the timeout under ASan: not seeds.
find examples stdlib tests -name '*.lsd' | xargs grep -L -e --limit-as |
while read -r f; do
  cp "$f" "$work/seeds/$(echo "$f" | tr / _)"
done
export ASAN_OPTIONS=detect_leaks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
$build/tests/fuzz/ldaec_fuzz_frontend $work/corpus $work/seeds \
  -max_total_time="$seconds" -timeout=10 -rss_limit_mb=3072 -max_len=8192 \
  -artifact_prefix=$work/artifacts/ -print_final_stats=1 "$@"
