#!/usr/bin/env python3
"""The paper's SCASM (Stronger & Stone, Fig. 4) in plain Python, for the
testbed's learner protocol: the same algorithm as the Rust `scasm-paper`
(every reading its own point of the sensor fit), step for step, so that on
the same recording it gives the same models.

    cargo run --release --example replay -- RUN_DIR --learner 'exec:python3 examples/learners/scasm_paper.py'

Each model is an exponentially weighted least-squares fit (Eq. 2-7) kept in
square-root form (Givens rotations), with the sensor fit's input normalised
to an interval that widens as readings arrive.
"""

import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from scasm_testbed import Command, Learner, run  # noqa: E402

RANK_TOL = 1e-10
WIDEN = 0.25
MIN_HALF_WIDTH = 1e-3
TIME_TOLERANCE_S = 1e-6
MIN_POSITIVE = 2.2250738585072014e-308


class Wls:
    """y ~ alpha + beta . v with forgetting, as the upper-triangular factor of [1 | v | y]."""

    def __init__(self, regressors, gamma):
        self.p = regressors
        self.m = regressors + 2
        self.r = [[0.0] * self.m for _ in range(self.m)]
        self.sqrt_gamma = math.sqrt(gamma)
        self.points = 0

    def add(self, v, y):
        m, r = self.m, self.r
        row = [1.0] + list(v) + [y]
        if self.sqrt_gamma != 1.0:
            for i in range(m):
                ri = r[i]
                for k in range(i, m):
                    ri[k] *= self.sqrt_gamma
        for j in range(m):
            a, b = r[j][j], row[j]
            if b == 0.0:
                continue
            h = math.sqrt(a * a + b * b)
            inv_h = 1.0 / h
            c, s = a * inv_h, b * inv_h
            r[j][j] = h
            row[j] = 0.0
            rj = r[j]
            for k in range(j + 1, m):
                rk, zk = rj[k], row[k]
                rj[k] = c * rk + s * zk
                row[k] = c * zk - s * rk
        self.points += 1

    def reparametrise(self, t):
        n = self.p + 1
        old = [row[:] for row in self.r]
        for i in range(n):
            for k in range(i, n):
                acc = 0.0
                for j in range(i, k + 1):
                    acc += old[i][j] * t[k][j]
                self.r[i][k] = acc

    def solve(self):
        n, r = self.p + 1, self.r
        if self.points < n:
            return None
        for j in range(n):
            col = 0.0
            for i in range(j + 1):
                col += r[i][j] * r[i][j]
            if not r[j][j] * r[j][j] > RANK_TOL * RANK_TOL * col:
                return None
        x = [0.0] * n
        for i in reversed(range(n)):
            tail = 0.0
            for k in range(i + 1, n):
                tail += r[i][k] * x[k]
            x[i] = (r[i][n] - tail) / r[i][i]
        return x if all(math.isfinite(v) for v in x) else None


def evaluate(coeffs, x):
    acc = 0.0
    for c in reversed(coeffs):
        acc = acc * x + c
    return acc


def from_normalised(q, centre, half_width):
    """p with p(x) = q((x - centre) / half_width), in raw powers of x."""
    n = len(q)
    p = [0.0] * n
    a, b = 1.0 / half_width, -centre / half_width
    for k in reversed(range(n)):
        nxt = [0.0] * n
        for j in range(n):
            if j + 1 < n:
                nxt[j + 1] += a * p[j]
            nxt[j] += b * p[j]
        nxt[0] += q[k]
        p = nxt
    return p


class PolynomialFit:
    """y ~ p(x), fitted on u = (x - centre) / half_width with |u| <= 1."""

    def __init__(self, degree, gamma):
        self.wls = Wls(degree, gamma)
        self.degree = degree
        self.interval = None

    def add(self, x, y):
        if self.interval is None:
            hw = MIN_HALF_WIDTH * max(abs(x), MIN_POSITIVE)
            self.interval = (x, hw)
        else:
            c, h = self.interval
            if not abs(x - c) <= h:
                lo, hi = min(c - h, x), max(c + h, x)
                new = (0.5 * (lo + hi), 0.5 * (hi - lo) * (1.0 + WIDEN))
                self.renormalise((c, h), new)
        centre, half_width = self.interval
        u = (x - centre) / half_width
        powers, p = [], 1.0
        for _ in range(self.degree):
            p *= u
            powers.append(p)
        self.wls.add(powers, y)

    def renormalise(self, old, new):
        a = old[1] / new[1]
        b = (old[0] - new[0]) / new[1]
        size = self.degree + 1
        t = [[0.0] * size for _ in range(size)]
        for k in range(size):
            binom = 1.0
            for j in range(k + 1):
                t[k][j] = binom * math.pow(a, j) * math.pow(b, k - j)
                binom = binom * (k - j) / (j + 1)
        self.wls.reparametrise(t)
        self.interval = new

    def polynomial(self):
        if self.interval is None:
            return None
        q = self.wls.solve()
        if q is None:
            return None
        p = from_normalised(q[: self.degree + 1], *self.interval)
        return p if all(math.isfinite(c) for c in p) else None


class ActionFit:
    """Eq. 5: x_s(t) on V_i(t) = integral of (C / scale)^i, i = 0..d, with intercept x(0)."""

    def __init__(self, degree, gamma, command_scale):
        self.wls = Wls(degree + 1, gamma)
        self.degree = degree
        self.scale = command_scale
        self.integrals = [0.0] * (degree + 1)

    def integrate(self, command, dt_s):
        u = command / self.scale
        p = 1.0
        for i in range(self.degree + 1):
            self.integrals[i] += p * dt_s
            p *= u

    def add(self, x_s):
        self.wls.add(self.integrals, x_s)

    def model(self):
        b = self.wls.solve()
        if b is None:
            return None
        coeffs, scale_pow = [], 1.0
        for bi in b[1 : self.degree + 2]:
            coeffs.append(bi / scale_pow)
            scale_pow *= self.scale
        return coeffs if all(math.isfinite(c) for c in coeffs) else None


class ScasmPaper(Learner):
    name = "scasm-paper-py"
    about = "the paper's SCASM in plain Python (the Rust scasm-paper, ported step for step)"

    def configure(self, own, shared):
        super().configure(own, shared)
        self.gamma = shared["gamma"]
        self.beta = shared["beta"]
        self.t_start = shared["t_start"]
        self.clock = 0.0
        self._x_a, self._x_s = 0.0, None
        self.sensor_fit = PolynomialFit(int(shared["sensor_degree"]), self.gamma)
        self.action_fit = ActionFit(int(shared["action_degree"]), self.gamma, shared["command_scale"])
        self.sensor, self.action = None, None

    def check_time(self, t_s):
        if t_s < self.clock - TIME_TOLERANCE_S or t_s > self.clock + TIME_TOLERANCE_S:
            raise ValueError(f"event at {t_s} s, learner clock at {self.clock} s")

    def handle(self, e):
        self.check_time(e.t_s)
        if isinstance(e, Command):
            if e.t_s < 2.0 * self.t_start or self.action is None:
                velocity = e.command  # A0, the identity
            else:
                velocity = evaluate(self.action, e.command)
            if math.isfinite(velocity):
                self._x_a += velocity * e.dt_s
            self.action_fit.integrate(e.command, e.dt_s)
            self.clock = e.t_s + e.dt_s
            return
        if e.t_s > self.t_start:
            x_s = evaluate(self.sensor, e.obs_px) if self.sensor is not None else None
            self._x_s = x_s if x_s is not None and math.isfinite(x_s) else None
            if self._x_s is not None:
                self.action_fit.add(self._x_s)
                self.action = self.action_fit.model()
                self._x_a = (1.0 - self.beta) * self._x_a + self.beta * self._x_s
        if math.isfinite(self._x_a):
            self.sensor_fit.add(e.obs_px, self._x_a)
            self.sensor = self.sensor_fit.polynomial()

    def action_model(self):
        return self.action

    def sensor_model(self):
        return self.sensor

    def x_a(self):
        return self._x_a

    def x_s(self):
        return self._x_s


if __name__ == "__main__":
    run(ScasmPaper)
