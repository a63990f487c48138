#!/usr/bin/env bash
# Installs dependencies if needed, builds, runs the whole test suite (unit tests, the Python
# tests, the CLI checks; the BARN dataset fidelity tests when BARN_DATASET_DIR names a copy of
# the original dataset), a 5-second smoke run of each file-reader fuzzer (tools/fuzz.sh, its
# own clang build in build-fuzz), 39 kill -9s of a small run each finished byte-identical
# (tools/kill_resume_check.sh), the Slurm path on a throw-away local Slurm
# (tools/slurm/test_slurm.sh), then the score regression check against the committed baseline
# (results/baseline, see the README).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
tools/fuzz.sh 5
tools/kill_resume_check.sh
tools/slurm/test_slurm.sh
build/barn regress --baseline results/baseline
