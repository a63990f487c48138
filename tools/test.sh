#!/usr/bin/env bash
# Installs dependencies if needed, builds, and runs the whole test suite (unit tests, the
# BARN dataset fidelity tests when ../shared/barn_dataset exists, and the CLI checks).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/setup.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
