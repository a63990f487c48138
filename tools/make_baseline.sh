#!/usr/bin/env bash
# (Re)creates the committed score baseline in results/baseline: one small but meaningful
# reference run per main controller. Run it (or `build/barn regress --update`) only after an
# intended change of behaviour, and commit the result with a note saying why scores moved.
set -euo pipefail
cd "$(dirname "$0")/.."
rm -rf results/baseline
for controller in pure_pursuit dwa lflh inventec_fi kulfm; do
  build/barn run --controller "$controller" --worlds test50 --trials 2 --out "results/baseline/$controller"
done
