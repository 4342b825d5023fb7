#!/usr/bin/env python3
"""What a Python user writes first: the paper's section IV. Take the walk
command as the velocity (the identity action model A0), dead-reckon the
location from it, and fit the sensor model by least squares over every
reading so far (the normal equations, solved with the standard library).
The action model is A0 itself. About forty lines of method.

    cargo run --release --example replay -- RUN_DIR --learner 'exec:python3 examples/learners/inverse_fit.py'
"""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from scasm_testbed import Command, Learner, Setting, run  # noqa: E402


def solve(a, b):
    """a x = b by Gaussian elimination with partial pivoting (None if singular)."""
    n = len(b)
    m = [row[:] + [b[i]] for i, row in enumerate(a)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(m[r][c]))
        if abs(m[p][c]) < 1e-12 * max(1.0, max(abs(v) for v in m[p][:n])):
            return None
        m[c], m[p] = m[p], m[c]
        for r in range(c + 1, n):
            f = m[r][c] / m[c][c]
            for k in range(c, n + 1):
                m[r][k] -= f * m[c][k]
    x = [0.0] * n
    for r in reversed(range(n)):
        x[r] = (m[r][n] - sum(m[r][k] * x[k] for k in range(r + 1, n))) / m[r][r]
    return x


class InverseFit(Learner):
    name = "inverse-fit-py"
    about = "section IV: dead reckoning with A0, S by least squares over every reading"
    settings = [Setting("scale_px", 30.0, min=1.0, doc="readings are divided by this inside the fit")]

    def configure(self, own, shared):
        super().configure(own, shared)
        self.degree = int(shared["sensor_degree"])
        self.scale = own["scale_px"]
        n = self.degree + 1
        self.ata = [[0.0] * n for _ in range(n)]
        self.aty = [0.0] * n
        self.x, self.readings, self.sensor = 0.0, 0, None

    def handle(self, e):
        if isinstance(e, Command):
            self.x += e.command * e.dt_s  # A0: the command is the velocity
            return
        u = e.obs_px / self.scale
        powers = [u**k for k in range(self.degree + 1)]
        for i, pi in enumerate(powers):
            self.aty[i] += pi * self.x
            for j, pj in enumerate(powers):
                self.ata[i][j] += pi * pj
        self.readings += 1
        q = solve(self.ata, self.aty) if self.readings > self.degree else None
        # Back to raw pixels: q_k u^k = q_k / scale^k obs^k.
        self.sensor = None if q is None else [c / self.scale**k for k, c in enumerate(q)]

    def action_model(self):
        return [0.0, 1.0]

    def sensor_model(self):
        return self.sensor

    def x_a(self):
        return self.x


if __name__ == "__main__":
    run(InverseFit)
