"""The locomotion generator's CoM obeys eq. (1) of paper 001 in every gait and across every switch,
is C1 continuous, is ballistic in flight, keeps the ZMP inside the (rotated) support polygon, and
walks without flight but runs with it. Every check is computed from the file arrays with code
independent of the generator (tests/physics.py: solve_ivp re-integration, convex hulls)."""

from __future__ import annotations

import itertools

import numpy as np

import physics

G = 9.81


def test_eq1_holds_at_every_support_sample(tour):
    _, d = tour
    assert physics.eq1_error(d, G) < 1e-9


def test_point_mass_zmp_identity_holds_at_every_stance_sample(tour):
    _, d = tour
    sup = d["phase"] != 2
    p, a, c = d["com_pos"][sup], d["com_acc"][sup], d["zmp"][sup]
    zmp = p[:, :2] - ((p[:, 2] - c[:, 2]) / (a[:, 2] + G))[:, None] * a[:, :2]
    assert np.max(np.abs(zmp - c[:, :2])) < 1e-9


def test_flight_is_ballistic_and_has_no_zmp(tour):
    _, d = tour
    fl = d["phase"] == 2
    assert fl.any()
    assert physics.flight_error(d, G) < 1e-12
    assert np.all(np.isnan(d["zmp"][fl]))
    assert not d["contact"][fl].any()


def test_reintegrating_eq1_reproduces_the_plan_within_and_across_every_switch(tour):
    _, d = tour
    within, across = physics.ode_errors(d, G)
    assert within < 1e-6
    assert across < 1e-6


def test_com_is_c1_continuous(tour):
    _, d = tour
    vel_err, _, _ = physics.finite_difference_errors(d)
    assert vel_err < 1e-3
    dt = d["t"][1] - d["t"][0]
    # no position jump larger than one step of the fastest motion
    jumps = np.linalg.norm(np.diff(d["com_pos"], axis=0), axis=1)
    assert np.max(jumps) < 2.5 * dt * np.max(np.linalg.norm(d["com_vel"], axis=1))


def test_zmp_stays_inside_the_rotated_support_polygon(tour):
    _, d = tour
    assert physics.zmp_outside_polygon(d, d["meta"]["foot_size"]) <= 1e-9


def test_walking_steps_have_no_flight_and_running_steps_have_flight(tour):
    _, d = tour
    gait, ph = d["gait"], d["phase"]
    assert not np.any(ph[gait == 1] == 2)
    # every running step (SS start to SS start) contains flight
    s = np.flatnonzero((ph[1:] == 1) & (ph[:-1] != 1)) + 1
    runs = [(a, b) for a, b in itertools.pairwise(s) if np.all(gait[a:b] == 2)]
    assert runs
    assert all(np.any(ph[a:b] == 2) for a, b in runs)


def test_plan_starts_and_ends_at_rest(tour):
    _, d = tour
    assert np.abs(d["com_vel"][0]).max() == 0.0
    assert np.abs(d["com_vel"][-1]).max() < 1e-9
    assert np.abs(d["com_acc"][-1]).max() < 1e-9


def test_feet_are_c1_smooth_and_still_while_in_contact(tour):
    """Sole positions and yaws have no jump or kink: their second differences stay at the size a
    smooth swing gives (acceleration x dt^2, ~1e-4 here), while a jump of even 0.01 rad or 1 cm would
    show as that much; a sole in contact does not move or turn."""
    _, d = tour
    yaw = np.unwrap(d["foot_yaw"], axis=0)
    pos = d["foot_pos"]
    assert np.max(np.abs(np.diff(yaw, 2, axis=0))) < 1e-3
    assert np.max(np.abs(np.diff(pos, 2, axis=0))) < 1e-3
    c = d["contact"]
    still = c[1:] & c[:-1]
    for s in (0, 1):
        assert np.max(np.abs(np.diff(yaw[:, s])[still[:, s]]), initial=0.0) < 1e-12
        assert np.max(np.abs(np.diff(pos[:, s], axis=0)[still[:, s]]), initial=0.0) < 1e-12
