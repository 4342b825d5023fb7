#!/usr/bin/env python3
# Copied unchanged from the team's shared tools (../shared/layout.py); .ci/run runs it.
"""Module import graph of each crate under crates/: cycles between files, the largest files.

A file's module path comes from its place under src/ (a/b.rs and a/b/mod.rs are crate::a::b);
an edge A -> B is any `crate::B...` path in A's code (use lines and inline paths; comments and doc
links aside), resolved to the
longest module prefix that exists. Prints, per crate, its files, edges, cycles (strongly connected
components of more than one file) and the largest files; exits 1 if any crate has a cycle or a
file over --max-lines non-test lines.
"""
import argparse
import os
import re
import sys


def modules(src):
    mods = {}
    for root, _, files in os.walk(src):
        for f in files:
            if not f.endswith(".rs"):
                continue
            p = os.path.join(root, f)
            rel = os.path.relpath(p, src)[:-3].split(os.sep)
            if rel[-1] in ("mod", "lib", "main"):
                rel = rel[:-1]
            mods["::".join(rel)] = p
    return mods


def code_lines(path):
    """Lines before the first `#[cfg(test)]` module, blank and comment lines aside."""
    n = 0
    for line in open(path, encoding="utf-8"):
        s = line.strip()
        if s.startswith("#[cfg(test)]"):
            break
        if s and not s.startswith("//"):
            n += 1
    return n


def edges(mods):
    out = {m: set() for m in mods}
    pat = re.compile(r"crate::((?:[a-z_][a-z0-9_]*::)*[a-z_][a-z0-9_]*)")
    for m, p in mods.items():
        text = open(p, encoding="utf-8").read()
        text = text.split("#[cfg(test)]")[0]
        # comments (doc links included) are not imports
        text = "\n".join(l.split("//")[0] for l in text.splitlines())
        names = [x for x in pat.findall(text)]
        # grouped paths, `crate::a::{b::X, c}`: each member is a path under the prefix
        for prefix, body in re.findall(r"crate::((?:[a-z_][a-z0-9_]*::)*)\{((?:[^{}]|\{[^{}]*\})*)\}", text):
            body = re.sub(r"\{[^{}]*\}", "", body)
            for part in body.split(","):
                part = part.strip().rstrip(":")
                if part and re.match(r"^[a-z_]", part) and part != "self":
                    names.append(prefix + part)
        # `super::x` paths: `super` is the parent module, whatever the file's name
        for sup, rest in re.findall(r"\b((?:super::)+)((?:[a-z_][a-z0-9_]*::)*[a-z_][a-z0-9_]*)", text):
            base = m.split("::") if m else []
            up = sup.count("super::")
            if up <= len(base):
                names.append("::".join(base[: len(base) - up] + rest.split("::")))
        for n in names:
            parts = n.split("::")
            for k in range(len(parts), 0, -1):
                cand = "::".join(parts[:k])
                if cand in mods and cand != m and cand != "":
                    out[m].add(cand)
                    break
    return out


def sccs(graph):
    index, low, stack, on, res, i = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = i[0]; i[0] += 1; stack.append(v); on.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w); low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop(); on.discard(w); comp.append(w)
                if w == v:
                    break
            res.append(comp)

    sys.setrecursionlimit(10000)
    for v in graph:
        if v not in index:
            visit(v)
    return [c for c in res if len(c) > 1]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("checkout")
    ap.add_argument("--max-lines", type=int, default=600)
    args = ap.parse_args()
    bad = []
    summary = []
    for crate in sorted(os.listdir(os.path.join(args.checkout, "crates"))):
        src = os.path.join(args.checkout, "crates", crate, "src")
        if not os.path.isdir(src):
            continue
        mods = modules(src)
        g = edges(mods)
        cyc = sccs(g)
        sizes = sorted(((code_lines(p), m or "lib") for m, p in mods.items()), reverse=True)
        big = [f"{m} {n}" for n, m in sizes if n > args.max_lines]
        summary.append(f"{crate}: {len(mods)} files, {sum(len(v) for v in g.values())} edges, "
                       f"{len(cyc)} cycles, largest {sizes[0][1]} {sizes[0][0]}")
        for c in cyc:
            bad.append(f"{crate}: import cycle {' -> '.join(sorted(c))}")
        for b in big:
            bad.append(f"{crate}: {b} lines of code (> {args.max_lines})")
    for b in bad:
        print(b)
    print("; ".join(summary))
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
