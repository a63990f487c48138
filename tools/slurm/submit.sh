#!/usr/bin/env bash
# Submits a barnbench run or sweep to Slurm as a job array of shards plus a merge job that
# starts when every shard has succeeded. The merged record equals a single-machine run.
#
#   tools/slurm/submit.sh [Slurm options] run   OUT --controller NAME [barn run options...]
#   tools/slurm/submit.sh [Slurm options] sweep OUT --controller NAME --param K=V1,V2 [barn sweep options...]
#
# e.g.  tools/slurm/submit.sh --shards 10 --partition short run results/fi_all \
#           --controller inventec_fi --worlds all --trials 10
#
# Slurm options (the defaults fit a small node):
#   --shards N          array tasks, one shard each (default 4)
#   --cpus-per-task C   CPUs per task, used as barn's --jobs (default 2)
#   --mem SIZE          memory per task (default 2G)
#   --time T            time limit per task (default 01:00:00)
#   --partition P, --account A, --qos Q
#   --sbatch OPTION     any other sbatch option, repeatable (e.g. --sbatch --constraint=avx2)
#   --dry-run           print the two sbatch commands instead of submitting them
#
# These come before run|sweep (after it, they are refused). barn's options are checked once
# (barn run|sweep --check) before anything is submitted.
#
# Writes OUT/shard_K (one per task), OUT/merged (the result) and OUT/logs/. Tasks may be
# requeued (preemption, node failure): a task that runs again resumes its shard. If a task
# fails or hits its time limit, run the same command again: finished shards are no-ops,
# unfinished ones resume, and the merge follows. OUT remembers the experiment; a different
# one in the same OUT is refused.
set -euo pipefail

usage() {
  sed -n '2,/^set -euo/p' "$0" | grep '^#' | sed 's/^# \{0,1\}//' >&2
  exit 2
}
fail() { echo "submit: $*" >&2; exit 2; }

shards=4
cpus=2
mem=2G
time_limit=01:00:00
dry_run=false
extra=()
while [ $# -gt 0 ]; do
  case $1 in
    --shards) [ $# -ge 2 ] || usage; shards=$2; shift 2 ;;
    --cpus-per-task) [ $# -ge 2 ] || usage; cpus=$2; shift 2 ;;
    --mem) [ $# -ge 2 ] || usage; mem=$2; shift 2 ;;
    --time) [ $# -ge 2 ] || usage; time_limit=$2; shift 2 ;;
    --partition|--account|--qos) [ $# -ge 2 ] || usage; extra+=("$1=$2"); shift 2 ;;
    --sbatch) [ $# -ge 2 ] || usage; extra+=("$2"); shift 2 ;;
    --dry-run) dry_run=true; shift ;;
    -h|--help) usage ;;
    run|sweep) break ;;
    *) fail "unknown option $1 (Slurm options come before run|sweep; see $0 --help)" ;;
  esac
done
[ $# -ge 2 ] || usage
mode=$1
out=$2
shift 2
[[ $shards =~ ^[1-9][0-9]*$ ]] || fail "--shards $shards: not a positive whole number"
[[ $cpus =~ ^[1-9][0-9]*$ ]] || fail "--cpus-per-task $cpus: not a positive whole number"
for option in "$@"; do
  case $option in
    --out|--out=*|--shard|--shard=*|--resume|--resume=*|--merge|--merge=*|--jobs|--jobs=*)
      fail "$option: set by the job array (OUT is the second argument, --jobs is --cpus-per-task)" ;;
    --shards|--shards=*|--cpus-per-task|--cpus-per-task=*|--mem|--mem=*|--time|--time=*|--partition|--partition=*| \
    --account|--account=*|--qos|--qos=*|--sbatch|--sbatch=*|--dry-run)
      # Passed on, it would reach barn (every task failing) and a misplaced --dry-run would submit.
      fail "$option: an option of submit.sh, which must come before $mode (see $0 --help)" ;;
  esac
done

here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
[ -x "$repo/build/barn" ] || fail "$repo/build/barn not found: build barnbench first (tools/setup.sh)"
out=$(realpath -m "$out")

# barn's own arguments are checked once, as task 1 would read them, before anything is queued
# (a bad controller name would otherwise fail every task and kill the merge job). --check
# reads everything and writes nothing.
if [ ! -f "$out/experiment.txt" ]; then
  "$repo/build/barn" "$mode" --check --shard "1/$shards" --out "$out/shard_1" "$@" > /dev/null ||
    fail "barn $mode refused the options above (nothing submitted)"
fi

# The experiment OUT holds: a second submit must be the same one, or shards would resume
# a different experiment than the command asks for.
experiment=$(printf '%s\n' "$mode" "$shards" "$@")
if [ -f "$out/experiment.txt" ]; then
  [ "$(cat "$out/experiment.txt")" = "$experiment" ] ||
    fail "$out holds a different experiment (see $out/experiment.txt); choose another OUT"
elif [ "$dry_run" = false ]; then
  mkdir -p "$out/logs"
  printf '%s\n' "$experiment" > "$out/experiment.txt"
fi

array=(sbatch --parsable --array="1-$shards" --cpus-per-task="$cpus" --mem="$mem" --time="$time_limit"
       --requeue --open-mode=append --output="$out/logs/shard_%a.log" --export=ALL,BARN_REPO="$repo"
       "${extra[@]}" "$here/barn_array.sbatch" "$mode" "$out" "$@")
merge=(sbatch --parsable --kill-on-invalid-dep=yes --output="$out/logs/merge.log" --open-mode=append
       --export=ALL,BARN_REPO="$repo" "${extra[@]}" "$here/barn_merge.sbatch" "$mode" "$out" "$shards")
if [ "$dry_run" = true ]; then
  printf '%q ' "${array[@]}"; echo
  printf '%q ' "${merge[@]:0:2}" "--dependency=afterok:ARRAY_JOB" "${merge[@]:2}"; echo
  exit 0
fi
array_job=$("${array[@]}")
array_job=${array_job%%;*}  # --parsable prints "id;cluster" on multi-cluster setups
merge_job=$("${merge[@]:0:2}" --dependency="afterok:$array_job" "${merge[@]:2}")
merge_job=${merge_job%%;*}
echo "submitted job array $array_job ($shards shards) and merge job $merge_job"
echo "result: $out/merged   logs: $out/logs/   watch: squeue -j $array_job,$merge_job"
