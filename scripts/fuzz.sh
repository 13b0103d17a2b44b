#!/usr/bin/env bash
# Long libFuzzer runs of every reader (docs/reliability.md): builds the fuzz targets
# in build/test, runs each on a copy of its seed corpus (out/fuzz/<target>/corpus; the
# committed corpus stays untouched) until it has executed ANNEX_FUZZ_RUNS inputs
# (default 10 million) or ANNEX_FUZZ_SECONDS have passed (default: no limit), and
# prints one line per target: executions, coverage (edges, features), crashes.
# Crash inputs are kept as out/fuzz/<target>/crash-*; the exit status is 1 if any.
#
#   bash scripts/fuzz.sh                    # every target, 10 million executions each
#   ANNEX_FUZZ_SECONDS=600 bash scripts/fuzz.sh fuzz_pcd fuzz_tum_list
set -euo pipefail
cd "$(dirname "$0")/.."
build=build/test
runs=${ANNEX_FUZZ_RUNS:-10000000}
seconds=${ANNEX_FUZZ_SECONDS:-0}
all=(fuzz_haptic fuzz_scene fuzz_pcd fuzz_scan_conf fuzz_hmd_conf fuzz_depth_png
     fuzz_tum_list fuzz_script)
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=("${all[@]}")

if [ ! -f "$build/build.ninja" ]; then
  bash scripts/deps.sh
  CC=clang CXX=clang++ cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$build" -j"$(nproc)" --target "${targets[@]}"

status=0
for target in "${targets[@]}"; do
  name=${target#fuzz_}
  out=out/fuzz/$target
  mkdir -p "$out/corpus"
  cp -n fuzz/corpus/"$name"/* "$out/corpus/" 2>/dev/null || true
  # The dictionaries and input limits the CTest short runs use (fuzz/CMakeLists.txt).
  max_len=4096
  [ "$name" = depth_png ] && max_len=8192
  log=$out/run.log
  "$build/fuzz/$target" -runs="$runs" -max_total_time="$seconds" -seed=1 -rss_limit_mb=2048 \
    -max_len="$max_len" -dict=fuzz/"$name".dict -print_final_stats=1 \
    -artifact_prefix="$out/" "$out/corpus" >"$log" 2>&1 || true
  execs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | tail -1 | grep -o '[0-9]*$' || echo 0)
  cov=$(grep -Eo 'cov: [0-9]+ ft: [0-9]+' "$log" | tail -1 || echo "cov: ? ft: ?")
  crashes=$(find "$out" -maxdepth 1 \( -name 'crash-*' -o -name 'leak-*' -o -name 'timeout-*' \
            -o -name 'oom-*' \) | wc -l)
  echo "$target executions=$execs ${cov/: /=} crashes=$crashes log=$log" | sed 's/ ft: /ft=/; s/ft=/ ft=/'
  [ "$crashes" -eq 0 ] || status=1
done
exit $status
