#!/usr/bin/env python3
"""Run every command and code block the book and the README show.

Usage: python3 scripts/doc_check.py [FILE.md ...]   (default: README.md and book/src/**/*.md)

Every fenced block whose language can be run is run, or skipped with a stated reason:

- ``sh``: each command (a line, with ``\\`` continuations) runs in bash from the repository's
  root, in order, so that a page's commands may build on each other. Commands run as written,
  but for two cuts: a command that runs trials (``train``, ``benchmark``, ``sweep``, ``view``)
  gets ``--set trial.duration=<DOC_CHECK_DURATION>`` (default 60 s) appended, and ``cargo
  bench`` gets ``-- --test`` (each benchmark run once, as a test);
- ``python``, ``js``/``javascript``, ``c`` after ``<!-- check: learner -->``: the block (or the
  file it ``{{#include}}``s) is a learner program; it runs a short ``train`` trial, which must
  end ok (``trials_ok`` 1 in its summary.json);
- ``toml`` after ``<!-- check: scenario -->``: a scenario file; a one-trial ``train`` runs it;
- ``toml`` after ``<!-- check: robot DIR -->``: a robot file as it would stand in DIR (its URDF
  is named relative to it); a one-trial ``train`` of that robot runs;
- ``rust``: compiled and run by ``mdbook test`` (not here);
- a ``sh`` block after ``<!-- check: full REASON -->`` runs as written, with no cut (a scenario
  whose world changes late in a long trial, say);
- any block after ``<!-- check: skip REASON -->`` is skipped, and the reason printed.

A runnable block with neither a check nor a reason is an error: nothing is left unchecked
silently. Every relative link must name a file that exists. A failing block or link is reported
with its file and line. Exits 1 if any failed.
"""

import json
import os
import shutil
import tomllib
import re
import shlex
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DURATION = os.environ.get("DOC_CHECK_DURATION", "60")
RUNNABLE = {"sh", "bash", "python", "js", "javascript", "c", "toml", "rust"}
TRIAL_COMMANDS = re.compile(r"(--example|examples/)\s*(train|benchmark|sweep|view)\b")
TRAIN = ["cargo", "run", "--release", "--quiet", "--example", "train", "--"]


def blocks(path):
    """(line, language, marker, text) of each fenced block of a Markdown file."""
    lines = open(path, encoding="utf-8").read().split("\n")
    out, i = [], 0
    while i < len(lines):
        m = re.match(r"^(\s*)(```+)(.*)$", lines[i])
        if not m:
            i += 1
            continue
        fence, info, start = m.group(2), m.group(3).strip(), i + 1
        lang = re.split(r"[ ,]", info)[0] if info else ""
        marker = ""
        j = i - 1
        while j >= 0 and not lines[j].strip():
            j -= 1
        if j >= 0:
            mk = re.match(r"^\s*<!--\s*check:\s*(.*?)\s*-->\s*$", lines[j])
            if mk:
                marker = mk.group(1)
        body = []
        i += 1
        while i < len(lines) and not lines[i].strip().startswith(fence):
            body.append(lines[i])
            i += 1
        i += 1
        out.append((start, lang, marker, "\n".join(body), info))
    return out


def include(text, md_path):
    """A block's text with mdBook's whole-file ``{{#include path}}`` resolved."""

    def read(m):
        p = os.path.normpath(os.path.join(os.path.dirname(md_path), m.group(1).strip()))
        return open(p, encoding="utf-8").read()

    return re.sub(r"\{\{#include\s+([^}:]+)\}\}", read, text)


def commands(text):
    """The commands of a shell block: continuation lines joined, comments and blanks dropped."""
    out, cur = [], ""
    for line in text.split("\n"):
        if line.rstrip().endswith("\\"):
            cur += line.rstrip()[:-1] + " "
            continue
        cur += line
        words = cur.strip()
        cur = ""
        if words and not words.startswith("#"):
            out.append(words)
    return out


def cut(cmd, full=False):
    """The command with a trial's duration cut (unless `full`), and benchmarks run once."""
    # A trailing comment is not part of the command.
    try:
        words = shlex.split(cmd, comments=True)
    except ValueError:
        return cmd
    cmd = shlex.join(words)
    if TRIAL_COMMANDS.search(cmd) and not full:
        extra = ["--set", f"trial.duration={DURATION}"]
        if "cargo" in words[:1] and "--" not in words:
            extra = ["--"] + extra
        cmd = shlex.join(words + extra)
    elif words[:2] == ["cargo", "bench"]:
        cmd = shlex.join(words + (["--test"] if "--" in words else ["--", "--test"]))
    return cmd


# Errors without backtraces; the learner package importable from anywhere.
ENV = dict(os.environ, RUST_BACKTRACE="0", PYTHONPATH=os.path.join(ROOT, "python"))


def run(cmd, what):
    r = subprocess.run(["bash", "-c", cmd], cwd=ROOT, capture_output=True, text=True, env=ENV)
    if r.returncode != 0:
        tail = "\n".join((r.stdout + r.stderr).strip().split("\n")[-15:])
        return f"{what}: `{cmd}` exited with {r.returncode}:\n{tail}"
    return None


def learner(path, line, lang, text, tmp):
    ext = {"python": "py", "js": "js", "javascript": "js", "c": "c"}[lang]
    src = os.path.join(tmp, f"learner_{line}.{ext}")
    open(src, "w", encoding="utf-8").write(text)
    if ext == "py":
        prog = f"python3 {src}"
    elif ext == "js":
        prog = f"node {src}"
    else:
        exe = src[:-2]
        err = run(f"cc -O2 -std=c99 -o {shlex.quote(exe)} {shlex.quote(src)} -lm", "compiling")
        if err:
            return err
        prog = exe
    out = os.path.join(tmp, f"run_{line}")
    cmd = shlex.join(TRAIN + ["--learner", f"exec:{prog}", "--trials", "1", "--duration", DURATION,
                              "--out", out])
    err = run(cmd, "the learner's trial")
    if err:
        return err
    summary = json.load(open(os.path.join(out, "summary.json")))
    if summary.get("trials_ok") != 1:
        return f"the learner's trial did not end ok: {summary.get('trials')}"
    return None


def robot(line, text, home, tmp):
    """A robot file as it would stand in `home`: written beside a copy of its URDF, then trained."""
    d = os.path.join(tmp, f"robot_{line}")
    os.makedirs(d, exist_ok=True)
    urdf = tomllib.loads(text).get("urdf")
    if urdf:
        shutil.copy(os.path.join(ROOT, home, urdf), os.path.join(d, os.path.basename(urdf)))
    f = os.path.join(d, "robot.toml")
    open(f, "w", encoding="utf-8").write(text)
    out = os.path.join(tmp, f"robot_run_{line}")
    return run(shlex.join(TRAIN + ["--robot", f, "--trials", "1", "--duration", DURATION, "--out", out]),
               "the robot file")


def scenario(line, text, tmp):
    f = os.path.join(tmp, f"scenario_{line}.toml")
    open(f, "w", encoding="utf-8").write(text)
    out = os.path.join(tmp, f"scenario_run_{line}")
    return run(shlex.join(TRAIN + ["--config", f, "--trials", "1", "--out", out]),
               "the scenario")


def broken_links(path):
    """(line, link) of each relative link in a Markdown file whose target does not exist."""
    out = []
    text = open(path, encoding="utf-8").read()
    for m in re.finditer(r"\]\(([^)#\s]+)(#[^)]*)?\)", text):
        link = m.group(1)
        if re.match(r"^[a-z]+:", link):
            continue
        if not os.path.exists(os.path.normpath(os.path.join(os.path.dirname(path), link))):
            out.append((text[: m.start()].count("\n") + 1, link))
    return out


def main():
    files = sys.argv[1:]
    if not files:
        files = [os.path.join(ROOT, "README.md")]
        for d, _, fs in sorted(os.walk(os.path.join(ROOT, "book", "src"))):
            files += [os.path.join(d, f) for f in sorted(fs) if f.endswith(".md")]
    ran = skipped = by_mdbook = 0
    failures = []
    with tempfile.TemporaryDirectory(prefix="doc-check-") as tmp:
        for path in files:
            rel = os.path.relpath(path, ROOT)
            for line, link in broken_links(path):
                failures.append(f"{rel}:{line}: the link `{link}` names no file")
            for line, lang, marker, text, info in blocks(path):
                where = f"{rel}:{line}"
                if lang not in RUNNABLE:
                    continue
                if marker.startswith("skip"):
                    reason = marker[4:].strip(" :")
                    if not reason:
                        failures.append(f"{where}: `check: skip` needs a reason")
                    else:
                        skipped += 1
                        print(f"skip {where}: {reason}")
                    continue
                text = include(text, path)
                if lang == "rust":
                    by_mdbook += 1
                    continue
                err = None
                full = marker.startswith("full")
                if full and not marker[4:].strip(" :"):
                    failures.append(f"{where}: `check: full` needs a reason")
                    continue
                if lang in ("sh", "bash") and (not marker or full):
                    for cmd in commands(text):
                        c = cut(cmd, full)
                        print(f"run  {where}: {c}", flush=True)
                        err = run(c, "command")
                        ran += 1
                        if err:
                            break
                elif marker == "learner" and lang in ("python", "js", "javascript", "c"):
                    print(f"run  {where}: a {lang} learner's trial", flush=True)
                    err = learner(path, line, lang, text, tmp)
                    ran += 1
                elif marker.startswith("robot ") and lang == "toml":
                    print(f"run  {where}: a robot file's trial", flush=True)
                    err = robot(line, text, marker[6:].strip(), tmp)
                    ran += 1
                elif marker == "scenario" and lang == "toml":
                    print(f"run  {where}: a scenario file's trial", flush=True)
                    err = scenario(line, text, tmp)
                    ran += 1
                else:
                    err = (f"a `{info}` block with no check: mark it `<!-- check: learner -->`, "
                           "`<!-- check: scenario -->` or `<!-- check: skip REASON -->`")
                if err:
                    failures.append(f"{where}: {err}")
                    print(f"FAIL {where}", flush=True)
    print(f"\ndoc check: {ran} commands and blocks ran, {by_mdbook} Rust blocks left to "
          f"`mdbook test`, {skipped} skipped with a reason, {len(failures)} failed")
    for f in failures:
        print(f"\n{f}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
