#!/usr/bin/env bash
# The speed figures of the README: each controller's simulated seconds per wall second per
# core, measured by `barn run`'s own performance line, as the median of repeats, and as a ratio
# to pure_pursuit (the simulator with a trivial controller) measured in the same round, so a
# busy machine moves both alike. Then the scaling of --jobs 2 over --jobs 1 (medians of the same
# number of repeats) on a larger set: on 30 episodes the last one's tail (up to a 100 s timeout)
# leaves a thread idle for much of the run, which a real run (300 x 10 episodes) never sees.
#
#   tools/speed_report.sh [--against OTHER_BUILD_DIR] [BUILD_DIR] [WORLDS] [REPEATS] [SCALING_WORLDS]
#   defaults: build, 0:300:10 (30 worlds spread over the difficulty range), 3, 0:300:3 (100)
#   SCALING_WORLDS "none" skips the --jobs scaling; CONTROLLERS="a b c" (environment) measures
#   those controllers instead of the main six (pure_pursuit is always measured, as the reference)
#
# --against: also runs each controller on another build (e.g. of the previous commit) right
# before this one's, --jobs 1, and reports the median of the paired ratios: the way to tell
# a change's speed on a machine whose rate drifts by more than the change between runs.
#
# Run it on an idle machine; it takes about 10 minutes on 2 cores.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
against=""
if [[ "${1:-}" == "--against" ]]; then
  against="${2:-}"
  [[ -x "$against/barn" ]] || { echo "speed_report.sh: --against '$against': no barn program in that folder" >&2; exit 2; }
  against="$(cd "$against" && pwd)"
  shift 2
fi
build="${1:-$here/build}"
worlds="${2:-0:300:10}"
repeats="${3:-3}"
scaling_worlds="${4:-0:300:3}"
read -r -a controllers <<<"${CONTROLLERS:-inventec_fi inventec_mpc lflh dwa eband}"
controllers=(pure_pursuit "${controllers[@]/pure_pursuit/}")
controllers=($(printf '%s\n' "${controllers[@]}" | grep .))
cd "$here"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

# Prints the "per core" figure and the wall seconds of one run.
measure() {  # controller jobs [build] [worlds]
  local out="$work/$1-$2-$RANDOM$RANDOM"
  "${3:-$build}/barn" run --controller "$1" --worlds "${4:-$worlds}" --jobs "$2" --out "$out" 2>/dev/null |
    sed -n 's/.*performance: wall \([0-9.]*\) s, simulated [0-9.]* s, [0-9]* simulated s per wall s (\([0-9]*\) per core.*/\2 \1/p'
  rm -rf "$out"
}

median() { sort -g | awk '{v[NR] = $1} END {if (NR == 0) exit; print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }

declare -A rate ratio scaling paired
for c in "${controllers[@]}"; do rate[$c]=""; ratio[$c]=""; scaling[$c]=""; paired[$c]=""; done
for ((r = 1; r <= repeats; ++r)); do
  base=$(measure pure_pursuit 1 | cut -d' ' -f1)
  for c in "${controllers[@]}"; do
    if [[ -n "$against" ]]; then read -r other _ < <(measure "$c" 1 "$against"); fi
    read -r per_core _ < <(measure "$c" 1)
    if [[ -n "$against" ]]; then paired[$c]+="$(awk -v a="$per_core" -v b="$other" 'BEGIN {printf "%.4f", a / b}') "; fi
    rate[$c]+="$per_core "
    ratio[$c]+="$(awk -v a="$per_core" -v b="$base" 'BEGIN {printf "%.4f", a / b}') "
    echo "round $r/$repeats: $c $per_core sim-s per wall-s per core (--jobs 1)" >&2
  done
done
for ((r = 1; r <= repeats; ++r)); do
  [[ "$scaling_worlds" == "none" ]] && break
  for c in "${controllers[@]}"; do
    read -r _ wall1 < <(measure "$c" 1 "$build" "$scaling_worlds")
    read -r _ wall2 < <(measure "$c" 2 "$build" "$scaling_worlds")
    scaling[$c]+="$(awk -v a="$wall1" -v b="$wall2" 'BEGIN {printf "%.3f", a / b}') "
    echo "scaling round $r/$repeats: $c --jobs 2 speed-up $(awk -v a="$wall1" -v b="$wall2" 'BEGIN {printf "%.2f", a / b}') on $scaling_worlds" >&2
  done
done

echo
echo "worlds $worlds, 1 trial, medians of $repeats rounds ($(nproc) cores)${against:+; paired against $against}; --jobs 2 / 1 on $scaling_worlds"
printf "%-14s %18s %16s %14s" controller "sim-s/s per core" "vs pure_pursuit" "--jobs 2 / 1"
[[ -n "$against" ]] && printf " %14s" "vs --against"
echo
for c in "${controllers[@]}"; do
  m=$(tr ' ' '\n' <<<"${rate[$c]}" | grep . | median)
  q=$(tr ' ' '\n' <<<"${ratio[$c]}" | grep . | median)
  s=$(tr ' ' '\n' <<<"${scaling[$c]}" | { grep . || true; } | median)
  sc="-"
  [[ -n "$s" ]] && sc=$(awk -v s="$s" 'BEGIN {printf "%.2f", s}')
  printf "%-14s %18s %16s %14s" "$c" "$m" "$(awk -v q="$q" 'BEGIN {printf "%.3f", q}')" "$sc"
  if [[ -n "$against" ]]; then
    p=$(tr ' ' '\n' <<<"${paired[$c]}" | grep . | median)
    printf " %14s" "$(awk -v p="$p" 'BEGIN {printf "%.2f", p}')"
  fi
  echo
done
