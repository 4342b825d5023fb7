"""Testing a learner without the testbed's binary: a recorded trial replayed
to a learner in-process, as the host would drive it, under pytest or any test
runner::

    from scasm_testbed.testing import replay

    def test_my_learner_ends_with_both_models():
        answers = replay(Mine, "tests/data/trial-0")
        assert answers[-1].action is not None and answers[-1].sensor is not None

A recorded trial is a folder a ``train`` run writes for each trial,
``trial-<seed>/``: its ``events.csv`` is what the learner saw (the commands, and
the readings, where there were any), and its ``dataset.json`` the run's settings.
"""

import csv
import json
import os
from typing import Dict, Iterator, List, Mapping, Optional, Type

from . import Command, Event, Learner, Models, Reading

SHARED_DEFAULTS: Dict[str, float] = {
    "gamma": 0.999,
    "beta": 0.01,
    "t_start": 30.0,
    "sensor_degree": 3,
    "action_degree": 4,
    "sensor_window": 5,
    "forward_degree": 5,
    "action_prior": 10.0,
    "action_highpass": 5.0,
    "action_robust": 1.5,
    "command_scale": 300.0,
}
"""The shared settings at the ERS-7's defaults, for a trial that does not record them."""


def events(trial_dir: str) -> Iterator[Event]:
    """The events of a recorded trial, in order: each frame's command, and its
    reading where there was one (as the host sends them)."""
    with open(os.path.join(trial_dir, "events.csv"), newline="", encoding="utf-8") as f:
        rows = csv.DictReader(f)
        if rows.fieldnames != ["t_s", "dt_s", "command", "obs_px"]:
            raise ValueError(f"{trial_dir}/events.csv: columns {rows.fieldnames} are not a dataset's")
        for row in rows:
            t_s, dt_s = float(row["t_s"]), float(row["dt_s"])
            yield Command(t_s, dt_s, float(row["command"]))
            if row["obs_px"]:
                yield Reading(t_s + dt_s, float(row["obs_px"]))


def shared_settings(trial_dir: str) -> Dict[str, float]:
    """The shared learner settings the trial was recorded with (its
    ``dataset.json``'s scenario, read with ``tomllib`` on Python 3.11 and
    newer), over :data:`SHARED_DEFAULTS`."""
    out = dict(SHARED_DEFAULTS)
    try:
        import tomllib  # Python 3.11+
    except ImportError:  # older: the defaults
        return out
    path = os.path.join(trial_dir, "dataset.json")
    if not os.path.exists(path):
        return out
    with open(path, encoding="utf-8") as f:
        scenario = json.load(f).get("scenario", "")
    learner = tomllib.loads(scenario).get("learner", {}) if isinstance(scenario, str) else {}
    for key in SHARED_DEFAULTS:
        value = learner.get(key)
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            out[key] = float(value)
    return out


def replay(
    learner_class: Type[Learner],
    trial_dir: str,
    own: Optional[Mapping[str, float]] = None,
    shared: Optional[Mapping[str, float]] = None,
) -> List[Models]:
    """Replays recorded trial ``trial_dir`` to a new learner of ``learner_class``,
    set up with ``own`` settings (over its defaults) and ``shared`` ones (over
    the trial's): its answer after each frame, as the host would query it."""
    learner = learner_class()
    learner.set_up(dict(own or {}), {**shared_settings(trial_dir), **(shared or {})})
    answers: List[Models] = []
    pending = False
    for event in events(trial_dir):
        if isinstance(event, Command) and pending:
            answers.append(learner.models())
        learner.handle(event)
        pending = True
    if pending:
        answers.append(learner.models())
    return answers
