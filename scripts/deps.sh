#!/usr/bin/env bash
# Installs what Annex needs to build, test and run, from Debian 12's packages.
# Idempotent: only missing packages are installed. Sourced by demo.sh and test.sh.
set -euo pipefail

ANNEX_PACKAGES=(
  build-essential cmake ninja-build pkg-config git ca-certificates
  clang libclang-rt-14-dev                      # libFuzzer for the fuzz tests
  libeigen3-dev libpcl-dev libopenni2-dev libopenmpi-dev libcgal-dev
  libassimp-dev libglfw3-dev libglm-dev libimgui-dev libgl-dev libegl-dev libstb-dev zlib1g-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  assimp-testmodels                             # real models no one here wrote (model units tests)
  liblo-dev liblo-tools                         # the OSC stream; oscdump/oscsend in its tests
  xvfb xauth libgl1-mesa-dri                    # headless OpenGL for the editor's tests
  python3 python3-numpy python3-scipy           # independent reference for the assignment tests
  pybind11-dev python3-dev python3-pytest       # the Python module (bindings/python) and its tests
  mono-mcs mono-runtime                         # the C# binding and the Unity receiver of docs/streaming.md, run in tests
)

missing=()
for p in "${ANNEX_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "annex: installing ${#missing[@]} missing Debian packages: ${missing[*]}"
  SUDO=()
  if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null || { echo "annex: error: need root or sudo to install packages" >&2; exit 1; }
    SUDO=(sudo)
  fi
  export DEBIAN_FRONTEND=noninteractive
  "${SUDO[@]}" apt-get update -qq
  "${SUDO[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
