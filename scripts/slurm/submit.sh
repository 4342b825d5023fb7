#!/usr/bin/env bash
# A sweep or a benchmark as a Slurm array job of TASKS shards, then their merge:
#
#   scripts/slurm/submit.sh sweep TASKS OUT FLAGS...
#   scripts/slurm/submit.sh benchmark TASKS OUT FLAGS...
#
# e.g. scripts/slurm/submit.sh sweep 8 runs/sweep --gamma 0.99,0.995,0.999 --seeds 0..5
#
# Run from the repository's root on the cluster's login node. It builds once
# (so the tasks do not all compile), submits the array (task K writes
# OUT/shard-K, its log OUT/logs/shard-K.out) and the merge into OUT, which
# starts when every task has succeeded. Prints the two job ids.
set -euo pipefail
cd "$(dirname "$0")/../.."
kind=${1:?usage: submit.sh sweep|benchmark TASKS OUT FLAGS...}
tasks=${2:?usage: submit.sh sweep|benchmark TASKS OUT FLAGS...}
out=${3:?usage: submit.sh sweep|benchmark TASKS OUT FLAGS...}
shift 3
case "$kind" in sweep | benchmark) ;; *) echo "submit.sh: the kind is sweep or benchmark, not $kind" >&2; exit 2 ;; esac
cargo build --release --example "$kind"
mkdir -p "$out/logs"
array=$(sbatch --parsable --array="1-$tasks" --output="$out/logs/shard-%a.out" \
    scripts/slurm/shard.sbatch "$kind" "$out" "$@")
array=${array%%;*}
merge=$(sbatch --parsable --dependency="afterok:$array" --output="$out/logs/merge.out" \
    scripts/slurm/merge.sbatch "$kind" "$out" "$@")
merge=${merge%%;*}
echo "array job $array ($tasks tasks) and merge job $merge; results in $out"
