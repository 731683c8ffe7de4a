"""The trajectory contract: every format round-trips every key, writes are atomic, and each rule of
the contract (keys, shapes, dtypes, value sets, NaN placement, magnitudes, uniform time, meta,
extras) is enforced with one message naming the source, the key and the value."""

import json

import numpy as np
import pytest

import gaitshift
from gaitshift.errors import InputError, TrajectoryFileError
from gaitshift.trajectory.contract import CONTRACT_KEYS, FLIGHT, SS, Trajectory


@pytest.fixture(scope="module")
def traj():
    sc = gaitshift.load_scenario(
        {"gait": [{"gait": "walk", "steps": 1}, {"gait": "run", "steps": 2}, {"gait": "walk", "steps": 2}], "dt": 0.01}
    )
    return gaitshift.plan(sc)


@pytest.mark.parametrize("suffix", [".npz", ".csv", ".json"])
def test_every_format_round_trips_every_contract_key(traj, tmp_path, suffix):
    path = traj.save(tmp_path / f"plan{suffix}")
    back = Trajectory.load(path)
    for key in CONTRACT_KEYS:
        if key == "meta":
            assert back.meta == json.loads(json.dumps(traj.meta))
            continue
        a, b = getattr(traj, key), getattr(back, key)
        assert a.shape == b.shape and a.dtype == b.dtype, key
        np.testing.assert_array_equal(
            np.isnan(a) if a.dtype.kind == "f" else a, np.isnan(b) if b.dtype.kind == "f" else b
        )
        if a.dtype.kind == "f":
            np.testing.assert_allclose(a[np.isfinite(a)], b[np.isfinite(b)], rtol=1e-12, atol=0)


def test_npz_matches_the_documented_key_shapes_and_types(traj, tmp_path):
    path = traj.save(tmp_path / "plan.npz")
    with np.load(path) as z:
        n, m = len(z["t"]), len(z["footsteps"])
        shapes = {
            "t": (n,),
            "com_pos": (n, 3),
            "com_vel": (n, 3),
            "com_acc": (n, 3),
            "zmp": (n, 3),
            "phase": (n,),
            "contact": (n, 2),
            "foot_pos": (n, 2, 3),
            "stiffness": (n,),
            "footsteps": (m, 4),
            "footstep_side": (m,),
            "command_vel": (n, 2),
            "meta": (),
        }
        for key, shape in shapes.items():
            assert z[key].shape == shape, key
        assert z["phase"].dtype == np.int8 and z["footstep_side"].dtype == np.int8
        assert z["contact"].dtype == bool
        meta = json.loads(str(z["meta"]))
        assert meta["planner"] == "tvlip" and meta["gravity"] == 9.81 and len(meta["foot_size"]) == 2
        assert "scenario" in meta
        assert np.allclose(np.diff(z["t"]), z["t"][1] - z["t"][0])


def test_unknown_suffix_is_rejected_and_writes_nothing(traj, tmp_path):
    with pytest.raises(InputError, match="out"):
        traj.save(tmp_path / "plan.txt")
    assert list(tmp_path.iterdir()) == []


def test_failed_write_leaves_no_partial_file(traj, tmp_path, monkeypatch):
    def boom(*a, **k):
        raise OSError("disk full")

    monkeypatch.setattr(np, "savez_compressed", boom)
    with pytest.raises(OSError):
        traj.save(tmp_path / "plan.npz")
    assert list(tmp_path.iterdir()) == []


def test_csv_keeps_text_that_contains_nan(tmp_path):
    sc = gaitshift.load_scenario(
        {"description": "Hanasaki and Tazaki, nan-free", "gait": [{"gait": "walk", "steps": 1}], "dt": 0.02}
    )
    back = Trajectory.load(gaitshift.plan(sc).save(tmp_path / "p.csv"))
    assert back.meta["scenario"]["description"] == "Hanasaki and Tazaki, nan-free"


# ---------------------------------------------------------------------- the rules, one by one
def _broken(traj, edit):
    arrays = {k: np.array(v) for k, v in traj.arrays().items()}
    meta = json.loads(json.dumps(traj.meta))
    result = edit(arrays, meta)
    if isinstance(result, tuple) and result[0] == "new meta":
        meta = result[1]
    with pytest.raises(TrajectoryFileError) as exc:
        Trajectory.from_arrays(arrays, meta, source="plan.npz")
    return exc.value


def _set(key, index, value):
    def edit(arrays, meta):
        arrays[key] = arrays[key].astype(float)
        arrays[key][index] = value

    return edit


def _first(traj, phase):
    return int(np.flatnonzero(traj.phase == phase)[0])


RULES = {
    "missing key": (lambda a, m: a.pop("com_vel"), "com_vel", "missing"),
    "wrong shape": (lambda a, m: a.update(com_pos=a["com_pos"][:, :2]), "com_pos", "(N = len(t))"),
    "strings": (lambda a, m: a.update(com_acc=a["com_acc"].astype(str)), "com_acc", "dtype <U"),
    "complex": (lambda a, m: a.update(zmp=a["zmp"].astype(complex)), "zmp", "complex128"),
    "phase 7": (_set("phase", 3, 7), "phase", "values in {0, 1, 2}"),
    "phase 0.5": (_set("phase", 3, 0.5), "phase", "values in {0, 1, 2}"),
    "contact 2": (_set("contact", (3, 0), 2), "contact", "values in {0, 1}"),
    "NaN CoM": (_set("com_pos", (5, 0), np.nan), "com_pos", "NaN, "),
    "inf footstep": (_set("footsteps", (1, 2), np.inf), "footsteps", "Infinity, 0.0] at index 1"),
    "huge velocity": (_set("com_vel", (2, 1), 1e300), "com_vel", "within +/-1e+06"),
    "inf command": (_set("command_vel", (2, 1), np.inf), "command_vel", "or NaN"),
    "one sample": (
        lambda a, m: a.update({k: v[:1] for k, v in a.items() if k not in ("footsteps", "footstep_side")}),
        "t",
        "N >= 2",
    ),
    "t backwards": (lambda a, m: a.update(t=a["t"][::-1].copy()), "t", "dt in"),
    "t uneven": (_set("t", 4, 0.0305), "t", "uniform step"),
    "no foothold": (
        lambda a, m: a.update(footsteps=np.zeros((0, 4)), footstep_side=np.zeros(0)),
        "footsteps",
        "M >= 1",
    ),
    "meta not an object": (lambda a, m: ("new meta", [1, 2]), "meta", "a JSON object"),
    "meta gravity text": (lambda a, m: m.update(gravity="9.81"), "meta.gravity", "a number"),
    "meta foot size": (lambda a, m: m.update(foot_size=[0.2]), "meta.foot_size", "[length, width]"),
    "meta no planner": (lambda a, m: m.pop("planner"), "meta.planner", "missing"),
    "meta NaN": (lambda a, m: m.update(height=float("nan")), "meta.height", "finite numbers"),
    "extra text": (lambda a, m: a.update(note=np.array(["a"])), "note", "numbers"),
    "extra inf": (lambda a, m: a.update(gain=np.array([np.inf])), "gain", "numbers or NaN"),
    "extra bad name": (lambda a, m: a.update({"a,b": np.zeros(2)}), "extra key", "'a,b'"),
    "boundary_t NaN": (lambda a, m: a.update(boundary_t=np.array([0.0, np.nan])), "boundary_t", "NaN at index 1"),
}


@pytest.mark.parametrize("rule", sorted(RULES))
def test_each_broken_rule_names_the_source_key_and_value(traj, rule):
    edit, key, fragment = RULES[rule]
    err = _broken(traj, edit)
    assert isinstance(err, InputError) and isinstance(err, ValueError)
    assert err.source == "plan.npz" and err.key == key, str(err)
    assert str(err).startswith(f"plan.npz: {key} = ") and fragment in str(err), str(err)
    assert "\n" not in str(err)


def test_zmp_and_stiffness_may_be_nan_in_flight_only(traj):
    flight, support = _first(traj, FLIGHT), _first(traj, SS)
    assert np.isnan(traj.zmp[flight]).all() and np.isnan(traj.stiffness[flight])
    for key in ("zmp", "stiffness"):
        index = (support, 0) if key == "zmp" else support
        err = _broken(traj, _set(key, index, np.nan))
        assert err.key == key and "(phase SS)" in str(err) and "NaN only in flight" in str(err)


def test_contact_must_match_the_phase(traj):
    support = _first(traj, SS)

    def both_down(arrays, meta):
        arrays["contact"][support] = [True, True]

    err = _broken(traj, both_down)
    assert err.key == "contact" and "phase SS" in str(err) and "one in SS" in str(err)


def test_arrays_built_in_memory_name_Trajectory_as_the_source(traj):
    arrays = traj.arrays()
    arrays["com_pos"] = arrays["com_pos"][:, :2]
    with pytest.raises(TrajectoryFileError, match=r"^Trajectory: com_pos = shape"):
        Trajectory.from_arrays(arrays, traj.meta)


def test_loading_keeps_integer_and_boolean_dtypes(traj, tmp_path):
    for suffix in (".csv", ".json"):
        back = Trajectory.load(traj.save(tmp_path / f"p{suffix}"))
        assert back.phase.dtype == np.int8 and back.contact.dtype == bool and back.footstep_side.dtype == np.int8
