#!/usr/bin/env bash
# Checks the Slurm path end to end on a real (throw-away, single-node) Slurm:
#   1. a sharded run and a sharded sweep submitted with tools/slurm/submit.sh merge into records
#      byte-identical to single-machine runs of the same options;
#   2. a task requeued mid-run (as preemption does) resumes its shard, keeps the episodes it
#      had finished, and the merged record is still identical.
# Skips (exit 0, with the reason) only when Slurm cannot start on this machine.
# Run by tools/test.sh; needs build/barn (tools/setup.sh).
set -euo pipefail
cd "$(dirname "$0")/../.."
repo=$(pwd)
barn=$repo/build/barn

work=$(mktemp -d /tmp/barn_slurm_test.XXXXXX)
chmod 755 "$work"  # munged wants every folder above its socket reachable by all
cluster=$work/cluster
cleanup() {
  tools/slurm/local_cluster.sh stop "$cluster" >/dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT

status=0
tools/slurm/local_cluster.sh start "$cluster" || status=$?
if [ "$status" -eq 3 ]; then
  echo "slurm test: SKIPPED: Slurm cannot start on this machine (reason above)"
  exit 0
elif [ "$status" -ne 0 ]; then
  exit "$status"
fi
export SLURM_CONF=$cluster/slurm.conf

fail() {
  echo "slurm test: FAILED: $*" >&2
  for log in "$work"/*/logs/*.log; do [ -f "$log" ] && { echo "--- $log" >&2; tail -n 20 "$log" >&2; }; done
  exit 1
}

# Waits until Slurm has no job of this cluster left (at most $1 seconds).
wait_idle() {
  for _ in $(seq 1 $(($1 * 5))); do
    [ -z "$(squeue -h)" ] && return 0
    sleep 0.2
  done
  squeue >&2
  fail "jobs still queued after $1 s"
}

same_file() { cmp -s "$1" "$2" || fail "$2 differs from the single-machine $1"; }

# --- 1. sharded run and sweep --------------------------------------------------------------
run_options=(--controller pure_pursuit --worlds 0:300:10 --trials 2 --seed 7)
sweep_options=(--controller pure_pursuit --param lookahead=0.4,0.8 --param speed=0.5,1.0 --worlds 0:300:25 --seed 3)
"$barn" run "${run_options[@]}" --out "$work/reference_run" >/dev/null
"$barn" sweep "${sweep_options[@]}" --out "$work/reference_sweep" >/dev/null

tools/slurm/submit.sh --shards 3 --cpus-per-task 1 --mem 500M --time 00:10:00 run "$work/run" "${run_options[@]}"
tools/slurm/submit.sh --shards 2 --cpus-per-task 1 --mem 500M --time 00:10:00 sweep "$work/sweep" "${sweep_options[@]}"
wait_idle 120
for file in episodes.csv summary.json; do same_file "$work/reference_run/$file" "$work/run/merged/$file"; done
same_file "$work/reference_sweep/sweep.csv" "$work/sweep/merged/sweep.csv"
for cell in "$work"/reference_sweep/*/; do
  same_file "$cell/episodes.csv" "$work/sweep/merged/$(basename "$cell")/episodes.csv"
done
echo "slurm test: sharded run (3 tasks) and sweep (2 tasks x 4 cells) identical to single-machine runs"

# A second submit of a different experiment into the same folder is refused.
if tools/slurm/submit.sh --shards 3 run "$work/run" --controller pure_pursuit --worlds 0:300:10 --trials 3 2>/dev/null; then
  fail "submit.sh accepted a different experiment in $work/run"
fi

# --- 2. a task requeued mid-run resumes -----------------------------------------------------
requeue_options=(--controller dwa --worlds 0:300:20 --trials 1)
"$barn" run "${requeue_options[@]}" --out "$work/reference_requeue" >/dev/null
submitted=$(tools/slurm/submit.sh --shards 2 --cpus-per-task 1 --mem 500M --time 00:10:00 run "$work/requeue" "${requeue_options[@]}")
array_job=$(sed -n 's/^submitted job array \([0-9]*\) .*/\1/p' <<<"$submitted")
[ -n "$array_job" ] || fail "no job id in: $submitted"
journal=$work/requeue/shard_1/episodes.partial.csv
for _ in $(seq 1 300); do
  [ -f "$journal" ] && [ "$(wc -l < "$journal")" -ge 3 ] && break
  sleep 0.1
done
[ -f "$journal" ] || fail "shard 1 never started"
[ ! -f "$work/requeue/shard_1/episodes.csv" ] || fail "shard 1 finished before it could be requeued; make it longer"
scontrol requeue "${array_job}_1"
# Slurm holds a requeued job back for a while (BeginTime); release it now.
for _ in $(seq 1 50); do
  squeue -h -j "${array_job}_1" -o %T 2>/dev/null | grep -q PENDING && break
  sleep 0.2
done
scontrol update jobid="${array_job}_1" StartTime=now
wait_idle 180
log=$work/requeue/logs/shard_1.log
grep -q "attempt 2" "$log" || fail "shard 1 did not run a second time ($log)"
kept=$(sed -n 's/^resuming: \([0-9]*\) episodes already finished/\1/p' "$log")
if [ -z "$kept" ] || [ "$kept" -eq 0 ]; then fail "the requeued task did not resume its shard ($log)"; fi
for file in episodes.csv summary.json; do same_file "$work/reference_requeue/$file" "$work/requeue/merged/$file"; done
echo "slurm test: task requeued mid-run resumed with $kept episodes kept; merged record identical"
echo "slurm test: passed"
