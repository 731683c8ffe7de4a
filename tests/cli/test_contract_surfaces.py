"""The error contract per surface, with hypothesis (issue 28): the random case builders of
benchmarks/contract_sample.py, driven by a shrinkable ``Random`` (``st.randoms``), run in-process and
classified by the sample's own rules. A case must end in a result (exit 0/1, every promised file
written whole and loadable, finite JSON) or one line ``gaitshift: error: <field> = ...`` naming a field
of that input with exit 2 and no file left behind; never a traceback, another exception, a NumPy
RuntimeWarning, NaN in the output or a run past its time limit.

Surfaces (the ones tests/cli/test_contract_fuzz.py does not cover): locomotion scenario YAML, robot YAML
(``robot check``), campaign specs (``load_spec`` + expansion, and the command line), ``campaign report``
over damaged folders, ``simulate`` flags and other commands' flags (refused before any simulation or
IK), output names of every writer, the joints file of ``animate``, and the public Python API. The last
test runs the sample itself on 30 cases, so the benchmark's own code is exercised.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))

import contract_api
import contract_cases as cc
import contract_flags as cf
import contract_sample

SURFACE = settings(
    derandomize=True,
    deadline=None,
    database=None,
    print_blob=False,
    suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow],
)
#: per case, s (the slowest valid case, a robot check, takes about 1 s)
TIMEOUT = 20.0


@pytest.fixture(scope="module")
def base(tmp_path_factory) -> cc.Base:
    return cc.Base.make(tmp_path_factory.mktemp("contract-base"))


def _holds(builder, rng, base: cc.Base, tmp_path: Path) -> contract_sample.Outcome:
    folder = Path(tempfile.mkdtemp(dir=tmp_path))
    case = builder(rng, folder, base)
    outcome = contract_sample.run_case(case, folder, TIMEOUT)
    assert outcome.kind != "BAD", f"{case.argv or case.note}: {outcome.why}"
    return outcome


@settings(SURFACE, max_examples=50)
@given(rng=st.randoms(use_true_random=False))
def test_locomotion_scenarios_plan_or_refuse_in_one_line(rng, base, tmp_path):
    _holds(cc.locomotion_case, rng, base, tmp_path)


@settings(SURFACE, max_examples=10)
@given(rng=st.randoms(use_true_random=False))
def test_robot_yamls_check_or_refuse_in_one_line(rng, base, tmp_path):
    _holds(cc.robot_case, rng, base, tmp_path)


@settings(SURFACE, max_examples=80)
@given(rng=st.randoms(use_true_random=False))
def test_campaign_specs_expand_or_refuse_in_one_line(rng, base, tmp_path):
    _holds(cc.spec_case, rng, base, tmp_path)


@settings(SURFACE, max_examples=12)
@given(rng=st.randoms(use_true_random=False))
def test_campaign_reports_over_damaged_folders(rng, base, tmp_path):
    _holds(cc.report_case, rng, base, tmp_path)


@settings(SURFACE, max_examples=40)
@given(rng=st.randoms(use_true_random=False))
def test_simulate_flags_are_refused_before_any_simulation(rng, base, tmp_path):
    assert _holds(cf.simulate_case, rng, base, tmp_path).kind == "refused"


@settings(SURFACE, max_examples=40)
@given(rng=st.randoms(use_true_random=False))
def test_other_commands_flags_are_refused_before_any_work(rng, base, tmp_path):
    assert _holds(cf.flags_case, rng, base, tmp_path).kind == "refused"


@settings(SURFACE, max_examples=50)
@given(rng=st.randoms(use_true_random=False))
def test_output_names_of_every_writer(rng, base, tmp_path):
    _holds(cf.out_name_case, rng, base, tmp_path)


@settings(SURFACE, max_examples=30)
@given(rng=st.randoms(use_true_random=False))
def test_damaged_joints_files_are_one_line(rng, base, tmp_path):
    assert _holds(cc.joints_case, rng, base, tmp_path).kind == "refused"


@settings(SURFACE, max_examples=120)
@given(rng=st.randoms(use_true_random=False))
def test_python_api_ends_in_a_result_or_one_input_error(rng, base, tmp_path):
    _holds(contract_api.api_case, rng, base, tmp_path)


def test_the_sample_classifies_30_cases(tmp_path):
    """The benchmark end to end on 30 cases: every case classified, none BAD, counts add up."""
    summary = contract_sample.sample(30, seed=1, timeout=TIMEOUT, work=tmp_path, log=lambda _: None)
    assert summary["bad"] == [] and summary["cases"] == 30
    assert sum(summary["totals"].values()) == 30 and set(summary["totals"]) <= {"result", "refused"}
    assert summary["totals"].get("refused", 0) > 0


def test_the_classifier_catches_what_the_contract_forbids(tmp_path):
    """The rules can fail: a traceback, a second line, an unnamed field, a file left after a refusal,
    an empty output and NaN in JSON are each BAD."""
    classify = contract_sample.classify
    case = cc.Case("t", {"height"}, argv=["x"], outputs=(tmp_path / "o.npz",), extra={"json": True})
    line = "gaitshift: error: height = -1 is invalid: allowed > 0\n"
    assert classify(case, tmp_path, set(), 2, "", line).kind == "refused"
    assert classify(case, tmp_path, set(), 2, "", line + line).kind == "BAD"
    assert classify(case, tmp_path, set(), 2, "", line.replace("height", "width")).kind == "BAD"
    assert classify(case, tmp_path, set(), 2, "Traceback (most recent call last)", line).kind == "BAD"
    assert classify(case, tmp_path, set(), 3, "", "").kind == "BAD"
    (tmp_path / "o.npz").write_bytes(b"")
    assert classify(case, tmp_path, set(), 2, "", line).kind == "BAD"  # left after a refusal
    assert "empty" in classify(case, tmp_path, set(), 0, "{}", "").why
    (tmp_path / "o.npz").unlink()
    assert (
        classify(cc.Case("t", set(), argv=["x"], extra={"json": True}), tmp_path, set(), 0, '{"a": NaN}', "").kind
        == "BAD"
    )
