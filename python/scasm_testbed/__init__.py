"""Calibration learners in Python for the SCASM testbed.

A learner is a class with ``handle(event)`` and four queries (``action_model``,
``sensor_model``, ``x_a``, ``x_s``); :func:`run` speaks the testbed's learner
protocol (``book/src/learner/protocol.md``, version 1) for it on stdin and stdout::

    from scasm_testbed import Learner, Setting, run

    class Mine(Learner):
        name = "mine"
        about = "what it is, in a line"
        settings = [Setting("gain", 0.5, min=0.0, max=1.0, doc="how much")]

        def handle(self, event): ...
        def action_model(self): return None   # or [c0, c1, ...], lowest power first
        def sensor_model(self): return None

    if __name__ == "__main__":
        run(Mine)

and the testbed runs it with ``--learner 'exec:python3 mine.py'``. Only the
standard library is needed. Logs go to stderr: stdout is the protocol's.
"""

import json
import math
import sys
import traceback
from dataclasses import dataclass

__version__ = "0.2.0"
"""The package's version: the testbed's, which it ships with."""

PROTOCOL = 1
"""The protocol version this package speaks."""


@dataclass(frozen=True)
class Setting:
    """One of a learner's own settings: ``learner.<name>.<key>`` to the host."""

    key: str
    default: float
    min: float = None
    max: float = None
    integer: bool = False
    doc: str = ""

    def declaration(self):
        out = {"key": self.key, "default": self.default, "integer": self.integer, "doc": self.doc}
        if self.min is not None:
            out["min"] = self.min
        if self.max is not None:
            out["max"] = self.max
        return out


@dataclass(frozen=True)
class Command:
    """``command`` was in force from ``t_s`` to ``t_s + dt_s`` (back to back, from 0)."""

    t_s: float
    dt_s: float
    command: float


@dataclass(frozen=True)
class Reading:
    """The beacon's height in the image, px, at ``t_s`` (the end of the last command)."""

    t_s: float
    obs_px: float


class Learner:
    """A calibration learner. Subclasses set ``name`` (letters, digits, ``-``
    and ``_``), ``about`` and ``settings``, and implement :meth:`handle` and
    the queries. After construction the host's settings arrive in
    :meth:`configure`: ``self.own`` (its own settings by key) and
    ``self.shared`` (``gamma``, ``beta``, ``t_start``, ``sensor_degree``,
    ``action_degree``, ``sensor_window``, ``forward_degree``,
    ``action_prior``, ``action_highpass``, ``action_robust``,
    ``command_scale``)."""

    name = "python-learner"
    about = ""
    settings = []

    def configure(self, own, shared):
        self.own = own
        self.shared = shared

    def handle(self, event):
        """Takes a :class:`Command` or a :class:`Reading`; raise to refuse it
        (the trial then fails with the message)."""
        raise NotImplementedError

    def action_model(self):
        """Command -> location units per second: coefficients, lowest power first, or None."""
        return None

    def sensor_model(self):
        """Pixels -> location units: coefficients, lowest power first, or None."""
        return None

    def x_a(self):
        """The dead-reckoned location, or None."""
        return None

    def x_s(self):
        """The location the sensor model gave for the latest reading, or None."""
        return None


def _finite_list(coeffs):
    if coeffs is None:
        return None
    out = [float(c) for c in coeffs]
    if not out or not all(math.isfinite(c) for c in out):
        raise ValueError(f"a model must be finite coefficients, got {out}")
    return out


def _finite(x):
    if x is None:
        return None
    x = float(x)
    if not math.isfinite(x):
        raise ValueError(f"a location must be finite, got {x}")
    return x


def run(learner_class, stdin=None, stdout=None):
    """Speaks the protocol for a learner of ``learner_class`` until the host ends the trial."""
    stdin = stdin or sys.stdin
    stdout = stdout or sys.stdout

    def send(message):
        stdout.write(json.dumps(message, allow_nan=False) + "\n")
        stdout.flush()

    learner = learner_class()
    send({
        "type": "hello",
        "protocol": PROTOCOL,
        "name": learner.name,
        "about": learner.about,
        "settings": [s.declaration() for s in learner.settings],
    })
    try:
        for line in iter(stdin.readline, ""):
            m = json.loads(line)
            kind = m["type"]
            if kind == "command":
                learner.handle(Command(m["t_s"], m["dt_s"], m["command"]))
            elif kind == "reading":
                learner.handle(Reading(m["t_s"], m["obs_px"]))
            elif kind == "query":
                send({
                    "type": "models",
                    "action": _finite_list(learner.action_model()),
                    "sensor": _finite_list(learner.sensor_model()),
                    "x_a": _finite(learner.x_a()),
                    "x_s": _finite(learner.x_s()),
                })
            elif kind == "settings":
                if m.get("protocol") != PROTOCOL:
                    raise ValueError(f"the host speaks protocol {m.get('protocol')}, this package {PROTOCOL}")
                learner.configure(m["settings"], m["shared"])
            elif kind == "end":
                return
            else:
                raise ValueError(f"unknown message type {kind!r}")
    except Exception as e:  # the host is told why, and the trace goes to stderr
        traceback.print_exc(file=sys.stderr)
        try:
            send({"type": "error", "message": f"{type(e).__name__}: {e}"})
        except (OSError, ValueError):
            pass
        sys.exit(1)
