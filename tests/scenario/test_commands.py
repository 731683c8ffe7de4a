"""The teleop command-script format: tokens, their speed steps, waits in [0, 3600] s, and one
InputError naming the flag (or stdin) and the token for anything else."""

import pytest

from gaitshift.errors import InputError
from gaitshift.scenario.commands import ACTIONS, KEY_STEP, KEYS, MAX_WAIT, parse_script


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


def test_arrows_step_the_speed_command_by_key_step():
    assert KEYS["up"] == (KEY_STEP, 0.0) and KEYS["down"] == (-KEY_STEP, 0.0)
    assert KEYS["left"] == (0.0, KEY_STEP) and KEYS["right"] == (0.0, -KEY_STEP)


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
