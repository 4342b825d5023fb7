#!/usr/bin/env python3
"""A first learner: dead reckoning with the command as the velocity (A0), and a
straight-line sensor model fitted to it by least squares, over every reading.

    cargo run --release --example train -- --learner 'exec:python3 examples/learners/quickstart.py'
"""

import os
import sys
from typing import Mapping, Optional

# The package from this checkout (or: pip install ./python).
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from scasm_testbed import Coefficients, Command, Event, Learner, Setting, run  # noqa: E402


class Quickstart(Learner):
    name = "quickstart-py"
    about = "dead reckoning with A0, a straight-line sensor model by least squares"
    settings = [Setting("gain", 1.0, min=0.1, max=10.0, doc="the action model's slope")]

    def configure(self, own: Mapping[str, float], shared: Mapping[str, float]) -> None:
        self.gain = own["gain"]
        self.x = 0.0  # the location by dead reckoning, in the command's units
        self.n = self.su = self.sx = self.suu = self.sux = 0.0  # sums for the line x = s0 + s1 u

    def handle(self, event: Event) -> None:
        if isinstance(event, Command):
            self.x += self.gain * event.command * event.dt_s
            return
        u = event.obs_px
        self.n += 1
        self.su += u
        self.sx += self.x
        self.suu += u * u
        self.sux += u * self.x

    def action_model(self) -> Coefficients:
        return [0.0, self.gain]  # coefficients, lowest power first

    def sensor_model(self) -> Coefficients:
        det = self.n * self.suu - self.su * self.su
        if self.n < 2 or det <= 1e-9 * max(1.0, self.n * self.suu):
            return None  # not yet: every trial must end with a model
        s1 = (self.n * self.sux - self.su * self.sx) / det
        return [(self.sx - s1 * self.su) / self.n, s1]

    def x_a(self) -> Optional[float]:
        return self.x


if __name__ == "__main__":
    run(Quickstart)
