#!/usr/bin/env bash
# The README's Slurm jobs, run for real on a one-node cluster (CI runs this;
# it needs root and Debian's slurm-wlm, which it installs if missing):
#
# 1. a sweep grid (4 combinations x 2 seeds, 12 s trials) as an array of 3
#    tasks, then the merge, checked row for row against the unsharded sweep
#    (but for the wall-clock realtime_factor and learner_wall_s);
# 2. a task killed by `kill -9` mid-run and requeued as the same array
#    element resumes into its directory and finishes: its rows, and the
#    merge's, are the unsharded sweep's, none lost and none twice;
# 3. a task whose sweep.csv was truncated is refused, the error naming the
#    file;
# 4. the benchmark as an array of 2 tasks and its merge, checked the same way.
#
# The daemons are stopped on the way out, pass or fail.
set -euo pipefail
cd "$(dirname "$0")/../.."
root=$(pwd)
work=$root/target/slurm-check
rm -rf "$work"
mkdir -p "$work"
cache=$root/target/tmp/reference-cache

if ! command -v slurmctld > /dev/null; then
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq slurm-wlm > /dev/null 2>&1 ||
        { apt-get update -qq > /dev/null 2>&1 &&
            DEBIAN_FRONTEND=noninteractive apt-get install -y -qq slurm-wlm > /dev/null 2>&1; }
fi
trap 'bash "$root/scripts/slurm/local-cluster.sh" stop "$work/cluster"' EXIT
bash scripts/slurm/local-cluster.sh start "$work/cluster"
export SLURM_CONF=$work/cluster/slurm.conf
cargo build --release --example sweep --example benchmark

fail() { echo "slurm check: $*" >&2; exit 1; }
# Waits until job $1 (an array job's id waits for all its tasks) has left
# the queue, at most $2 s.
wait_job() {
    for _ in $(seq $((2 * $2))); do
        [ -z "$(squeue -h -j "$1" 2> /dev/null)" ] && return 0
        sleep 0.5
    done
    squeue
    fail "job $1 still in the queue after $2 s"
}
state() { scontrol show job "$1" | grep -oE 'JobState=[A-Z_]+' | head -n 1 | cut -d= -f2; }
# The rows of two CSV files equal but for the wall-clock columns.
same_rows() {
    python3 - "$1" "$2" << 'PY'
import csv, sys
def rows(path):
    r = list(csv.reader(open(path)))
    drop = [i for i, c in enumerate(r[0]) if c in ("realtime_factor", "learner_wall_s")]
    return [[c for i, c in enumerate(row) if i not in drop] for row in r]
a, b = rows(sys.argv[1]), rows(sys.argv[2])
if a != b:
    sys.exit(f"{sys.argv[2]}: {len(b) - 1} rows differ from {sys.argv[1]}'s {len(a) - 1}")
print(f"{sys.argv[2]}: the same {len(a) - 1} rows as {sys.argv[1]} (but for the wall-clock columns)")
PY
}
rows() { echo $(($(wc -l < "$1") - 1)); }
# Requeues array task $1 (whose log is $2) and waits until it has run. slurmd
# refuses to launch a job it has only just seen end ("Job N already killed,
# do not launch batch job"), and the controller then marks it FAILED without
# running it, so no log is written: the log is removed first, and the task
# requeued again (at most 3 times) while none appears.
requeue_task() {
    local task=$1 log=$2 attempt
    for attempt in 1 2 3; do
        rm -f "$log"
        sleep 2
        scontrol requeue "$task"
        scontrol update jobid="$task" StartTime=now
        wait_job "${task%%_*}" 300
        [ -f "$log" ] && return 0
        echo "requeue $attempt: task $task ended $(state "$task") without running"
    done
    fail "task $task did not run after 3 requeues"
}

# Runs KIND (sweep or benchmark) with FLAGS unsharded, and through submit.sh
# as an array of TASKS and the merge into $work/NAME; checks that the merged
# CSV has the unsharded one's rows.
sharded_as_unsharded() {
    local kind=$1 tasks=$2 name=$3 csv=$4 submitted array merge
    shift 4
    "target/release/examples/$kind" "$@" --out "$work/$name-unsharded" > "$work/$name-unsharded.log"
    submitted=$(scripts/slurm/submit.sh "$kind" "$tasks" "$work/$name" "$@" | tail -n 1)
    echo "$submitted"
    array=$(sed -nE 's/.*array job ([0-9]+).*/\1/p' <<< "$submitted")
    merge=$(sed -nE 's/.*merge job ([0-9]+).*/\1/p' <<< "$submitted")
    wait_job "$array" 300
    wait_job "$merge" 120
    [ "$(state "$merge")" = COMPLETED ] ||
        fail "the $kind merge job ended $(state "$merge"): $(cat "$work/$name/logs/merge.out")"
    same_rows "$work/$name-unsharded/$csv" "$work/$name/$csv"
}

echo "== 1. the README's sweep as an array job, then the merge"
sharded_as_unsharded sweep 3 sweep sweep.csv \
    --gamma 0.99,0.999 --t-start 2,4 --seeds 0..2 --set trial.duration=12 --cache "$cache"

echo "== 2. a task killed mid-run, requeued as the same element, resumes"
long=(--gamma 0.99,0.999 --seeds 0..6 --set trial.duration=200 --cache "$cache")
target/release/examples/sweep "${long[@]}" --out "$work/long-unsharded" > "$work/long-unsharded.log"
mkdir -p "$work/long/logs"
array=$(sbatch --parsable --array=1-2 --output="$work/long/logs/shard-%a.out" \
    scripts/slurm/shard.sbatch sweep "$work/long" "${long[@]}")
array=${array%%;*}
csv=$work/long/shard-2/sweep.csv
for _ in $(seq 1200); do
    [ -f "$csv" ] && [ "$(rows "$csv")" -ge 1 ] && break
    sleep 0.05
done
[ -f "$csv" ] || fail "task 2 wrote no row in 60 s"
pkill -9 -f -- "--out $work/long/shard-2\$" || fail "no process of task 2 to kill"
done_at_kill=$(rows "$csv")
echo "killed task ${array}_2 (kill -9) with $done_at_kill of its 6 runs in $csv"
[ "$done_at_kill" -lt 6 ] || fail "task 2 had finished before it was killed: lengthen the trials"
for _ in $(seq 60); do
    s=$(state "${array}_2")
    [ "$s" != RUNNING ] && [ "$s" != COMPLETING ] && break
    sleep 0.5
done
echo "task ${array}_2 ended $(state "${array}_2")"
requeue_task "${array}_2" "$work/long/logs/shard-2.out"
[ "$(state "${array}_2")" = COMPLETED ] || fail "the requeued task ended $(state "${array}_2")"
grep -q "already done" "$work/long/logs/shard-2.out" || fail "the requeued task did not report a resume"
grep "already done" "$work/long/logs/shard-2.out"
[ "$(rows "$csv")" = 6 ] || fail "task 2 has $(rows "$csv") rows, not its 6"
target/release/examples/sweep --merge "$work"/long/shard-* --out "$work/long" > /dev/null
same_rows "$work/long-unsharded/sweep.csv" "$work/long/sweep.csv"

echo "== 3. a task whose sweep.csv is truncated is refused, naming the file"
truncate -s -9 "$csv"
requeue_task "${array}_2" "$work/long/logs/shard-2.out"
[ "$(state "${array}_2")" = FAILED ] || fail "the task with a truncated sweep.csv ended $(state "${array}_2")"
grep -F "$csv" "$work/long/logs/shard-2.out" || fail "the error does not name $csv: $(cat "$work/long/logs/shard-2.out")"

echo "== 4. the benchmark as an array job, then the merge"
sharded_as_unsharded benchmark 2 bench leaderboard.csv --scenarios default,noisy_camera \
    --learners scasm,batch-ml --seeds 0..3 --set trial.duration=12 --cache "$cache"
echo "the Slurm check passed"
