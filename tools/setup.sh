#!/usr/bin/env bash
# Installs barnbench's dependencies (Debian packages only) and builds it in build/ (Release).
# Usage: tools/setup.sh            (as root, or with sudo available)
#        tools/setup.sh --with-torch   (or BARN_WITH_TORCH=1): also Debian's PyTorch (CPU), PyYAML and
#        OpenBLAS, for the training tools (tools/train_e2e.py, docs/rl.md); never needed to build or run
set -euo pipefail
cd "$(dirname "$0")/.."
with_torch="${BARN_WITH_TORCH:-0}"
for arg in "$@"; do
  case "$arg" in
    --with-torch) with_torch=1 ;;
    *) echo "setup: unknown argument '$arg' (known: --with-torch)" >&2; exit 2 ;;
  esac
done

packages=(g++ cmake make pkg-config libbox2d-dev libeigen3-dev libyaml-cpp-dev libcli11-dev
          libgtest-dev libgmock-dev libbenchmark-dev libcairo2-dev libfreetype-dev fonts-dejavu-core nlohmann-json3-dev libboost-dev python3 python3-dev
          pybind11-dev python3-numpy python3-pytest slurm-wlm munge chromium strace)
# The training tools' extras, only when asked: Debian's torch multiplies matrices with the
# reference BLAS unless an optimised one is installed (OpenBLAS: about 20x faster training).
[ "$with_torch" = "1" ] && packages+=(python3-torch python3-yaml libopenblas0-serial)
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
