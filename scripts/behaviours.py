#!/usr/bin/env python3
"""How fast and how far each run's learner gets with its behaviour: for each
`train` run directory, from its trials' errors_over_time.csv (the models
judged every 5 s), the first time after which the means over the ok trials
of all three figures stay at the paper's level (action at most 4.9 % of the
measured range, sensor at most 2.9 %, consistency at most 0.08), the
median over trials of each trial's own such time, and the mean errors at
45 s, 90 s and the trial's end. Prints a Markdown table.

    python3 scripts/behaviours.py RUN_DIR [RUN_DIR ...]
"""
import csv
import json
import math
import pathlib
import statistics
import sys

PAPER = {"action": 0.049, "sensor": 0.029, "consistency": 0.08}


def setting(config, key):
    section, name = key.split(".", 1)
    head = f"[{section}]"
    inside = False
    for line in config.splitlines():
        line = line.strip()
        if line.startswith("["):
            inside = line == head
        elif inside and line.split("=", 1)[0].strip() == name:
            return line.split("=", 1)[1].strip().strip('"')
    return "?"


def ranges(run):
    with open(run / "measured_action.csv") as f:
        v = [float(r["velocity_mm_s"]) for r in csv.DictReader(f)]
    with open(run / "measured_sensor.csv") as f:
        d = [float(r["distance_mm"]) for r in csv.DictReader(f)]
    return max(v) - min(v), max(d) - min(d)


def number(text):
    return float(text) if text not in ("", None) else math.nan


def at_level(row, action_range, sensor_range):
    a, s, c = row
    return (a <= PAPER["action"] * action_range and s <= PAPER["sensor"] * sensor_range
            and c <= PAPER["consistency"])


def first_stay(times, rows, action_range, sensor_range):
    """The first time from which every later row is at the paper's level."""
    found = None
    for t, row in zip(times, rows):
        if at_level(row, action_range, sensor_range):
            found = t if found is None else found
        else:
            found = None
    return found


def run_row(run):
    config = (run / "config.toml").read_text()
    summary = json.loads((run / "summary.json").read_text())
    action_range, sensor_range = ranges(run)
    ok = [t["seed"] for t in summary["trials"] if t.get("status") == "ok"]
    series = {}
    for seed in ok:
        with open(run / f"trial-{seed}" / "errors_over_time.csv") as f:
            rows = list(csv.DictReader(f))
        series[seed] = [(float(r["t"]), (number(r["action_rmse_mm_s"]), number(r["sensor_rmse_mm"]),
                                          number(r["consistency"]))) for r in rows]
    times = [t for t, _ in next(iter(series.values()))]
    means = []
    for k in range(len(times)):
        rows = [series[s][k][1] for s in ok]
        means.append(tuple(statistics.fmean(r[i] for r in rows) if all(not math.isnan(r[i]) for r in rows)
                           else math.inf for i in range(3)))
    own = [first_stay([t for t, _ in series[s]], [r for _, r in series[s]], action_range, sensor_range)
           for s in ok]
    reached = [t for t in own if t is not None]

    def at(t):
        k = min(range(len(times)), key=lambda i: abs(times[i] - t))
        a, s, c = means[k]
        if math.isinf(a) or math.isinf(c):
            have = sum(1 for seed in ok if not math.isnan(series[seed][k][1][0]))
            return f"{have} of {len(ok)} have models"
        return f"{100 * a / action_range:.1f} %, {100 * s / sensor_range:.1f} %, {c:.3f}"

    ratios = summary.get("floor_ratios", {})
    ratio = lambda key: ratios.get(key, {}).get("rms") if isinstance(ratios.get(key), dict) else None
    fmt = lambda v: f"{v:.2f}x" if isinstance(v, (int, float)) else "-"
    mean_time = first_stay(times, means, action_range, sensor_range)
    seconds = lambda t: f"{t:.0f} s" if t is not None else "never"
    return (f"| {setting(config, 'learner.name')} | {setting(config, 'behaviour.name')} | {len(ok)} "
            f"| {seconds(mean_time)} "
            f"| {seconds(statistics.median(reached)) if len(reached) == len(own) else 'not all'} "
            f"({len(reached)} of {len(own)}) | {at(45)} | {at(90)} | {at(times[-1])} "
            f"| {fmt(ratio('action'))} / {fmt(ratio('sensor'))} |")


def main():
    runs = [pathlib.Path(p) for p in sys.argv[1:]]
    if not runs:
        sys.exit(__doc__)
    print("| learner | behaviour | trials ok | paper level from (means) | median trial's time "
          "(trials that reach it) | at 45 s: action, sensor (% of range), consistency | at 90 s "
          "| at the end | floor ratio, RMS: action / sensor |")
    print("|---|---|---|---|---|---|---|---|---|")
    for run in runs:
        print(run_row(run))


if __name__ == "__main__":
    main()
