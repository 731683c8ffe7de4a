"""Fixtures of the locomotion tests."""

from __future__ import annotations

import pytest

from loco_checks import plan


@pytest.fixture(scope="module")
def tour():
    """Walk 0.5 m/s, turn left walking, run 1.5 m/s (auto switch), turn right running, walk 0.4, stop."""
    cmds = [
        {"t": 0.0, "vx": 0.5},
        {"t": 6.0, "vx": 0.5, "yaw_rate": 0.5},
        {"t": 10.0, "vx": 1.5},
        {"t": 16.0, "vx": 1.5, "yaw_rate": -0.5},
        {"t": 22.0, "vx": 0.4},
    ]
    return plan(cmds, 28.0)
