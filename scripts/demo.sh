#!/usr/bin/env bash
# The main job on bundled samples: install, build Release, then run Annex.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DANNEX_BUILD_TESTS=OFF >/dev/null
cmake --build build/release --target annex-runtime -j"$(nproc)"
rt=build/release/runtime/annex-runtime

echo "== check the study spec =="
"$rt" check samples/specs/study.haptic
echo
echo "== the paper's Figure 3 =="
"$rt" match samples/figure3/figure3.haptic samples/figure3/figure3.scene
echo
echo "== the study objects against the household library =="
"$rt" match samples/specs/study.haptic samples/library/household.scene
