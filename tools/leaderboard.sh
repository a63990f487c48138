#!/usr/bin/env bash
# The BARN leaderboard in barnbench: runs every system barnbench implements on the official
# test worlds of a BARN dataset copy and on barnbench's own test50 worlds, each on its edition's
# scale, and rewrites the generated table of docs/leaderboard.md.
#
# Usage: tools/leaderboard.sh BARN_DATASET [WORK_DIR]
#   BARN_DATASET   the official BARN dataset folder (grid_files/, path_files/, ...); its test
#                  worlds (0, 6, ...) that it holds are the "official" column
#   WORK_DIR       where the records go (default: a new temporary folder)
# Environment: OFFICIAL_TRIALS (10), TEST50_TRIALS (2), JOBS (all cores), ONLY (a comma list of
# controllers to rerun; the others' records must already be in WORK_DIR).
# The learned rows need the published networks converted first (docs/leaderboard.md):
# configs/policies/lics_transformer_99.policy and configs/policies/applr_dwa.policy; a row
# whose network is missing is listed as such. Needs build/barn (tools/setup.sh) and python3.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 1 ]; then
  sed -n '2,/^set -euo/p' "$0" | grep '^#' | sed 's/^# \{0,1\}//' >&2
  exit 2
fi
dataset=$1
work=${2:-$(mktemp -d /tmp/barn_leaderboard.XXXXXX)}
official_trials=${OFFICIAL_TRIALS:-10}
test50_trials=${TEST50_TRIALS:-2}
jobs=${JOBS:-0}
[ -d "$dataset" ] || { echo "leaderboard: no dataset folder $dataset" >&2; exit 2; }
[ -x build/barn ] || { echo "leaderboard: build/barn missing; run tools/setup.sh" >&2; exit 2; }
mkdir -p "$work"

worlds="$work/official_worlds"
[ -d "$worlds" ] || build/barn import-barn "$dataset" --out "$worlds" > /dev/null
official=$(seq 0 6 294 | while read -r w; do
             if [ -f "$(printf '%s/world_%03d.yaml' "$worlds" "$w")" ]; then echo "$w"; fi
           done | paste -sd, -)
[ -n "$official" ] || { echo "leaderboard: the dataset holds no official test world" >&2; exit 2; }

# controller protocol: each system on its edition's scale (k = 4 up to 2023, k = 2 from 2024).
rows="kulfm barn2023
inventec_fi barn2023
almeria_tps barn2023
ut_amrl barn2023
lflh barn2023
eband barn2023
e2e barn2023
applr_dwa barn2023
meco barn2023
dwa_fast barn2023
dwa barn2023
lics barn2024
rrsl_vfh barn2024
in2bot barn2024"

run() {  # controller protocol worlds-dir worlds trials name
  if [ -d "$work/$6" ]; then return; fi
  if ! build/barn run --controller "$1" --protocol "$2" --world-dir "$3" --worlds "$4" --trials "$5" --jobs "$jobs" \
       --out "$work/$6" > "$work/$6.log" 2>&1; then
    if [ -f "$work/$6/summary.json" ]; then
      echo "leaderboard: $6 done (some episodes ended in error)"
    else
      echo "leaderboard: $6 could not run: $(grep -m1 -i 'error' "$work/$6.log" || tail -n 1 "$work/$6.log")"
    fi
    return
  fi
  echo "leaderboard: $6 done"
}
while read -r controller protocol; do
  if [ -n "${ONLY:-}" ] && [[ ",$ONLY," == *",$controller,"* ]]; then
    rm -rf "$work/official_$controller" "$work/test50_$controller"
  fi
  run "$controller" "$protocol" "$worlds" "$official" "$official_trials" "official_$controller"
  run "$controller" "$protocol" worlds test50 "$test50_trials" "test50_$controller"
done <<< "$rows"

python3 tools/leaderboard.py "$work" "$official_trials" "$test50_trials"
