#!/usr/bin/env bash
# How trials spread over cores: the default `train` (15 trials, seeds 0-14)
# with 1, 2, 4 and 8 worker threads (RAYON_NUM_THREADS), the trials' wall
# time of each (train's "N trials in S s wall" line; the reference models
# are measured once, before, and read from the cache after) and the speed-up
# over one thread. Threads beyond the machine's cores share them.
#
#   bash scripts/thread_scaling.sh [OUT_DIR]     (default target/thread-scaling)
#
# Writes OUT_DIR/scaling.csv (threads, wall_s, speedup, cores) and prints it.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-target/thread-scaling}
mkdir -p "$out"
cargo build --release --example train --quiet
train=target/release/examples/train
cache="$out/cache"
# Measure the reference models once, so that every timed run reads them.
"$train" --out "$out/warm" --cache "$cache" > /dev/null 2>&1 || true
cores=$(nproc)
echo "threads,wall_s,speedup,cores" > "$out/scaling.csv"
one=
for t in 1 2 4 8; do
    line=$(RAYON_NUM_THREADS=$t "$train" --out "$out/t$t" --cache "$cache" | grep -E '^  [0-9]+ trials in ')
    wall=$(echo "$line" | awk '{print $4}')
    one=${one:-$wall}
    speedup=$(awk -v a="$one" -v b="$wall" 'BEGIN{printf "%.2f", a/b}')
    echo "$t,$wall,$speedup,$cores" >> "$out/scaling.csv"
done
column -s, -t < "$out/scaling.csv"
echo "commit $(git rev-parse --short HEAD 2>/dev/null || echo unknown); $out/scaling.csv"
