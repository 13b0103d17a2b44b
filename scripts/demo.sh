#!/usr/bin/env bash
# The main job on bundled samples: install, build Release, then annex the study's
# virtual objects onto the props of a recorded sequence. Output lands in out/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/deps.sh
cmake -S . -B build/release -G Ninja -DCMAKE_BUILD_TYPE=Release -DANNEX_BUILD_TESTS=OFF \
  -DANNEX_BUILD_BENCH=OFF >/dev/null
cmake --build build/release --target annex-runtime annex-author annex-make-models \
  annex-make-recording -j"$(nproc)"
rt=build/release/runtime/annex-runtime
out=out/demo
mkdir -p "$out"

echo "== check the study spec =="
"$rt" check samples/specs/study.haptic
echo
echo "== the paper's Figure 3: v1 gives up p1 so that v3 gets a prop =="
"$rt" match samples/figure3/figure3.haptic samples/figure3/figure3.scene
echo
echo "== the study objects against the household library =="
"$rt" match samples/specs/study.haptic samples/library/household.scene
echo
echo "== scan the first recorded frame =="
"$rt" scan samples/recordings/tabletop/frame_0000.pcd --png "$out/scan.png" --scene "$out/scan.scene"
echo
echo "== annex: scan, vote, match, track and overlay every frame of the recording =="
"$rt" run samples/specs/study.haptic --source samples/recordings/tabletop --out "$out"
echo
echo "Written: $out/scan.png, $out/poses.txt, $out/matches.txt, $out/overlay_*.png"
echo "Editor:  build/release/authoring/annex-author samples/specs/study.haptic"
