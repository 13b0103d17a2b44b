#!/usr/bin/env bash
# Installs, builds and runs the whole test suite; exits non-zero on any failure.
# Set ANNEX_SANITIZE=1 for an AddressSanitizer + UndefinedBehaviorSanitizer build.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh
build=build/test
flags=()
if [ "${ANNEX_SANITIZE:-0}" = 1 ]; then
  build=build/asan
  flags+=(-DANNEX_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo)
else
  flags+=(-DCMAKE_BUILD_TYPE=Release)
fi
# clang builds the libFuzzer targets too, so the suite includes short fuzz runs.
CC=clang CXX=clang++ cmake -S . -B "$build" -G Ninja "${flags[@]}" >/dev/null
cmake --build "$build" -j"$(nproc)"
cd "$build"
ctest --output-on-failure -j"$(nproc)"
