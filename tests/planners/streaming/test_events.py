"""Events round their time to 1e-9 s, store plain floats and serialise to strict JSON."""

import json

import numpy as np

from gaitshift.planners.streaming.events import Event


def test_events_are_plain_json():
    e = Event.at(0.1 + 0.2, "clamp_speed", "command.vx", np.float64(9.0), np.float64(1.5), "|v| <= 1.5")
    assert e.t == 0.3 and type(e.requested) is float and type(e.applied) is float
    d = json.loads(json.dumps(e.as_dict(), allow_nan=False))
    assert d == {
        "t": 0.3,
        "kind": "clamp_speed",
        "field": "command.vx",
        "requested": 9.0,
        "applied": 1.5,
        "note": "|v| <= 1.5",
    }
