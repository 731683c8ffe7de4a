"""The teleop command-script format: tokens, their speed steps, waits in [0, 3600] s, and one
InputError naming the flag (or stdin) and the token for anything else."""

import pytest

from gaitshift.errors import InputError
from gaitshift.scenario.commands import ACTIONS, KEYS, LOCOMOTION_STEP, MAX_WAIT, VHIP_STEP, key_change, parse_script


def test_tokens_are_parsed_in_order_with_any_separator_and_case():
    assert parse_script("up, DOWN wait=0.5 wait:1e-1;stop\nquit") == [
        ("up", 0.0),
        ("down", 0.0),
        ("wait", 0.5),
        ("wait", 0.1),
        ("stop", 0.0),
        ("quit", 0.0),
    ]
    assert parse_script("   ") == []


def test_one_key_table_steps_each_generator_by_its_own_step():
    assert key_change("up", VHIP_STEP) == (VHIP_STEP[0], 0.0, 0.0) and key_change("down", VHIP_STEP)[0] == -0.3
    assert key_change("left", VHIP_STEP) == (0.0, VHIP_STEP[1], 0.0)
    assert key_change("right", LOCOMOTION_STEP) == (0.0, -LOCOMOTION_STEP[1], 0.0)
    assert key_change("turn-left", LOCOMOTION_STEP) == (0.0, 0.0, LOCOMOTION_STEP[2])
    assert key_change("turn-right", VHIP_STEP) == (0.0, 0.0, 0.0)  # paper 003 has no yaw-rate command
    assert set(ACTIONS) == {*KEYS, "stop", "quit"}


@pytest.mark.parametrize(
    "tok", ["wait=-1", "wait=nan", "wait=inf", "wait=1e999", f"wait={MAX_WAIT + 1}", "wait=", "wait=x"]
)
def test_bad_waits_name_the_token_and_the_range(tok):
    with pytest.raises(InputError) as exc:
        parse_script(f"up {tok}")
    assert exc.value.field == "--script" and exc.value.value == tok and "0 <= seconds <= 3600" in exc.value.allowed


def test_unknown_token_names_the_source_and_lists_the_tokens():
    with pytest.raises(InputError) as exc:
        parse_script("up jump", field="stdin")
    msg = str(exc.value)
    assert msg.startswith("stdin = 'jump' is invalid: allowed tokens ") and "\n" not in msg
    for token in (*ACTIONS, "wait=<seconds>"):
        assert token in msg


def test_long_tokens_are_clipped_in_the_message():
    with pytest.raises(InputError) as exc:
        parse_script("x" * 10_000)
    assert len(str(exc.value)) < 200
