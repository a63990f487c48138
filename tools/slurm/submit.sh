#!/usr/bin/env bash
# Submits a sharded barnbench run and a merge job that starts when every shard succeeded.
#
#   tools/slurm/submit.sh SHARDS CONTROLLER RECORD_DIR [barn run options...]
#   e.g. tools/slurm/submit.sh 16 pure_pursuit results/pp_all --worlds all --trials 10
#
# The merged record lands in RECORD_DIR/merged.
set -euo pipefail
if [ $# -lt 3 ]; then
  echo "usage: $0 SHARDS CONTROLLER RECORD_DIR [barn run options...]" >&2
  exit 2
fi
shards=$1
controller=$2
record=$3
shift 3
here=$(cd "$(dirname "$0")" && pwd)
repo=$(cd "$here/../.." && pwd)
array_job=$(sbatch --parsable --array="1-${shards}" "$here/barn_array.sbatch" "$controller" "$record" "$@")
shard_dirs=()
for k in $(seq 1 "$shards"); do shard_dirs+=("$record/shard_$k"); done
sbatch --dependency="afterok:${array_job}" --job-name=barnbench-merge --cpus-per-task=1 --time=00:10:00 \
  --output="barnbench_merge_%j.log" --wrap="$repo/build/barn merge ${shard_dirs[*]} --out $record/merged"
echo "submitted array job $array_job ($shards shards) and its merge; result: $record/merged"
