#!/usr/bin/env python3
"""What a Python user writes first: the paper's section IV. Take the walk
command as the velocity (the identity action model A0), dead-reckon the
location from it, and fit the sensor model by least squares over every
reading so far (the normal equations, solved with the standard library).
The action model is A0 itself. About forty lines of method, and twenty
more for saying how sure it is (`posterior`): the least-squares fit's own
Gaussian over the sensor model's coefficients (the residuals' variance times
the inverse of the normal equations), its action model A0 taken as known.
That belief counts the readings' scatter about the fit, not the dead
reckoning's drift, and A0 is not the robot's response: the run's band
coverage says how far to trust it.

    cargo run --release --example replay -- RUN_DIR --learner 'exec:python3 examples/learners/inverse_fit.py'
"""

import os
import random
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from scasm_testbed import Command, Draw, Learner, Setting, run  # noqa: E402


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
        self.yty, self.seen = 0.0, (float("inf"), 0.0)

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
        self.yty += self.x * self.x
        self.seen = (min(self.seen[0], e.obs_px), max(self.seen[1], e.obs_px))
        self.q = q = solve(self.ata, self.aty) if self.readings > self.degree else None
        # Back to raw pixels: q_k u^k = q_k / scale^k obs^k.
        self.sensor = None if q is None else [c / self.scale**k for k, c in enumerate(q)]

    def action_model(self):
        return [0.0, 1.0]

    def sensor_model(self):
        return self.sensor

    def x_a(self):
        return self.x

    def posterior(self, draws):
        n = self.degree + 1
        if self.sensor is None or self.readings <= n:
            return None
        # The residuals' variance, and the coefficients' covariance: its
        # times the inverse of the normal equations (Cholesky-factored).
        rss = self.yty - sum(q * b for q, b in zip(self.q, self.aty))
        var = max(rss, 0.0) / (self.readings - n)
        cols = [solve(self.ata, [float(i == j) for i in range(n)]) for j in range(n)]
        if any(c is None for c in cols):
            return None
        cov = [[var * cols[j][i] for j in range(n)] for i in range(n)]
        low = [[0.0] * n for _ in range(n)]
        for i in range(n):
            for j in range(i + 1):
                d = cov[i][j] - sum(low[i][k] * low[j][k] for k in range(j))
                low[i][j] = max(d, 0.0) ** 0.5 if i == j else (d / low[j][j] if low[j][j] else 0.0)
        rng = random.Random(self.readings)  # the same events, the same draws
        lo, hi = self.seen
        if not hi > lo:
            return None
        table_obs = [lo + (hi - lo) * k / 31 for k in range(32)]
        out = []
        for _ in range(draws):
            z = [rng.gauss(0.0, 1.0) for _ in range(n)]
            q = [self.q[i] + sum(low[i][k] * z[k] for k in range(i + 1)) for i in range(n)]
            table = [(o, sum(c * (o / self.scale) ** k for k, c in enumerate(q))) for o in table_obs]
            out.append(Draw(action=[0.0, 1.0], sensor=table))
        return out


if __name__ == "__main__":
    run(InverseFit)
