#!/usr/bin/env bash
# Installs dependencies if needed, builds, runs the whole test suite (unit tests, the BARN
# dataset fidelity tests when ../shared/barn_dataset exists, the CLI checks), then the score
# regression check against the committed baseline (results/baseline, see the README).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
build/barn regress --baseline results/baseline
