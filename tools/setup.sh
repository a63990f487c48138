#!/usr/bin/env bash
# Installs barnbench's dependencies (Debian packages only) and builds it in build/ (Release).
# Usage: tools/setup.sh            (as root, or with sudo available)
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(g++ cmake make pkg-config libbox2d-dev libeigen3-dev libyaml-cpp-dev libcli11-dev
          libgtest-dev libgmock-dev libbenchmark-dev libcairo2-dev nlohmann-json3-dev libboost-dev python3 python3-dev
          pybind11-dev python3-numpy python3-pytest slurm-wlm munge chromium strace)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq "${missing[@]}"
fi

# CI (CI=true) builds with warnings as errors; elsewhere warnings stay warnings.
werror=OFF
[ "${CI:-}" = "true" ] && werror=ON
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DBARN_WARNINGS_AS_ERRORS="$werror"
cmake --build build -j "$(nproc)"
echo "setup: built build/barn and the Python module in build/python (PYTHONPATH=build/python)"
