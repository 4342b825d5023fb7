#!/usr/bin/env python3
"""A learner that does no work: it answers every query with the same fixed
models. Replaying a trial to it measures what the protocol itself costs.

    cargo run --release --example replay -- RUN_DIR/trial-0 --learner 'exec:python3 examples/learners/noop.py'
"""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "python"))
from scasm_testbed import Learner, run  # noqa: E402


class Noop(Learner):
    name = "noop-py"
    about = "no work: fixed models, for the protocol's own cost"

    def handle(self, event):
        pass

    def action_model(self):
        return [0.0, 1.0]

    def sensor_model(self):
        return [5000.0, -100.0]


if __name__ == "__main__":
    run(Noop)
