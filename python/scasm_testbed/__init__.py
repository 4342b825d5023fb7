"""Calibration learners in Python for the SCASM testbed.

A learner is a subclass of :class:`Learner` with ``handle(event)`` and four
queries (``action_model``, ``sensor_model``, ``x_a``, ``x_s``); :func:`run`
speaks the testbed's learner protocol (``book/src/learner/protocol.md``,
version 1) for it on stdin and stdout::

    from scasm_testbed import Command, Event, Learner, Setting, run

    class Mine(Learner):
        name = "mine"
        about = "what it is, in a line"
        settings = [Setting("gain", 0.5, min=0.0, max=1.0, doc="how much")]

        def handle(self, event: Event) -> None: ...
        def action_model(self) -> Coefficients: return [0.0, 1.0]   # or None: not yet
        def sensor_model(self) -> Coefficients: return None

    if __name__ == "__main__":
        run(Mine)

and the testbed runs it with ``--learner 'exec:python3 mine.py'``. A trial
must end with both models. Only the standard library is needed. Logs go to
stderr: stdout is the protocol's. :mod:`scasm_testbed.testing` replays a
recorded trial to a learner in-process, for its tests.
"""

import abc
import json
import math
import sys
import traceback
from dataclasses import dataclass
from typing import IO, Any, Dict, List, Mapping, Optional, Sequence, Tuple, Type, Union

__version__ = "0.2.0"
"""The package's version: the testbed's, which it ships with."""

PROTOCOL = 1
"""The protocol version this package speaks."""

Coefficients = Optional[Sequence[float]]
"""A model: polynomial coefficients, lowest power first, or None for "not yet"."""


@dataclass(frozen=True)
class Setting:
    """One of a learner's own settings: ``learner.<name>.<key>`` to the host."""

    key: str
    default: float
    min: Optional[float] = None
    max: Optional[float] = None
    integer: bool = False
    doc: str = ""

    def declaration(self) -> Dict[str, Any]:
        """The setting as the hello declares it."""
        out: Dict[str, Any] = {"key": self.key, "default": self.default, "integer": self.integer, "doc": self.doc}
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


Event = Union[Command, Reading]
"""What the host tells a learner: a command in force, or a reading."""


@dataclass(frozen=True)
class Models:
    """A learner's answer to a query."""

    action: Optional[List[float]]
    sensor: Optional[List[float]]
    x_a: Optional[float]
    x_s: Optional[float]


@dataclass(frozen=True)
class Draw:
    """One draw of a learner's posterior over the robot's true responses, in
    its own units: the action response (coefficients, lowest power first)
    and the sensor response as a table of ``(reading px, location)`` sorted
    by reading (2 to 64 points; the host interpolates between them)."""

    action: Sequence[float]
    sensor: Sequence[Tuple[float, float]]


class Learner(abc.ABC):
    """A calibration learner. Subclasses set ``name`` (letters, digits, ``-``
    and ``_``), ``about`` and ``settings``, and implement :meth:`handle` and the
    queries.

    Before any event the host's settings arrive: ``self.own`` (its own settings
    by key) and ``self.shared`` (``gamma``, ``beta``, ``t_start``,
    ``sensor_degree``, ``action_degree``, ``sensor_window``, ``forward_degree``,
    ``action_prior``, ``action_highpass``, ``action_robust``, ``command_scale``)
    are set by the package, and then :meth:`configure` is called: override it
    to set up from them (there is no need to call ``super().configure``)."""

    name: str = "python-learner"
    about: str = ""
    settings: Sequence[Setting] = ()

    def __init__(self) -> None:
        self.own: Dict[str, float] = {s.key: s.default for s in self.settings}
        self.shared: Dict[str, float] = {}

    def configure(self, own: Mapping[str, float], shared: Mapping[str, float]) -> None:
        """Called once, before any event, with the settings in force (also
        in ``self.own`` and ``self.shared``)."""

    @abc.abstractmethod
    def handle(self, event: Event) -> None:
        """Takes a :class:`Command` or a :class:`Reading`; raise to refuse it
        (the trial then fails with the message)."""

    def action_model(self) -> Coefficients:
        """Command -> location units per second: coefficients, lowest power first, or None."""
        return None

    def sensor_model(self) -> Coefficients:
        """Pixels -> location units: coefficients, lowest power first, or None."""
        return None

    def x_a(self) -> Optional[float]:
        """The dead-reckoned location, or None."""
        return None

    def x_s(self) -> Optional[float]:
        """The location the sensor model gave for the latest reading, or None."""
        return None

    def posterior(self, draws: int) -> Optional[List[Draw]]:
        """Optional: at most ``draws`` draws of its posterior over the robot's
        true responses, asked once at the end of a trial; None if it has none
        then. A learner that overrides it says so in its hello, and the host
        judges its models against each draw: its predicted error and band."""
        return None

    def set_up(self, own: Mapping[str, float], shared: Mapping[str, float]) -> None:
        """Keeps the settings in force (its own over their defaults) and calls
        :meth:`configure`: what the host's ``settings`` message does."""
        self.own = {**{s.key: s.default for s in self.settings}, **own}
        self.shared = dict(shared)
        self.configure(self.own, self.shared)

    def models(self) -> Models:
        """Its answer to a query, checked: finite numbers, or None."""
        return Models(
            _finite_list(self.action_model()),
            _finite_list(self.sensor_model()),
            _finite(self.x_a()),
            _finite(self.x_s()),
        )


def _finite_list(coeffs: Coefficients) -> Optional[List[float]]:
    if coeffs is None:
        return None
    out = [float(c) for c in coeffs]
    if not out or not all(math.isfinite(c) for c in out):
        raise ValueError(f"a model must be finite coefficients, got {out}")
    return out


def _finite(x: Optional[float]) -> Optional[float]:
    if x is None:
        return None
    x = float(x)
    if not math.isfinite(x):
        raise ValueError(f"a location must be finite, got {x}")
    return x


def _draws(draws: Optional[List[Draw]]) -> Optional[List[Dict[str, Any]]]:
    """A posterior's draws as the protocol writes them, checked."""
    if draws is None:
        return None
    out = []
    for d in draws:
        table = [[float(obs), float(x)] for obs, x in d.sensor]
        if not all(math.isfinite(v) for p in table for v in p) or any(
            b[0] <= a[0] for a, b in zip(table, table[1:])
        ):
            raise ValueError(f"a draw's sensor table must be finite and sorted by reading, got {table[:4]}...")
        out.append({"action": _finite_list(d.action), "sensor": table})
    return out


def hello(learner_class: Type[Learner]) -> Dict[str, Any]:
    """The hello a learner of ``learner_class`` says."""
    out: Dict[str, Any] = {
        "type": "hello",
        "protocol": PROTOCOL,
        "name": learner_class.name,
        "about": learner_class.about,
        "settings": [s.declaration() for s in learner_class.settings],
    }
    if learner_class.posterior is not Learner.posterior:
        out["posterior"] = True
    return out


def run(learner_class: Type[Learner], stdin: Optional[IO[str]] = None, stdout: Optional[IO[str]] = None) -> None:
    """Speaks the protocol for a learner of ``learner_class`` until the host ends the trial."""
    inp = stdin or sys.stdin
    out = stdout or sys.stdout

    def send(message: Dict[str, Any]) -> None:
        out.write(json.dumps(message, allow_nan=False) + "\n")
        out.flush()

    learner = learner_class()
    send(hello(learner_class))
    try:
        for line in iter(inp.readline, ""):
            m = json.loads(line)
            kind = m["type"]
            if kind == "command":
                learner.handle(Command(m["t_s"], m["dt_s"], m["command"]))
            elif kind == "reading":
                learner.handle(Reading(m["t_s"], m["obs_px"]))
            elif kind == "query":
                a = learner.models()
                send({"type": "models", "action": a.action, "sensor": a.sensor, "x_a": a.x_a, "x_s": a.x_s})
            elif kind == "posterior":
                send({"type": "posterior", "draws": _draws(learner.posterior(m["draws"]))})
            elif kind == "settings":
                if m.get("protocol") != PROTOCOL:
                    raise ValueError(f"the host speaks protocol {m.get('protocol')}, this package {PROTOCOL}")
                learner.set_up(m["settings"], m["shared"])
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


__all__ = [
    "Coefficients",
    "Command",
    "Draw",
    "Event",
    "Learner",
    "Models",
    "PROTOCOL",
    "Reading",
    "Setting",
    "__version__",
    "hello",
    "run",
]
