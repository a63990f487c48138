#!/usr/bin/env bash
# kill -9 at any moment of `barn run`, then finish the record as a requeued job does: the
# record ends byte-identical to an uninterrupted run's (episodes.csv, summary.json, every
# trajectory file, and the manifest apart from its start and wall times).
#
# 39 kills of a small run (pure_pursuit, 10 worlds x 2 trials, --jobs 2, --trajectories):
#   - 9 timed kills, spread over the run's length;
#   - 2 chains of 3 timed kills (the run killed, its resume killed, that resume killed);
#   - 24 kills at an exact system call (strace fault injection; skipped without strace): the
#     1st to 6th rename and fsync, the 1st to 4th unlink, linkat and write.
# A record is finished as tools/slurm/barn_array.sbatch finishes a shard: `barn run --resume`
# if it holds a manifest or a commit note (an interrupted write), else the run again.
#
# Usage: tools/kill_resume_check.sh [BARN]   (default build/barn). Exit 1 on a difference.
# Run by tools/test.sh; about a minute on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
barn=$(realpath "${1:-build/barn}")
work=$(mktemp -d /tmp/barn_kill_check.XXXXXX)
trap 'rm -rf "$work"' EXIT
args=(run --controller pure_pursuit --worlds 0:300:30 --trials 2 --jobs 2 --trajectories)

start=$(date +%s.%N)
"$barn" "${args[@]}" --out "$work/reference" > /dev/null
length=$(echo "$(date +%s.%N) - $start" | bc)

failures=0
kills=0   # processes killed
records=0 # records checked

# Finishes the record in $1 as a requeued job would; a few goes (each may find another state).
finish() {
  local out=$1
  for _ in 1 2 3; do
    if [ -f "$out/manifest.yaml" ] || [ -f "$out/.barn.commit" ]; then
      "$barn" run --resume "$out" > "$out.log" 2>&1 && return 0
    else
      "$barn" "${args[@]}" --out "$out" > "$out.log" 2>&1 && return 0
    fi
  done
  return 1
}

# The manifest without what differs between sessions by design (when it ran, for how long).
stable_manifest() { grep -v -E '^(started|wall_time_s): ' "$1"; }

# Checks the finished record $2 against the reference; $1 says how it was killed.
check() {
  local how=$1 out=$2 problem=""
  records=$((records + 1))
  if ! finish "$out"; then
    problem="could not be finished: $(tail -n 3 "$out.log" | tr '\n' ' ')"
  else
    for file in episodes.csv summary.json; do
      cmp -s "$work/reference/$file" "$out/$file" || problem="$problem $file differs;"
    done
    diff -q <(stable_manifest "$work/reference/manifest.yaml") <(stable_manifest "$out/manifest.yaml") > /dev/null ||
      problem="$problem manifest.yaml differs;"
    diff -rq "$work/reference/trajectories" "$out/trajectories" > /dev/null 2>&1 || problem="$problem trajectories/ differ;"
    [ -e "$out/.barn.commit" ] && problem="$problem a commit note is left;"
  fi
  if [ -n "$problem" ]; then
    echo "kill check: FAILED after $how: $problem (record kept in $out)"
    failures=$((failures + 1))
    trap - EXIT
  fi
  return 0
}

# Starts the run (or resumes the record) in $1 and kills it -9 after $2 seconds.
kill_after() {
  local out=$1 delay=$2
  if [ -f "$out/manifest.yaml" ] || [ -f "$out/.barn.commit" ]; then
    "$barn" run --resume "$out" > /dev/null 2>&1 &
  else
    "$barn" "${args[@]}" --out "$out" > /dev/null 2>&1 &
  fi
  local pid=$!
  sleep "$delay"
  kill -9 "$pid" 2> /dev/null || true
  wait "$pid" 2> /dev/null || true
  kills=$((kills + 1))
}

# 9 timed kills at 5 %, 15 %, ... 85 % of the run's length.
for k in 0 1 2 3 4 5 6 7 8; do
  delay=$(echo "$length * (5 + 10 * $k) / 100" | bc -l)
  kill_after "$work/timed_$k" "$delay"
  check "a kill at $(printf '%.2f' "$delay") s" "$work/timed_$k"
done

# 2 chains: killed, resumed and killed, resumed and killed, then finished.
for chain in 1 2; do
  out=$work/chain_$chain
  for step in 1 2 3; do kill_after "$out" "$(echo "$length * (0.1 * $step + 0.05 * $chain)" | bc -l)"; done
  check "a chain of 3 kills ($chain)" "$out"
done

# 24 kills at an exact system call.
if command -v strace > /dev/null 2>&1; then
  for spec in rename:1:6 fsync:1:6 unlink:1:4 linkat:1:4 write:1:4; do
    IFS=: read -r call first last <<< "$spec"
    for when in $(seq "$first" "$last"); do
      out=$work/${call}_$when
      # strace re-raises the tracee's SIGKILL on its process group: setsid keeps this script
      # out of it. The braces send the shell's own "Killed" notice to /dev/null too.
      { setsid strace -f -o /dev/null -e trace="$call" -e inject="$call:signal=SIGKILL:when=$when" \
          "$barn" "${args[@]}" --out "$out" > /dev/null 2>&1; } 2> /dev/null || true
      kills=$((kills + 1))
      check "a kill at $call #$when" "$out"
    done
  done
else
  echo "kill check: strace not found: the 24 kills at exact system calls are skipped"
fi

if [ "$failures" -gt 0 ]; then
  echo "kill check: $failures of $records records ($kills kills) did not finish byte-identical"
  exit 1
fi
printf 'kill check: %d kills in %d records, all finished byte-identical (the run alone: %.1f s)\n' \
  "$kills" "$records" "$length"
