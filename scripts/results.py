#!/usr/bin/env python3
"""The book's results pages, generated from result files kept in the repository.

    python3 scripts/results.py collect runs/eval   # keep an evaluate.sh run's results (book/src/results/data/)
    python3 scripts/results.py                     # write book/src/results/index.md from them
    python3 scripts/results.py --check             # fail if the page differs from what the data give

`collect` keeps, of each summary.json of the run (train and each replay), what the tables
need (the learner, the statistics over the trials, the counts), and of the benchmark its
leaderboard.md, each stamped with the commit, seeds and command that made it (from the run's
config.toml). Regenerating every figure is one command:

    bash scripts/evaluate.sh && python3 scripts/results.py collect runs/eval && python3 scripts/results.py
"""

import json
import math
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.path.join(ROOT, "book", "src", "results", "data")
PAGE = os.path.join(ROOT, "book", "src", "results", "index.md")
KEEP = ("learner", "learner_parameters", "mean", "std", "median", "p10", "p90", "n", "trials_ok",
        "trials_failed", "trials_worse_than_start", "trials_worse_than_start_seeds", "floor_ratios")


def quantile(sorted_values, q):
    """As `testbed::summary::quantile`: linear between the closest ranks."""
    if not sorted_values:
        return float("nan")
    h = (len(sorted_values) - 1) * q
    lo = int(h)
    if lo + 1 < len(sorted_values):
        return sorted_values[lo] + (h - lo) * (sorted_values[lo + 1] - sorted_values[lo])
    return sorted_values[lo]


def floor_ratio(trials, error, floor):
    """As `testbed::summary::FloorRatio::of`, over the ok trials' figures (for a
    summary.json written before summary.json carried `floor_ratios`)."""
    pairs = [(t[error], t[floor]) for t in trials if t.get("status") == "ok"
             and isinstance(t.get(error), (int, float)) and isinstance(t.get(floor), (int, float))
             and math.isfinite(t[error]) and math.isfinite(t[floor]) and t[floor] > 0]
    if not pairs:
        return {"floor_rms": None, "rms": None, "median": None, "p90": None, "n": 0}
    n = len(pairs)
    floor_rms = math.sqrt(sum(f * f for _, f in pairs) / n)
    each = sorted(e / f for e, f in pairs)
    return {"floor_rms": floor_rms, "rms": math.sqrt(sum(e * e for e, _ in pairs) / n) / floor_rms,
            "median": quantile(each, 0.5), "p90": quantile(each, 0.9), "n": n}
ORDER = ["scasm-paper", "scasm", "scasm-eiv", "batch-ml", "batch-ml-lag"]


def stamp(run_dir):
    """Commit, dirty flag, seeds and command of a run, from its config.toml's header and keys."""
    text = open(os.path.join(run_dir, "config.toml")).read()
    commit = re.search(r"commit ([0-9a-f]+)", text)
    command = re.search(r"^# Command: (.*)$", text, re.M)
    seeds = re.search(r'^seeds = "([^"]+)"', text, re.M)
    # A flag given on the command line beats the file's setting.
    flag = re.search(r"--seeds (\S+)", command.group(1)) if command else None
    if flag:
        seeds = flag
    return {
        "commit": commit.group(1) if commit else "unknown",
        "uncommitted_changes": "uncommitted" in text.split("\n\n")[0],
        "seeds": seeds.group(1) if seeds else "unknown",
        "command": command.group(1).strip() if command else "unknown",
    }


def collect(run):
    os.makedirs(DATA, exist_ok=True)
    # A train's or a replay's folder (the benchmark's, which has a summary.json too, is kept below).
    dirs = [d for d in sorted(os.listdir(run))
            if all(os.path.exists(os.path.join(run, d, f)) for f in ("summary.json", "config.toml"))]
    for d in dirs:
        summary = json.load(open(os.path.join(run, d, "summary.json")))
        kept = {k: summary[k] for k in KEEP if k in summary}
        if "floor_ratios" not in kept and "trials" in summary:
            kept["floor_ratios"] = {
                "action": floor_ratio(summary["trials"], "action_rmse_mm_s", "action_crb_rmse_mm_s"),
                "sensor": floor_ratio(summary["trials"], "sensor_rmse_mm", "sensor_crb_rmse_mm")}
        kept["made_by"] = stamp(os.path.join(run, d))
        name = summary["learner"]
        with open(os.path.join(DATA, f"eval-{name}.json"), "w") as f:
            json.dump(kept, f, indent=1, sort_keys=True)
            f.write("\n")
    board = os.path.join(run, "benchmark", "leaderboard.md")
    if os.path.exists(board):
        made = stamp(os.path.join(run, "benchmark", "config-default"))
        with open(os.path.join(DATA, "eval-benchmark.md"), "w") as f:
            f.write(f"<!-- made_by: {json.dumps(made, sort_keys=True)} -->\n")
            f.write(open(board).read())
    print(f"kept {len(dirs)} summaries and the benchmark's leaderboard in {os.path.relpath(DATA, ROOT)}")


def by_floor(summary, model):
    """The error over the floor by RMS over the trials (median, p90 of the
    per-trial ratios); by means where a kept summary has no `floor_ratios`."""
    r = summary.get("floor_ratios", {}).get(model)
    if r and r.get("n"):
        return f"{r['rms']:.2f}x ({r['median']:.2f}x, {r['p90']:.2f}x)"
    m = summary["mean"]
    key = ("action_rmse_mm_s", "action_crb_rmse_mm_s") if model == "action" else ("sensor_rmse_mm", "sensor_crb_rmse_mm")
    return f"{m[key[0]] / m[key[1]]:.2f}x (by means)"


def by_likelihood(summary, model):
    """The error over the likelihood's floor by RMS over the trials; "-" where a
    kept summary was written before the likelihood's floor was."""
    r = summary.get("floor_ratios", {}).get(f"{model}_likelihood")
    return f"{r['rms']:.2f}x" if r and r.get("n") else "-"


def f1(x):
    return "-" if x is None else f"{x:.1f}"


def page():
    rows, stamps = [], []
    for name in ORDER:
        p = os.path.join(DATA, f"eval-{name}.json")
        if not os.path.exists(p):
            continue
        s = json.load(open(p))
        m, sd, md, p10, p90 = (s[k] for k in ("mean", "std", "median", "p10", "p90"))
        ok = s["trials_ok"]
        worse = s["trials_worse_than_start"]
        seeds = s.get("trials_worse_than_start_seeds", [])
        by_action = sum(w["action_rmse_mm_s"] > w["action_a0_rmse_mm_s"] for w in seeds)
        by_sensor = sum(w["sensor_rmse_mm"] > w["sensor_start_rmse_mm"] for w in seeds)
        rows.append(
            f"| `{name}` | {f1(m['action_rmse_mm_s'])} +- {f1(sd['action_rmse_mm_s'])} | "
            f"{f1(md['action_rmse_mm_s'])} [{f1(p10['action_rmse_mm_s'])}, {f1(p90['action_rmse_mm_s'])}] | "
            f"{m['action_rmse_mm_s'] / m['action_best_rmse_mm_s']:.2f}x; "
            f"{by_floor(s, 'action')}; {by_likelihood(s, 'action')} | "
            f"{f1(m['sensor_rmse_mm'])} +- {f1(sd['sensor_rmse_mm'])} | "
            f"{f1(md['sensor_rmse_mm'])} [{f1(p10['sensor_rmse_mm'])}, {f1(p90['sensor_rmse_mm'])}] | "
            f"{m['sensor_rmse_mm'] / m['sensor_best_rmse_mm']:.2f}x; "
            f"{by_floor(s, 'sensor')}; {by_likelihood(s, 'sensor')} | "
            f"{m['consistency']:.3f} | {worse} of {ok} ({by_action}, {by_sensor}) |")
        stamps.append((name, s["made_by"]))
        best = m
    out = ["# Headline results", "",
           "<!-- generated by scripts/results.py from book/src/results/data/: do not edit -->", "",
           "## The evaluation set", "",
           "Seeds 1000-1049: 50 trials of 150 s in the default world, on which no setting, default "
           "or learner has been chosen (they are chosen on development seeds, 100-999). `scasm` runs "
           "live (`train`); every other learner is replayed the same 50 recorded worlds. \"/ best\" is "
           "the mean error over the mean best polynomial of the learner's degree through the measured "
           "model; \"/ floor\" the error over the information floor (the metric's floor) by root "
           "mean square over the trials, with the median and 90th percentile of the per-trial ratios "
           "in brackets (the floor bounds a mean square), and \"/ likelihood\" over the likelihood's "
           "floor, where maximum likelihood of the floor's model lands, by RMS (see "
           "[the information floor](../design/information-floor.md)).", "",
           "| learner | action mm/s: mean +- std | median [p10, p90] | / best; / floor; / likelihood | "
           "sensor mm: mean +- std | median [p10, p90] | / best; / floor; / likelihood | consistency | "
           "worse than start (action, sensor) |",
           "|---|---|---|---|---|---|---|---|---|", *rows, ""]
    if rows:
        out += [f"The best quartic through the measured action model is {best['action_best_rmse_mm_s']:.1f} mm/s, "
                f"the best cubic through the sensor model {best['sensor_best_rmse_mm']:.1f} mm, A0 "
                f"{best['action_a0_rmse_mm_s']:.1f} mm/s; the information floor's mean is "
                f"{best['action_crb_rmse_mm_s']:.1f} mm/s and {best['sensor_crb_rmse_mm']:.1f} mm"
                + (f", the likelihood's floor's {best['action_likelihood_floor_mm_s']:.1f} mm/s and "
                   f"{best['sensor_likelihood_floor_mm']:.1f} mm" if "action_likelihood_floor_mm_s" in best else "")
                + ". "
                "The benchmark's table below is its leaderboard as that run wrote it.", ""]
    out += ["Made by (each table's run):", ""]
    for name, st in stamps:
        dirty = " (with uncommitted changes)" if st["uncommitted_changes"] else ""
        out.append(f"- `{name}`: commit `{st['commit']}`{dirty}, seeds {st['seeds']}, `{st['command']}`")
    bench = os.path.join(DATA, "eval-benchmark.md")
    if os.path.exists(bench):
        text = open(bench).read()
        made = json.loads(re.match(r"<!-- made_by: (.*) -->", text).group(1))
        out += ["", "## The benchmark: every learner on every scenario", "",
                f"The suite's six scenarios (`assets/scenarios/suite/`), seeds {made['seeds']}: "
                f"commit `{made['commit']}`, `{made['command']}`. The `default` rows are the same trials "
                "as the table above. Its leaderboard, as the benchmark wrote it:", "",
                text.split("\n", 1)[1].strip(), ""]
    out += ["## Regenerating", "",
            "Every figure on this page, from scratch (about 5 min on 2 cores):", "",
            "<!-- check: skip the evaluation set is run once, when figures are published -->",
            "```sh", "bash scripts/evaluate.sh && python3 scripts/results.py collect runs/eval && "
            "python3 scripts/results.py", "```", ""]
    return "\n".join(out)


def main():
    args = sys.argv[1:]
    if args[:1] == ["collect"]:
        collect(args[1] if len(args) > 1 else os.path.join(ROOT, "runs", "eval"))
        return 0
    text = page()
    if "--check" in args:
        if open(PAGE).read() != text:
            print("results: book/src/results/index.md differs from what its data give: "
                  "run `python3 scripts/results.py` and commit it")
            return 1
        print("results: the page is what its data give")
        return 0
    os.makedirs(os.path.dirname(PAGE), exist_ok=True)
    open(PAGE, "w").write(text)
    print(f"wrote {os.path.relpath(PAGE, ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
