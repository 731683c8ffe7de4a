"""Fused contact: without a plan and away from the ground level it is the force trigger; a sole that
rests at the ground level stays on through a force below the noise, and is released once it rises or
moves; an off sole resting at the ground switches on in the plan's stance only; a small sustained
load on a sole at the ground level is found by the CUSUM within its expected delay while pure noise
there rarely switches it on, and the same load above the ground band is left to the force trigger; in
the plan's swing the latest sample releases the sole at once, and so does a rise off the sole's own
stand; a sole that left the floor is on again as soon as it is back at the ground level (a landing),
whatever its force and the plan; a take-off seen by the IMU releases the soles that were on at once;
bad settings raise InputError."""

from __future__ import annotations

import numpy as np
import pytest

from gaitshift.control.estimation.contact import ContactDetector
from gaitshift.control.estimation.contact_fusion import (
    CUSUM_SHIFT,
    CUSUM_THRESHOLD,
    FLIGHT_OFF,
    FLIGHT_ON,
    LAND_SPEED,
    LIFT_HEIGHT,
    NEAR_HEIGHT,
    SWING_SPEED,
    ContactFusion,
)
from gaitshift.errors import InputError

WEIGHT = 330.0  # N, the G1
STD = 0.02 * WEIGHT  # force noise of one sample, N
ON, OFF = 4.0 * STD, 1.5 * STD
GROUND, HIGH = 0.0, 0.005  # m: the ground level, a sole 5 mm above it
TRUE, FALSE = np.array([True, True]), np.array([False, False])


def _fusion() -> ContactFusion:
    det = ContactFusion(ON, OFF, STD, window=1)
    det.reset((True, True))
    det.update(np.full(2, WEIGHT / 2), np.full(2, GROUND), np.zeros(2), TRUE)  # learns the ground level
    return det


def _run(det: ContactFusion, left: np.ndarray, z: float, planned: np.ndarray | None, vz: float = 0.0) -> np.ndarray:
    """Feed the left sole ``left`` (N per tick) at height z, the right sole loaded at the ground."""
    out = []
    for f in left:
        flags = det.update(np.array([f, WEIGHT / 2]), np.array([z, GROUND]), np.array([vz, 0.0]), planned)
        out.append(bool(flags[0]))
    return np.array(out)


def _trigger(forces: np.ndarray, state: bool) -> np.ndarray:
    """The plain force trigger (window 1)."""
    out = []
    for f in forces:
        state = f > OFF if state else f > ON
        out.append(state)
    return np.array(out)


def test_without_plan_and_off_the_ground_it_is_the_force_trigger():
    rng = np.random.default_rng(1)
    forces = np.clip(np.sin(np.linspace(0, 12, 600)), 0, None) * WEIGHT + rng.normal(0, STD, 600)
    assert np.array_equal(_run(_fusion(), forces, HIGH, None), _trigger(forces, True))


def test_a_resting_sole_stays_on_below_the_noise_and_is_released_when_it_rises():
    rng = np.random.default_rng(2)
    light = 0.005 * WEIGHT + rng.normal(0, STD, 300)  # 1.6 N: below what the force can tell
    assert _run(_fusion(), light, GROUND, TRUE).all()  # the plan's stance, resting
    assert _run(_fusion(), light, GROUND, FALSE).all()  # on and resting: kept in the plan's swing too
    raised = _run(_fusion(), light, HIGH, TRUE)  # 5 mm above the ground level
    assert not raised[5:].any()
    moving = _run(_fusion(), light, GROUND, TRUE, vz=0.3)  # not resting: the force (and its CUSUM) decide
    assert not moving[0] and moving.mean() < 0.2
    unplanned = _off_at_the_ground()
    assert _run(unplanned, np.zeros(1), GROUND, TRUE)[0]  # resting at the ground in the plan's stance: on
    swing = _off_at_the_ground()
    assert not _run(swing, np.zeros(1), GROUND, FALSE)[0]  # the same in the plan's swing: the force decides


def _off_at_the_ground() -> ContactFusion:
    """A fusion whose left sole was switched off at the ground level without rising (not armed)."""
    det = _fusion()
    assert not _run(det, np.zeros(1), GROUND, FALSE, vz=0.3)[0]  # unloaded, moving: off where it stood
    return det


def test_a_sole_that_left_the_floor_is_on_when_it_comes_back_to_the_ground_level():
    """A landing: a sole that rose more than LIFT_HEIGHT switches on at the first tick its lowest point
    is back within the ground band, with no force and in the plan's swing (a graze before the planned
    touch-down), stays on there while its force stays below the noise, and is off again once it rises
    out of the band (a bounce) or moves faster than a loaded sole can; a sole landing on a tread
    above the ground level, one that never left the floor, or one landing from a flight (the other
    sole off too), or one passing the ground level faster than LAND_SPEED on its way down a stair is left
    to the force."""
    band = 0.5 * NEAR_HEIGHT
    det = _fusion()
    _run(det, np.zeros(3), HIGH, FALSE)  # lifted: off, armed
    assert not _run(det, np.zeros(3), 2 * NEAR_HEIGHT, FALSE, vz=-0.1).any()  # descending, not yet in the band
    assert _run(det, np.full(40, 0.2 * STD), band, FALSE, vz=-0.1).all()  # landed: held on below the noise
    assert not _run(det, np.zeros(2), 2 * NEAR_HEIGHT, FALSE, vz=0.1).any()  # out of the band again: off
    fast = _fusion()
    _run(fast, np.zeros(3), HIGH, FALSE)
    flags = [fast.update(np.array([0.0, WEIGHT / 2]), np.array([band, GROUND]), np.zeros(2), FALSE,
                         np.array([1.5 * SWING_SPEED, 0.0]))[0] for _ in range(2)]  # fmt: skip
    assert flags == [False, False]  # the veto: faster than a loaded sole moves
    tread = _fusion()
    _run(tread, np.zeros(3), 0.1 + HIGH, FALSE)
    assert not _run(tread, np.zeros(3), 0.1, FALSE).any()  # on a tread 10 cm up, unloaded: the force decides
    assert not _run(_off_at_the_ground(), np.zeros(3), band, FALSE).any()  # never left the floor
    passing = _fusion()
    _run(passing, np.zeros(3), HIGH, FALSE)
    fast = -1.5 * LAND_SPEED  # through the ground level on its way down a stair: no landing
    assert not _run(passing, np.zeros(2), band, FALSE, vz=fast).any()
    flight = _fusion()
    for z in (HIGH, band, band):  # both soles off the floor (a running flight): the ground level is a memory
        flags = flight.update(np.zeros(2), np.array([z, HIGH]), np.zeros(2), FALSE)
    assert not flags.any()


def test_a_graze_at_the_ground_level_is_found_and_noise_is_not():
    rng = np.random.default_rng(3)
    det = _off_at_the_ground()  # off, in swing, not armed (a landing would switch it on at once)
    graze = 1.0 * STD + rng.normal(0, STD, 200)  # 6.6 N sustained: below the on threshold (26 N)
    flags = _run(det, graze, GROUND, FALSE)
    first = int(np.argmax(flags))
    d = CUSUM_SHIFT  # expected delay ~ h / (d (mu - d / 2)) in units of sigma: 2 / 0.45 = 4.4 ticks
    assert flags.any() and first <= 4 * CUSUM_THRESHOLD / (d * (1.0 - d / 2))
    high = _fusion()
    _run(high, np.zeros(3), HIGH, FALSE)
    assert np.array_equal(_run(high, graze, HIGH, FALSE), _trigger(graze, False))  # the force trigger alone
    noise = _off_at_the_ground()
    ons = 0
    for f in rng.normal(0, STD, 4000):  # an unloaded sole at the ground level, switched back off by hand
        if _run(noise, np.array([f]), GROUND, FALSE, vz=0.3)[0]:
            ons += 1
            _run(noise, np.zeros(1), GROUND, FALSE, vz=0.3)
    assert ons / 4000 < 0.05  # Page's CUSUM, h = 2, d = 0.7 s: one false alarm per ~50 ticks at the ground


def test_the_plans_swing_releases_on_the_latest_sample():
    det = ContactFusion(ON, OFF, STD, window=2)
    det.reset((True, True))
    loaded = np.array([1.5 * WEIGHT, 0.0])
    assert list(_run(det, loaded, HIGH, FALSE)) == [True, False]  # the mean (0.75 W) lags; the sample does not
    det.reset((True, True))
    assert list(_run(det, loaded, HIGH, TRUE)) == [True, True]  # in the plan's stance the mean decides


def test_a_sole_that_rose_off_its_floor_in_the_plans_swing_is_off_whatever_its_lagging_force():
    """A rigid floor does not let a loaded sole rise: in the plan's swing a sole whose lowest point rose
    more than LIFT_HEIGHT above where it stood, still rising, is off although its (lagging) force reads
    the weight; in the plan's stance, or not rising, or risen less, the force decides; a sole standing
    on a higher tread (far above the ground level, at its own stand) keeps its contact."""
    loaded = np.full(3, WEIGHT / 2)
    risen = GROUND + 1.5 * LIFT_HEIGHT
    assert not _run(_fusion(), loaded, risen, FALSE, vz=0.3).any()
    assert _run(_fusion(), loaded, risen, TRUE, vz=0.3).all()  # the plan's stance: the force decides
    assert _run(_fusion(), loaded, risen, FALSE, vz=0.0).all()  # not rising
    assert _run(_fusion(), loaded, GROUND + 0.5 * LIFT_HEIGHT, FALSE, vz=0.3).all()  # risen less
    tread = ContactFusion(ON, OFF, STD, window=1)
    tread.reset((True, True))
    step = 0.1  # the left sole on a tread 10 cm above the right one, both loaded and still
    tread.update(np.full(2, WEIGHT / 2), np.array([step, GROUND]), np.zeros(2), TRUE)
    assert _run(tread, loaded, step, FALSE, vz=0.3).all()  # rolling on its toe: still at its own stand
    assert not _run(tread, loaded, step + 1.5 * LIFT_HEIGHT, FALSE, vz=0.3).any()


def test_a_sole_faster_than_a_loaded_one_can_move_is_off_in_the_plans_swing_and_releases_the_trigger():
    """A loaded sole on a rigid floor is still (or slides, or rolls over its toe, its centre slower than
    SWING_SPEED): a sole of the plan's swing whose centre moves faster carries nothing, whatever a force
    reads; the force trigger it feeds is released at the next tick. In the plan's stance, slower, or
    without a plan, the force decides."""
    loaded = np.full(3, WEIGHT / 2)
    fast, slow = np.array([1.5 * SWING_SPEED, 0.0]), np.array([0.5 * SWING_SPEED, 0.0])
    for speed, plan, expected in ((fast, FALSE, False), (fast, TRUE, True), (slow, FALSE, True), (fast, None, True)):
        det = _fusion()
        flags = [det.update(loaded[:2], np.full(2, HIGH), np.zeros(2), plan, speed)[0] for _ in range(3)]
        assert flags == [expected] * 3
        assert det.veto[0] is (not expected) and not det.veto[1]
    trigger = ContactDetector(WEIGHT, ON / WEIGHT, OFF / WEIGHT, debounce=1)
    trigger.reset((True, True))
    trigger.release([True, False])
    assert trigger.contact.tolist() == [False, True]
    assert trigger.update_values([WEIGHT / 2, WEIGHT / 2]) == (True, True)  # the force switches it on again


def test_a_take_off_seen_by_the_imu_releases_the_soles_on_at_once_and_leaves_a_landing_to_the_force():
    """In a flight the pelvis's vertical specific force falls below FLIGHT_ON g: the sole that was on (in
    the plan's swing) is off at that tick although its lagging force still reads the weight; a sole that
    comes on during the flight (a landing, the pelvis still below 0 g) is left to its force; the flight
    lasts until the specific force rises above FLIGHT_OFF g (a brief rise below it does not start a new
    flight that would release the landing sole), and then the lagging force decides again. In the plan's
    stance, or without the specific force, the flight rule does nothing."""
    g = 9.81
    take_off = np.array([False, False])  # the left sole lifts (the plan's swing), the right one swings
    plan_right = np.array([False, True])  # later: the right sole's stance is due
    load, swinging, at = np.array([WEIGHT, 0.0]), np.array([GROUND, HIGH]), np.full(2, GROUND)
    det = _fusion()
    assert det.update(load, swinging, np.zeros(2), take_off, specific_force=1.5 * g).tolist() == [True, False]
    assert not det.flight
    assert det.update(load, swinging, np.zeros(2), take_off, specific_force=-0.3 * g).tolist() == [False, False]
    assert det.flight and det.airborne == [True, False] and det.veto == [True, False]
    landing = np.array([WEIGHT, 0.2 * WEIGHT])  # the left sole's force still lags; the right one lands
    assert det.update(landing, at, np.zeros(2), take_off, specific_force=-0.05 * g).tolist() == [False, True]
    assert det.update(landing, at, np.zeros(2), plan_right, specific_force=0.2 * g).tolist() == [False, True]
    assert det.flight  # below FLIGHT_OFF g: still the same flight, the landing sole kept
    assert det.update(landing, at, np.zeros(2), plan_right, specific_force=0.5 * g).tolist() == [True, True]
    assert not det.flight and det.airborne == [False, False]  # the lagging force decides again
    for plan, a_v in ((np.array([True, False]), -0.3 * g), (take_off, None)):
        other = _fusion()
        other.update(load, swinging, np.zeros(2), plan, specific_force=1.5 * g)
        assert other.update(load, swinging, np.zeros(2), plan, specific_force=a_v)[0]
    assert FLIGHT_ON < 0.0 < FLIGHT_OFF


@pytest.mark.parametrize(
    ("args", "field"),
    [
        ((OFF, ON, STD), "contact.off_force"),
        ((ON, OFF, 0.0), "contact.force_std"),
        ((ON, OFF, STD, 0), "contact.window"),
    ],
)
def test_bad_settings_raise(args, field):
    with pytest.raises(InputError, match=field):
        ContactFusion(*args)
