#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz) in build-fuzz with clang++ and runs each one for
# SECONDS (default 5, the smoke run of tools/test.sh), seeded with the repository's own files.
# A finding (crash, sanitizer report, an exception other than core::InputError, a broken
# read/write round trip, a slow input, a large allocation) stops the script with exit 1; the
# input is saved as build-fuzz/findings/<target>/crash-* (or oom-, timeout-, leak-) and
# `build-fuzz/tests/fuzz/fuzz_<target> FILE` replays it.
# Usage: tools/fuzz.sh [SECONDS] [TARGET...]
#   targets: world_file npy policy config controller_config manifest episodes external_answer
#            (default all)
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-5}"
[ $# -gt 0 ] && shift
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(world_file npy policy config controller_config manifest episodes external_answer)

# Debian's clang brings libFuzzer and the sanitizer runtimes.
if ! command -v clang++ >/dev/null 2>&1; then
  echo "fuzz: installing clang"
  sudo_cmd=""
  [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq clang
fi

# ccache where there is one: the targets of controller configs, manifests and episodes build
# most of the libraries (controllers, navigation, simulation) with the sanitizers.
launcher=()
command -v ccache > /dev/null 2>&1 && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S . -B build-fuzz -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Release -DBARN_FUZZ=ON \
      -DBARN_BUILD_TESTS=OFF -DBARN_BUILD_PYTHON=OFF "${launcher[@]}" > /dev/null
cmake --build build-fuzz -j "$(nproc)" --target $(printf 'fuzz_%s ' "${targets[@]}") > build-fuzz/build.log 2>&1 ||
  { tail -n 40 build-fuzz/build.log; exit 1; }

# Small .npy seeds (no data files in the repository): the shapes and versions the reader meets.
mkdir -p build-fuzz/seeds/npy
/usr/bin/python3 - build-fuzz/seeds/npy <<'PY'
import sys
import numpy as np
from numpy.lib import format as npy_format
out = sys.argv[1]
np.save(f"{out}/empty_float64.npy", np.zeros((0, 3), dtype=np.float64))
np.save(f"{out}/grid_int64.npy", np.arange(16, dtype=np.int64).reshape(4, 4) % 2)
np.save(f"{out}/path_float64.npy", np.array([[0.0, 0.0], [0.5, 1.25], [1.0, 2.5]]))
np.save(f"{out}/scalar_int64.npy", np.array(7, dtype=np.int64))
with open(f"{out}/v2_int64.npy", "wb") as f:
    npy_format.write_array(f, np.array([1, 2, 3], dtype=np.int64), version=(2, 0))
PY

# The seeds are read where they are (libFuzzer's -seed_inputs), not copied.
seeds() {
  case "$1" in
    world_file) ls worlds/world_*.yaml ;;
    npy) ls build-fuzz/seeds/npy/*.npy ;;
    policy) ls tests/fuzz/seeds/policy/*.policy configs/policies/*.policy ;;
    config) ls configs/sim/*.yaml configs/controllers/*.yaml configs/lflh/*.yaml examples/external/*.yaml ;;
    controller_config) ls configs/controllers/*.yaml examples/external/*.yaml tests/fuzz/seeds/controller_config/*.yaml ;;
    manifest) ls results/baseline/*/manifest.yaml tests/fuzz/seeds/manifest/*.yaml ;;
    episodes) ls results/baseline/*/episodes.csv tests/fuzz/seeds/episodes/*.csv ;;
    external_answer) ls tests/fuzz/seeds/external_answer/*.json ;;
  esac
}
# Dictionaries of the formats' tokens (tests/fuzz/*.dict).
dict() {
  case "$1" in
    world_file|config|controller_config|manifest) echo tests/fuzz/yaml.dict ;;
    *) echo "tests/fuzz/$1.dict" ;;
  esac
}
# Longest input tried: a little over the largest seed that matters (the shipped policies,
# 1 MB of weights, are cut to their header).
max_len() {
  case "$1" in
    policy) echo 8192 ;;
    external_answer) echo 4096 ;;
    *) echo 16384 ;;
  esac
}

status=0
for target in "${targets[@]}"; do
  corpus="build-fuzz/corpus/$target"
  findings="build-fuzz/findings/$target"
  log="build-fuzz/logs/$target.log"
  mkdir -p "$corpus" "$findings" "$(dirname "$log")"
  seeds "$target" | paste -sd, > "build-fuzz/logs/$target.seeds"
  # -malloc_limit_mb: no reader needs 64 MB at once for an input of at most max_len bytes, so a
  # bigger single allocation means a size taken from the input unchecked.
  if "build-fuzz/tests/fuzz/fuzz_$target" "$corpus" -seed_inputs="@build-fuzz/logs/$target.seeds" \
       -dict="$(dict "$target")" -max_total_time="$seconds" -max_len="$(max_len "$target")" -timeout=10 \
       -rss_limit_mb=2048 -malloc_limit_mb=64 -artifact_prefix="$findings/" > "$log" 2>&1; then
    echo "fuzz: $target ok ($(grep -o 'Done [0-9]* runs in [0-9]* second(s)' "$log" | tail -n 1))"
  else
    echo "fuzz: $target FOUND A PROBLEM (log: $log; input in $findings/)"
    grep -v '^#[0-9]' "$log" | tail -n 40
    status=1
  fi
done
exit $status
