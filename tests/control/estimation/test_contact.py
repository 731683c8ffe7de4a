"""Contact detector: the Schmitt trigger switches at on/off fractions of the weight, ignores noise
between them (hysteresis), and waits ``debounce`` consecutive ticks (spikes shorter than that are
ignored); the moving average halves a one-tick spike; thresholds derived from the force noise hold a
swing sole off through pure noise and release an unloaded sole at once; bad settings raise InputError."""

from __future__ import annotations

import numpy as np
import pytest

from gaitshift.control.estimation import ContactDetector, FootForces
from gaitshift.control.estimation.contact import noise_thresholds
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


def test_the_moving_average_halves_a_one_tick_spike():
    det = ContactDetector(WEIGHT, on_fraction=0.2, off_fraction=0.05, debounce=1, window=2)
    spike = [0.0, 0.3 * WEIGHT, 0.0, 0.0]  # the mean of two samples: 0.15 W < 0.2 W
    assert not any(_feed(det, spike))
    assert _feed(det, [0.3 * WEIGHT] * 2) == [False, True]  # a held load: on at the second sample


def test_noise_thresholds_scale_with_the_averaged_noise_and_hold_off_pure_noise():
    on1, off1 = noise_thresholds(0.02, 1)
    on4, off4 = noise_thresholds(0.02, 4)
    assert on4 == pytest.approx(on1 / 2) and off4 == pytest.approx(off1 / 2)
    assert noise_thresholds(0.0, 1)[0] > 0  # a noise-free signal keeps the sensor's resolution
    on, off = noise_thresholds(0.02, 2)
    det = ContactDetector(WEIGHT, on_fraction=on, off_fraction=off, debounce=1, window=2)
    rng = np.random.default_rng(0)
    unloaded = rng.normal(0.0, 0.02 * WEIGHT, 20000)  # a swing sole: noise only
    assert np.count_nonzero(_feed(det, list(unloaded))) <= 20  # a 4-sigma event: 3e-5 per tick
    det.reset((True, False))
    released = _feed(det, list(unloaded[:50]))
    assert released.index(False) <= 5  # an unloaded sole is released at once (Phi(1.5) = 0.93 per tick)
