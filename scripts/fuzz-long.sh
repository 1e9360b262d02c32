#!/usr/bin/env bash
# The long mutation run: 10^5 stage runs (20000 mutants) of the mutation
# test (tests/fuzz/mutate.py) with a seed other than CI's, against the
# ldaec of build-fuzz/ (configured and built if needed).
#   scripts/fuzz-long.sh [COUNT] [SEED]     defaults: 100000 2
# Failing mutants are kept in build-fuzz/tests/fuzz/long-SEED/mutants/;
# about 80 minutes on two cores for 10^5 (10^4 took 475 s).
set -euo pipefail
cd "$(dirname "$0")/.."
count=${1:-100000}
seed=${2:-2}
build=build-fuzz
if [ ! -f $build/build.ninja ]; then
  cmake -S . -B $build -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo
fi
cmake --build $build --target ldaec ldae_jit
# A copy: a rebuild during the run must not replace the binary under it;
# the JIT module beside it, where ldaec looks first (docs/codegen.md).
work=$build/tests/fuzz/long-$seed
mkdir -p $work
cp $build/compiler/driver/ldaec $work/ldaec
# (The build's own: a find over the build dir picked an earlier run's copy,
# from another build, and every JIT stage failed on it.)
cp $build/compiler/driver/libldae_jit.so $work/
python3 tests/fuzz/mutate.py --ldaec $work/ldaec \
  --source-dir . --work-dir $work \
  --count "$count" --seed "$seed" --jobs "${JOBS:-2}"
