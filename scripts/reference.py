#!/usr/bin/env python3
"""The book's reference pages, generated from the code: book/src/reference/{settings,learners,
flags,outputs}.md.

    python3 scripts/reference.py           # write the pages
    python3 scripts/reference.py --check   # fail where a committed page differs from what the code generates now

- settings.md and learners.md: the settings table and the learners' declarations
  (`cargo run --example reference -- settings|learners`);
- flags.md: every binary's flags, from clap (`BINARY --help-markdown`);
- outputs.md: every file a short train, replay, benchmark and sweep write, with each CSV's
  columns and each JSON file's keys as the programs wrote them now. Each file and column is
  described below (FILES, COLUMNS) or, for a per-trial figure, by its doc comment in the code
  (`testbed::summary::Figures`). A file or column written with no description, or described and
  no longer written, is an error: the page cannot drift from what the programs write.
"""

import csv
import difflib
import json
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PAGES = os.path.join(ROOT, "book", "src", "reference")
EXAMPLES = os.path.join(ROOT, "target", "release", "examples")
# Every binary whose flags are listed, in the order of the page. `view` is built only with the
# `rerun` feature (`cargo run --features rerun --example view -- --help`), so it is not here.
BINARIES = ["train", "replay", "benchmark", "sweep", "measure_action", "measure_sensor",
            "learner_check", "fingerprint", "peer_trace", "reference"]
DURATION = "60"  # s: long enough that every learner has models (SCASM starts at 30 s)

# What each file is. `trial-<seed>/` stands for every trial's folder.
FILES = {
    "train/config.toml": "every setting of the run, headed by the version, the git commit (and whether "
                         "the tree had uncommitted changes) and the command line: `train --config` it to run it again",
    "train/summary.json": "per trial figures and status, and their mean, std, median, p10, p90 and n over the ok trials; "
                          "`floor_ratios`: each model's information floor by root mean square over the trials, the error "
                          "over it by RMS, and the per-trial ratios' median and p90",
    "train/index.html": "the figures beside the results table: open it in a browser",
    "train/measured_action.csv": "the action model the stopwatch measured (the reference)",
    "train/measured_sensor.csv": "the sensor model measured by standing at marked distances (the reference)",
    "train/fig*.png": "the paper's figures 2a, 2b, 3, 6, 7a, 7b and 8 from this run's data (each also as .svg)",
    "train/localisation.png": "the localiser's estimates over the typical trial (also .svg)",
    "train/demos/*.csv": "traces of the section IV and V demonstrations (Figs. 2a, 2b, 3)",
    "train/demos/*.json": "the demonstrations' models",
    "train/trial-<seed>/events.csv": "what the learner saw: a dataset's events (with truth.csv and dataset.json, "
                                     "the recorded world that `replay` reads)",
    "train/trial-<seed>/truth.csv": "the ground truth, kept apart from what the learner saw",
    "train/trial-<seed>/dataset.json": "the dataset's robot, every setting, seed, format version, reference models and provenance",
    "train/trial-<seed>/trace.csv": "the learner and the localisers, one row a frame",
    "train/trial-<seed>/errors_over_time.csv": "both errors every 5 s (Fig. 8)",
    "train/trial-<seed>/models.json": "the final models: raw-unit coefficients, lowest power first",
    "failed/trial-<seed>/failure.json": "written in place of the learner's trace and models when a trial "
                                        "fails: its status, the reason, and the frame and time (s) it failed at "
                                        "where known (a `train` whose learner program crashed, here)",
    "failed/trial-<seed>/learner_stderr.txt": "everything a learner program wrote to its stderr during the trial "
                                              "(up to 4 MiB), whether the trial ended ok or not",
    "replay/config.toml": "as train's",
    "replay/summary.json": "as train's",
    "replay/trial-<seed>/trace.csv": "as train's",
    "replay/trial-<seed>/errors_over_time.csv": "as train's",
    "replay/trial-<seed>/models.json": "as train's",
    "benchmark/leaderboard.csv": "a row per learner, scenario and seed",
    "benchmark/summary.json": "the seeds and scenarios; each learner as named (`spec`: a program's command too) "
                              "with the settings it ran with on each scenario; and per learner and scenario "
                              "(`cells[]`) the trial counts and every figure's mean, std, median, p10, p90 and n",
    "benchmark/leaderboard.md": "the leaderboard's table per learner and scenario, as Markdown",
    "benchmark/index.html": "the table and the figures of the ratios",
    "benchmark/leaderboard-*.png": "each learner's median error over the best polynomial's and its p10-p90, per scenario (also .svg)",
    "benchmark/config-<scenario>/config.toml": "each scenario's settings, as train's config.toml",
    "sweep/config.toml": "the sweep's base settings, axes and seeds",
    "sweep/sweep.csv": "a row per combination of the axes and seed",
    "sweep/sweep_summary.csv": "a row per combination: each figure's mean, std, median, p10, p90 and n over the seeds",
}

# The columns that are not per-trial figures.
COLUMNS = {
    "measured_action.csv": {
        "command": "the walk command", "velocity_mm_s": "the mean of the stopwatch's timings, mm/s",
        "std_mm_s": "their standard deviation", "min_mm_s": "the slowest timing", "max_mm_s": "the fastest timing",
        "upright": "1 if the robot stayed upright", "blew_up": "1 if the physics blew up",
    },
    "measured_sensor.csv": {
        "distance_mm": "the distance held (ground truth, averaged over the readings)",
        "obs_px": "the readings' mean, px", "std_px": "their standard deviation, px",
        "nominal_mm": "the marked distance", "distance_std_mm": "how far the held distance wandered",
        "missed": "frames with no reading",
    },
    "events.csv": {
        "t_s": "the start of the command's frame, s", "dt_s": "the frame's length, s",
        "command": "the walk command in force", "obs_px": "the reading at the frame's end, px (empty: no reading)",
    },
    "truth.csv": {
        "t_s": "time, s", "x_true_mm": "the true distance to the beacon along the line, mm",
        "lateral_mm": "the distance off the line, mm", "yaw_rad": "the heading off the line, rad",
        "upright": "1 while the robot is upright", "blew_up": "1 if the physics blew up",
    },
    "trace.csv": {
        "t": "time, s", "command": "the walk command", "obs": "the reading, px (empty: none)",
        "x_true_mm": "the true distance, mm", "x_a": "the learner's location by dead reckoning (its units)",
        "x_s": "the learner's location from its sensor model (its units)",
        "x_loc": "the localiser's estimate with the learned models", "x_loc_std": "its standard deviation",
        "x_loc_true_mm": "the localiser with the measured (true) models, mm",
        "x_loc_a0": "the localiser with A0 and its section IV sensor model",
        "x_loc_best_mm": "the localiser with the best polynomials of the learner's degrees, mm",
        "falling_back": "1 while the learner reports older models (its check on itself), 0 while its own, "
                        "empty for a learner with no check",
    },
    "errors_over_time.csv": {
        "t": "time, s", "action_rmse_mm_s": "the action model's error then (empty: no model yet)",
        "sensor_rmse_mm": "the sensor model's error then", "consistency": "the consistency then",
    },
    "leaderboard.csv": {
        "learner": "the learner's name", "scenario": "the suite's scenario", "seed": "the trial's seed",
        "worse_than_start": "true if the trial ended worse than its uncalibrated start",
        "worse_than_start_action": "true if its action model ended worse than A0",
        "worse_than_start_sensor": "true if its sensor model ended worse than the start's",
        "status": "ok, or why the trial failed",
    },
    "sweep.csv": {"seed": "the trial's seed", "status": "ok, or why the trial failed"},
    "sweep_summary.csv": {
        "runs_ok": "trials ok", "runs_failed": "trials failed",
        "runs_worse_than_start": "ok trials that ended worse than their start",
        "runs_worse_than_start_action": "of those, the trials whose action model ended worse than A0",
        "runs_worse_than_start_sensor": "of those, the trials whose sensor model ended worse than the start's",
    },
}
STATS = ("mean", "std", "median", "p10", "p90", "n")


def run(args, may_fail=False):
    r = subprocess.run(args, cwd=ROOT, capture_output=True, text=True)
    if r.returncode != 0 and not may_fail:
        sys.exit(f"reference: `{' '.join(args)}` exited with {r.returncode}:\n{r.stderr[-3000:]}")
    return r.stdout


def example(name, *args, may_fail=False):
    return run([os.path.join(EXAMPLES, name), *args], may_fail)


def figure_docs():
    out = {}
    for line in example("reference", "figures").strip().split("\n"):
        name, doc = line.split("\t", 1)
        # rustdoc's links as code, and a table cell's bars escaped
        doc = re.sub(r"\[`([^`]+)`\](\([^)]*\))?", r"`\1`", doc)
        out[name] = doc.replace("|", "\\|")
    return out


def json_keys(value, prefix="", depth=0):
    """`key: type` lines of a JSON value, objects opened up to three levels."""
    def kind(v):
        if isinstance(v, dict):
            return "object"
        if isinstance(v, list):
            inner = {kind(x) for x in v}
            return "list" + (f" of {inner.pop()}s" if len(inner) == 1 else "")
        return {bool: "boolean", int: "number", float: "number", str: "string", type(None): "null"}[type(v)]

    lines = []
    if isinstance(value, dict):
        for k in value:
            v = value[k]
            lines.append(f"`{prefix}{k}`: {kind(v)}")
            if depth < 2 and isinstance(v, dict) and k not in STAT_OBJECTS:
                lines += json_keys(v, f"{prefix}{k}.", depth + 1)
            if depth < 2 and isinstance(v, list) and v and isinstance(v[0], dict):
                lines += json_keys(v[0], f"{prefix}{k}[].", depth + 1)
    return lines


STAT_OBJECTS = set(STATS) | {"paper"}


def produce(tmp):
    cache = os.path.join(ROOT, "runs", ".cache")
    d = lambda name: os.path.join(tmp, name)  # noqa: E731
    example("train", "--trials", "2", "--duration", DURATION, "--out", d("train"), "--cache", cache)
    example("replay", d("train"), "--learner", "batch-ml", "--out", d("replay"))
    # A learner program whose trial fails: what a failed trial keeps.
    example("train", "--learner", "exec:python3 tests/fixtures/learners/bad.py crash", "--trials", "1",
            "--duration", "20", "--out", d("failed"), "--cache", cache, may_fail=True)
    example("benchmark", "--learners", "scasm", "--scenarios", "default", "--seeds", "0..2",
            "--set", f"trial.duration={DURATION}", "--out", d("benchmark"), "--cache", cache)
    example("sweep", "--gamma", "0.99,0.999", "--seeds", "0..2", "--set", f"trial.duration={DURATION}",
            "--out", d("sweep"), "--cache", cache)


def pattern(rel):
    rel = re.sub(r"trial-\d+", "trial-<seed>", rel)
    rel = re.sub(r"config-[a-z_]+/", "config-<scenario>/", rel)
    rel = re.sub(r"/fig\w+\.png$", "/fig*.png", rel)
    rel = re.sub(r"/demos/\w+\.(csv|json)$", r"/demos/*.\1", rel)
    rel = re.sub(r"/leaderboard-\w+\.png$", "/leaderboard-*.png", rel)
    return rel


def outputs_page():
    figures = figure_docs()
    errors, seen, sections = [], {}, []
    with tempfile.TemporaryDirectory(prefix="reference-") as tmp:
        produce(tmp)
        for dirpath, _, files in sorted(os.walk(tmp)):
            for f in sorted(files):
                full = os.path.join(dirpath, f)
                rel = os.path.relpath(full, tmp)
                if rel.endswith(".svg"):
                    continue  # each figure's .svg beside its .png
                seen.setdefault(pattern(rel), full)
        for name in FILES:
            if name not in seen:
                errors.append(f"{name} is described but no program wrote it")
        for name, full in seen.items():
            if name.startswith("failed/") and name not in FILES:
                continue  # the failed run's other files are train's
            if name not in FILES:
                errors.append(f"{name} was written but is not described in scripts/reference.py's FILES")
                continue
            lines = [f"### `{name}`", "", FILES[name] + ".", ""]
            base = os.path.basename(name)
            if name.endswith(".csv") and "/demos/" not in name:
                header = next(csv.reader(open(full, newline="")))
                own = COLUMNS.get(base, {})
                lines += ["| column | meaning |", "|---|---|"]
                for col in header:
                    doc = own.get(col) or figures.get(col)
                    stat = col.rsplit("_", 1)
                    if doc is None and len(stat) == 2 and stat[1] in STATS and stat[0] in figures:
                        doc = f"the {stat[1]} over the seeds of `{stat[0]}`"
                    if doc is None and col.startswith("learner.") or col in ("learner.gamma",):
                        doc = "the sweep's axis: the setting's value"
                    if doc is None:
                        errors.append(f"{name}: column {col} has no description")
                        doc = "?"
                    lines.append(f"| `{col}` | {doc} |")
                for col in own:
                    if col not in header:
                        errors.append(f"{name}: column {col} is described but not written")
                lines.append("")
            elif name.endswith(".json") and "/demos/" not in name:
                lines += ["Keys (as written by a short run; a figure that does not apply may be absent):", ""]
                lines += [f"- {k}" for k in json_keys(json.load(open(full)))]
                lines.append("")
            sections.append("\n".join(lines))
    fig = ["## The per-trial figures", "",
           "Each trial's figures, as `summary.json`'s `trials[]`, `leaderboard.csv`, `sweep.csv` and "
           "the statistics' objects name them (from their doc comments in `testbed::summary::Figures`):", "",
           "| figure | meaning |", "|---|---|"]
    fig += [f"| `{k}` | {v} |" for k, v in figures.items()]
    head = ["# Output files", "",
            "<!-- generated by scripts/reference.py from what the programs write: do not edit -->", "",
            "Every file that `train`, `replay`, `benchmark` and `sweep` write into their run directory "
            f"(written here by a short run of each: 2 trials of {DURATION} s), with each CSV's columns "
            "and each JSON file's keys. A `.png` figure has an `.svg` beside it. CSV files are "
            "RFC 4180, as the `csv` crate writes them: a cell holding a comma, a quote or a line "
            "break (a failed trial's status, say) is quoted; an empty cell is a value there is not.", "",
            "## Files", ""]
    return "\n".join(head) + "\n" + "\n".join(sections) + "\n" + "\n".join(fig) + "\n", errors


def pages():
    flags = ["# Command-line flags", "",
             "<!-- generated by scripts/reference.py from each binary's clap declaration: do not edit -->", "",
             "Every binary is an example of the root package: `cargo run --release --example NAME -- FLAGS`, "
             "or `target/release/examples/NAME FLAGS` once built. Each takes `--help`, and `--version` "
             "(the version and the commit it was built from). A flag marked with a setting's key "
             "in brackets sets that setting, and overrides the scenario file and `--set`. `view` is built "
             "only with the `rerun` feature: `cargo run --features rerun --example view -- --help`.", "",
             "The same commands are the subcommands of one binary, `scasm-testbed` (`cargo install --path .`, "
             "or `cargo run --release --bin scasm-testbed --`), with the same flags; an example's name "
             "with `-` for `_` (`measure-action`), and `peer` for `peer_trace`:", "",
             "```text", run([os.path.join(ROOT, "target", "release", "scasm-testbed"), "--help"]).split("\n", 2)[2].rstrip(),
             "```", ""]
    for b in BINARIES:
        flags.append(example(b, "--help-markdown"))
    settings = ["# Settings", "",
                "<!-- generated by scripts/reference.py from the settings table (testbed::scenario): do not edit -->", "",
                "Every setting, as `--set key=value`, a scenario file's `[section] key = value`, or a sweep's "
                "`--axis key=values`; `--set list` prints the same table. A value outside its range is refused, "
                "naming the key, the value and the range. Defaults are the ERS-7's (a robot file scales "
                "the trial's length and the learner's time constants with the robot).", "",
                example("reference", "settings")]
    learners = ["# Learners and their settings", "",
                "<!-- generated by scripts/reference.py from the learners' declarations: do not edit -->", "",
                "Every built-in learner (`--learner list` prints the same), with the shared settings it reads "
                "(at their defaults) and its own, set as `learner.<name>.<key>`.", "",
                example("reference", "learners")]
    outputs, errors = outputs_page()
    return {
        "settings.md": "\n".join(settings).rstrip() + "\n",
        "learners.md": "\n".join(learners).rstrip() + "\n",
        "flags.md": "\n".join(flags).rstrip() + "\n",
        "outputs.md": outputs,
    }, errors


def main():
    check = "--check" in sys.argv[1:]
    run(["cargo", "build", "--release", "--quiet", "--examples", "--bins"])
    generated, errors = pages()
    for e in errors:
        print(f"reference: {e}")
    differ = []
    for name, text in generated.items():
        path = os.path.join(PAGES, name)
        if check:
            old = open(path).read() if os.path.exists(path) else ""
            if old != text:
                differ.append(name)
                sys.stdout.writelines(difflib.unified_diff(
                    old.splitlines(True), text.splitlines(True), f"committed {name}", f"generated {name}", n=1))
        else:
            os.makedirs(PAGES, exist_ok=True)
            open(path, "w").write(text)
    if differ:
        print(f"\nreference: {', '.join(differ)} differ from what the code generates now: "
              "run `python3 scripts/reference.py` and commit the pages")
    if errors or differ:
        return 1
    print("reference: " + ("the pages are what the code generates" if check else f"wrote {len(generated)} pages"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
