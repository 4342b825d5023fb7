#!/usr/bin/env bash
# The evaluation set, run once when figures are published (README, "Figures
# that hold"): seeds 1000-1049, never looked at while choosing a setting, a
# default or a learner change. Writes runs/eval/{train,replay-*,benchmark}.
#
#   bash scripts/evaluate.sh          # about 3 min on the 2-core machine (8 min with rapier's own dynamics)
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-runs/eval}
seeds=1000..1050
cargo build --release --examples
run() { echo "+ $*"; "$@"; }
mkdir -p "$out"
# The default learner live, every other learner on the same recordings.
run target/release/examples/train --seeds "$seeds" --out "$out/train" | tee "$out/train.log"
for learner in scasm-paper scasm-eiv batch-ml batch-ml-lag; do
    run target/release/examples/replay "$out/train" --learner "$learner" --out "$out/replay-$learner" \
        | tee "$out/replay-$learner.log"
done
# Every learner on every scenario of the suite.
run target/release/examples/benchmark --seeds "$seeds" --out "$out/benchmark" | tee "$out/benchmark.log"
