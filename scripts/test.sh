#!/usr/bin/env bash
# Installs, builds and runs the whole test suite; exits non-zero on any failure.
# Set ANNEX_SANITIZE=1 for an AddressSanitizer + UndefinedBehaviorSanitizer build, or
# ANNEX_SANITIZE=thread for ThreadSanitizer over the threaded code's tests (build/tsan).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh
build=build/test
flags=()
tests=()
case "${ANNEX_SANITIZE:-0}" in
  0) flags+=(-DCMAKE_BUILD_TYPE=Release) ;;
  thread)
    # ThreadSanitizer on the code that runs threads: the session (trackers on a pool,
    # background scans on its worker), run's PNG writer beside the next frame, the
    # renderer, the OSC stream, the scan's own worker threads (ScanThreads).
    build=build/tsan
    flags+=(-DANNEX_SANITIZE=thread -DCMAKE_BUILD_TYPE=RelWithDebInfo -DANNEX_BUILD_EDITOR=OFF
            -DANNEX_BUILD_BENCH=OFF)
    tests=(-R "${ANNEX_TSAN_TESTS:-AnnexSession|SessionBackground|RunCommand|SessionExclude|RunStream|OscStream|OscListener|Renderer|Png|Fault|ScanThreads}")
    # For the test discovery at build time, the tests, and the annex-runtime they run.
    export TSAN_OPTIONS="${TSAN_OPTIONS:-halt_on_error=1 second_deadlock_stack=1 suppressions=$PWD/tests/tsan.supp}"
    ;;
  *)
    build=build/asan
    flags+=(-DANNEX_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo)
    ;;
esac
# clang builds the libFuzzer targets too, so the suite includes short fuzz runs.
CC=clang CXX=clang++ cmake -S . -B "$build" -G Ninja "${flags[@]}" >/dev/null
cmake --build "$build" -j"$(nproc)"
cd "$build"
ctest --output-on-failure -j"$(nproc)" "${tests[@]}"
