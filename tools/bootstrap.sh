#!/usr/bin/env bash
# One-command set-up for BlendBench on Debian 12: installs the Debian packages that are
# missing, configures and builds in Release, then either runs the default scenario ("run") or
# the whole test suite ("test").
#
#   bash tools/bootstrap.sh run [extra arguments for `blendbench run`]
#   bash tools/bootstrap.sh test
set -euo pipefail

mode=${1:-}
shift || true
case "$mode" in
  run|test) ;;
  *) echo "usage: bash tools/bootstrap.sh run|test [arguments]" >&2; exit 2 ;;
esac

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"

packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libmujoco-dev libosmesa6-dev liburdfdom-dev libyaml-dev libyaml-cpp-dev
  libcli11-dev nlohmann-json3-dev googletest libgtest-dev libbenchmark-dev
  ffmpeg python3 python3-matplotlib python3-numpy python3-pil python3-yaml
)
# the test suite also brings up a one-machine Slurm for the sweep's job-array test
if [ "$mode" = test ]; then
  packages+=(slurm-wlm munge)
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "bootstrap: installing ${missing[*]}"
  if [ "$(id -u)" -eq 0 ]; then
    sudo=()
  elif command -v sudo >/dev/null 2>&1; then
    sudo=(sudo)
  else
    echo "bootstrap: these Debian packages are missing and this user cannot install them:" >&2
    echo "  ${missing[*]}" >&2
    echo "ask an administrator to run: apt-get install ${missing[*]}" >&2
    exit 1
  fi
  export DEBIAN_FRONTEND=noninteractive
  "${sudo[@]}" apt-get update -qq
  "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j "$jobs"

if [ "$mode" = run ]; then
  exec build/blendbench run "$@"
else
  exec ctest --test-dir build --output-on-failure -j "$jobs" "$@"
fi
