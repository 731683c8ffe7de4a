"""The typer application that every ``gaitshift.cli.*`` command module registers on."""

import typer

app = typer.Typer(
    name="gaitshift",
    help="Walking, running and walk-run transitions for biped robots.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
