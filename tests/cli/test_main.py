"""``gaitshift.cli.main``: user mistakes end in exit 2 with one line on stderr, help is a result, and
a stray EOFError (which click would turn into a silent exit 1) surfaces as the bug it is."""

import pytest

from gaitshift.cli import main
from gaitshift.cli.app import app
from gaitshift.errors import InputError


def test_no_arguments_prints_the_help_and_succeeds(cli):
    code, out, err = cli([])
    assert code == 0 and "plan" in out and "check" in out and err == ""


def test_usage_errors_are_one_line(cli):
    for argv in (["plan"], ["no-such-command"], ["stiffness", "--height", "abc"]):
        code, _, err = cli(argv)
        assert code == 2 and err.count("\n") == 1 and err.startswith("gaitshift: error: ")


@pytest.fixture
def probe_command():
    """A throw-away command registered for one test (removed after it)."""
    added = []

    def register(fn):
        app.command("probe-contract")(fn)
        added.append(app.registered_commands[-1])
        return fn

    yield register
    for info in added:
        app.registered_commands.remove(info)


def test_a_multi_line_message_is_printed_on_one_line(cli, probe_command):
    @probe_command
    def probe() -> None:
        raise InputError("field", "a\nb", "one\nline")

    code, _, err = cli(["probe-contract"])
    assert code == 2 and err == "gaitshift: error: field = 'a\\nb' is invalid: allowed one line\n"


def test_a_stray_eof_error_is_not_hidden_as_exit_1(cli, probe_command):
    @probe_command
    def probe() -> None:
        raise EOFError("bug")

    with pytest.raises(EOFError, match="bug"):
        main(["probe-contract"])
