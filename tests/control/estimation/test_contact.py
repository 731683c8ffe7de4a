"""Contact detector: the Schmitt trigger switches at on/off fractions of the weight, ignores noise
between them (hysteresis), and waits ``debounce`` consecutive ticks (spikes shorter than that are
ignored); bad settings raise InputError."""

from __future__ import annotations

import numpy as np
import pytest

from gaitshift.control.estimation import ContactDetector, FootForces
from gaitshift.errors import InputError

WEIGHT = 330.0  # N, the G1


def _feed(det: ContactDetector, left: list[float]) -> list[bool]:
    return [bool(det.update(FootForces(np.array([f, 0.0])))[0]) for f in left]


def test_switches_on_and_off_at_the_thresholds_after_the_debounce():
    det = ContactDetector(WEIGHT, on_fraction=0.2, off_fraction=0.05, debounce=3)
    on, off = 0.2 * WEIGHT, 0.05 * WEIGHT
    flags = _feed(det, [on + 1] * 3 + [off - 1] * 3)
    assert flags == [False, False, True, True, True, False]


def test_hysteresis_band_keeps_the_state():
    det = ContactDetector(WEIGHT, on_fraction=0.2, off_fraction=0.05, debounce=1)
    mid = 0.1 * WEIGHT  # between the thresholds
    assert _feed(det, [mid] * 5) == [False] * 5
    det.reset((True, False))
    assert _feed(det, [mid] * 5) == [True] * 5


def test_spikes_shorter_than_the_debounce_are_ignored():
    det = ContactDetector(WEIGHT, on_fraction=0.2, off_fraction=0.05, debounce=3)
    spike = [0.0, 0.0, WEIGHT, WEIGHT, 0.0, 0.0]  # 2 ticks over the threshold
    assert not any(_feed(det, spike))
    det.reset((True, True))
    dropout = [WEIGHT, 0.0, 0.0, WEIGHT, WEIGHT]  # 2 ticks of lost load
    assert all(_feed(det, dropout))


def test_noisy_force_near_the_on_threshold_toggles_at_most_once():
    det = ContactDetector(WEIGHT, on_fraction=0.2, off_fraction=0.05, debounce=2)
    rng = np.random.default_rng(0)
    forces = 0.2 * WEIGHT + rng.normal(0.0, 0.02 * WEIGHT, 500)  # noise << on - off gap
    flags = np.array(_feed(det, list(forces)))
    assert np.count_nonzero(np.diff(flags.astype(int))) <= 1


@pytest.mark.parametrize(
    ("kwargs", "field"),
    [
        ({"weight": 0.0}, "contact.weight"),
        ({"weight": WEIGHT, "on_fraction": 0.1, "off_fraction": 0.2}, "contact.off_fraction"),
        ({"weight": WEIGHT, "debounce": 0}, "contact.debounce"),
    ],
)
def test_bad_settings_raise_input_error(kwargs, field):
    with pytest.raises(InputError) as err:
        ContactDetector(**kwargs)
    assert err.value.field == field
