"""The Python package's own tests: the protocol loop, the settings hook, and
replaying a recorded trial to a learner in-process (no Rust binary)."""

import io
import json
import math
import os
import sys
from typing import Any, Dict, List, Mapping, Optional

import pytest

import scasm_testbed
from scasm_testbed import Coefficients, Command, Draw, Event, Learner, Reading, Setting, hello, run
from scasm_testbed.testing import events, replay, shared_settings

HERE = os.path.dirname(os.path.abspath(__file__))
TRIAL = os.path.join(HERE, "data", "trial-0")
sys.path.insert(0, os.path.join(HERE, "..", "..", "examples", "learners"))
from quickstart import Quickstart  # noqa: E402


class Counting(Learner):
    name = "counting"
    settings = [Setting("k", 2, min=1, max=9, integer=True)]

    def configure(self, own: Mapping[str, float], shared: Mapping[str, float]) -> None:
        # No super() call: the package keeps the settings all the same.
        self.events = 0

    def handle(self, event: Event) -> None:
        self.events += 1

    def action_model(self) -> Coefficients:
        return [0.0, float(self.own["k"])]

    def sensor_model(self) -> Coefficients:
        return [float(self.events), 1.0]


def exchange(learner: type, lines: List[Dict[str, Any]]) -> List[Dict[str, Any]]:
    out = io.StringIO()
    run(learner, io.StringIO("".join(json.dumps(m) + "\n" for m in lines)), out)
    return [json.loads(line) for line in out.getvalue().splitlines()]


def test_the_version_is_the_testbeds() -> None:
    assert scasm_testbed.__version__ == "0.2.0"


def test_a_learner_without_handle_cannot_be_made() -> None:
    class Incomplete(Learner):  # no handle
        pass

    with pytest.raises(TypeError):
        Incomplete()  # type: ignore[abstract]


def test_the_protocol_loop_says_hello_takes_settings_and_answers_queries() -> None:
    said = exchange(
        Counting,
        [
            {"type": "settings", "protocol": 1, "settings": {"k": 3}, "shared": {"gamma": 0.999}},
            {"type": "command", "t_s": 0.0, "dt_s": 0.05, "command": 100.0},
            {"type": "reading", "t_s": 0.05, "obs_px": 20.0},
            {"type": "query"},
            {"type": "end"},
        ],
    )
    assert said[0] == hello(Counting)
    assert said[0]["settings"][0]["integer"] is True
    assert said[1] == {"type": "models", "action": [0.0, 3.0], "sensor": [2.0, 1.0], "x_a": None, "x_s": None}


def test_settings_reach_a_learner_whose_configure_does_not_call_super() -> None:
    learner = Counting()
    learner.set_up({}, {"gamma": 0.99})
    assert learner.own == {"k": 2} and learner.shared == {"gamma": 0.99}
    learner.set_up({"k": 5}, {})
    assert learner.own["k"] == 5 and learner.events == 0


def test_a_non_finite_model_is_refused_with_an_error_line() -> None:
    class Nan(Counting):
        name = "nan"

        def action_model(self) -> Coefficients:
            return [math.nan]

    with pytest.raises(SystemExit):
        exchange(Nan, [{"type": "settings", "protocol": 1, "settings": {}, "shared": {}}, {"type": "query"}])


def test_a_learner_with_a_posterior_says_so_and_answers_it() -> None:
    class Sure(Counting):
        name = "sure"

        def posterior(self, draws: int) -> Optional[List[Draw]]:
            return [Draw([0.0, 1.0 + 0.01 * k], [(10.0, 3.0), (20.0, 1.5)]) for k in range(draws)]

    assert "posterior" not in hello(Counting)
    said = exchange(
        Sure,
        [
            {"type": "settings", "protocol": 1, "settings": {}, "shared": {}},
            {"type": "query"},
            {"type": "posterior", "draws": 2},
            {"type": "end"},
        ],
    )
    assert said[0]["posterior"] is True
    assert said[2] == {
        "type": "posterior",
        "draws": [
            {"action": [0.0, 1.0], "sensor": [[10.0, 3.0], [20.0, 1.5]]},
            {"action": [0.0, 1.01], "sensor": [[10.0, 3.0], [20.0, 1.5]]},
        ],
    }

    class Unsorted(Sure):
        def posterior(self, draws: int) -> Optional[List[Draw]]:
            return [Draw([0.0, 1.0], [(20.0, 1.5), (10.0, 3.0)])]

    with pytest.raises(SystemExit):
        exchange(Unsorted, [{"type": "settings", "protocol": 1, "settings": {}, "shared": {}}, {"type": "posterior", "draws": 1}])


def test_a_recorded_trial_replays_to_a_learner_in_process() -> None:
    frames = sum(1 for e in events(TRIAL) if isinstance(e, Command))
    readings = sum(1 for e in events(TRIAL) if isinstance(e, Reading))
    assert frames == 1200 and 0 < readings <= frames
    assert shared_settings(TRIAL)["sensor_degree"] == 3
    answers = replay(Quickstart, TRIAL)
    assert len(answers) == frames
    last = answers[-1]
    assert last.action == [0.0, 1.0] and last.sensor is not None and len(last.sensor) == 2
    # Its own setting reaches it.
    assert replay(Quickstart, TRIAL, own={"gain": 2.0})[-1].action == [0.0, 2.0]
    # Its location grows as it walks forwards, towards the beacon, which then
    # looks taller: the fitted line rises with the reading.
    assert last.sensor[1] > 0
    none: Optional[List[float]] = answers[0].sensor
    assert none is None
