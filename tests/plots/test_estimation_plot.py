"""The estimate-against-truth figure (plots/estimation.py, issue 17): its attitude angles invert the
z-y-x rotation they name, its series show a known estimation error as that error (the yaw error wrapped
across +-pi), and ``gaitshift plot`` draws it from a simulation log, with a log that lacks the estimate
refused in one line, exit 2, and no file written."""

from __future__ import annotations

import json

import numpy as np
from scipy.spatial.transform import Rotation

from gaitshift.common.rotations import roll_pitch_yaw
from gaitshift.plots.estimation import estimate_vs_truth


def _quat_wxyz(euler_zyx: np.ndarray) -> np.ndarray:
    xyzw = Rotation.from_euler("ZYX", euler_zyx).as_quat()
    return np.concatenate([xyzw[:, 3:], xyzw[:, :3]], axis=1)


def test_roll_pitch_yaw_inverts_the_zyx_rotation():
    rng = np.random.default_rng(3)
    yaw = rng.uniform(-3.1, 3.1, 200)
    pitch = rng.uniform(-1.4, 1.4, 200)
    roll = rng.uniform(-3.1, 3.1, 200)
    q = _quat_wxyz(np.stack([yaw, pitch, roll], axis=1)) * 2.0  # not unit: normalised inside
    np.testing.assert_allclose(roll_pitch_yaw(q), np.stack([roll, pitch, yaw], axis=1), atol=1e-9)


def _log(n: int = 50) -> dict[str, np.ndarray]:
    t = np.arange(n) * 0.002
    truth = np.stack([np.full(n, 3.1), np.zeros(n), np.full(n, 0.05)], axis=1)  # yaw, pitch, roll
    est = truth + np.array([-6.2, 0.0, 0.02])  # yaw -3.1: 0.083 rad across the wrap, roll off by 0.02 rad
    qpos, est_qpos = np.zeros((n, 9)), np.zeros((n, 9))
    qpos[:, 0], est_qpos[:, 0] = t, t + 0.01
    qpos[:, 3:7], est_qpos[:, 3:7] = _quat_wxyz(truth), _quat_wxyz(est)
    qvel = np.zeros((n, 8))
    qvel[:, 0] = 0.5
    est_qvel = qvel + np.array([0.0, 0.03, 0.0, 0, 0, 0, 0, 0])
    contact = np.zeros((n, 2), bool)
    contact[:, 0] = True
    grf = np.zeros((n, 2, 3))
    grf[:, 0, 2] = 300.0
    est_contact = contact.copy()
    est_contact[:5, 1] = True
    return {
        "t": t,
        "qpos": qpos,
        "qvel": qvel,
        "contact": contact,
        "grf": grf,
        "est_qpos": est_qpos,
        "est_qvel": est_qvel,
        "est_contact": est_contact,
    }


def test_the_series_show_a_known_estimation_error_as_that_error():
    s = estimate_vs_truth(_log())
    np.testing.assert_allclose(s["vel_hat"] - s["vel"], [[0.0, 0.03, 0.0]] * 50, atol=1e-15)
    np.testing.assert_allclose(s["rpy_hat"][:, 0] - s["rpy"][:, 0], 0.02, atol=1e-9)
    np.testing.assert_allclose(s["yaw_error"], 2 * np.pi - 6.2, atol=1e-9)  # wrapped, not -6.2
    np.testing.assert_allclose(s["pos_hat"][:, 0] - s["pos"][:, 0], 0.01, atol=1e-15)
    assert np.all(s["contact"][:, 0]) and not np.any(s["contact"][:, 1])
    assert s["contact_hat"][:5, 1].all() and not s["contact_hat"][5:, 1].any()


def _write(path, arrays):
    meta = {"metrics": {"estimation": {"base_vel_rmse": 0.03, "tilt_rmse": 0.02, "yaw_drift": 0.08}}}
    np.savez(path, **arrays, fell=np.array(False), meta=np.array(json.dumps(meta)))


def test_gaitshift_plot_draws_the_estimate_of_a_simulation_log(cli, tmp_path):
    _write(tmp_path / "run.npz", _log())
    code, out, err = cli(["plot", str(tmp_path / "run.npz"), "--out", str(tmp_path / "figs")])
    assert code == 0, err
    assert out.strip() == f"wrote {tmp_path / 'figs' / 'sim_estimation.png'}"
    assert (tmp_path / "figs" / "sim_estimation.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_a_log_without_the_estimate_is_one_line_and_exit_2(cli, tmp_path):
    arrays = _log()
    del arrays["est_qpos"]
    _write(tmp_path / "old.npz", arrays)
    code, out, err = cli(["plot", str(tmp_path / "old.npz"), "--out", str(tmp_path / "figs")])
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and "input" in err and "missing est_qpos" in err and "Traceback" not in err
    assert not (tmp_path / "figs" / "sim_estimation.png").exists()
