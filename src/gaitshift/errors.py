"""The exception hierarchy of gaitshift.

Every error a user can cause derives from :class:`GaitshiftError`. The CLI prints its message on one
line and exits with code 2; library callers catch the base class. Messages always name the field, the
offending value and what is allowed.
"""

from __future__ import annotations

from collections.abc import Iterable


class GaitshiftError(Exception):
    """Base class of every gaitshift error."""


class InputError(GaitshiftError, ValueError):
    """A user-supplied value is outside its allowed range.

    Args:
        field: dotted name of the offending field, e.g. ``timing.single_support``.
        value: the value that was given.
        allowed: a human-readable description of the allowed range or choices.
    """

    def __init__(self, field: str, value: object, allowed: str):
        self.field = field
        self.value = value
        self.allowed = allowed
        super().__init__(f"{field} = {value!r} is invalid: allowed {allowed}")


def number_in(field: str, value: object, bounds: tuple[float, float], unit: str = "") -> float:
    """``value`` as a float when it is a number (not a bool) in ``bounds`` (inclusive), else the
    :class:`InputError` "a number in [lo, hi] unit" naming ``field``."""
    lo, hi = bounds
    if isinstance(value, bool) or not isinstance(value, int | float) or not lo <= value <= hi:
        raise InputError(field, value, f"a number in [{lo:g}, {hi:g}]" + (f" {unit}" if unit else ""))
    return float(value)


def check_flag(field: str, value: object) -> bool:
    """``value`` when it is a bool, else the :class:`InputError` "true or false" naming ``field``."""
    if not isinstance(value, bool):
        raise InputError(field, value, "true or false")
    return value


def one_of(choices: Iterable[str]) -> str:
    """The allowed-text of a choice: ``"one of: a, b, c"``, in the given order."""
    return "one of: " + ", ".join(choices)


def check_choice(field: str, value: object, choices: Iterable[str]) -> str:
    """``value`` when it is one of ``choices`` (a string), else the :class:`InputError` "one of: ..."
    naming ``field``; an unhashable value (a list, a mapping) is refused the same way."""
    names = tuple(choices)
    if not isinstance(value, str) or value not in names:
        raise InputError(field, value, one_of(names))
    return value


class ScenarioError(InputError):
    """A scenario file or name is invalid (unknown key, wrong type, unknown built-in)."""


class TrajectoryFileError(InputError):
    """A trajectory (a file, or arrays handed to :class:`~gaitshift.trajectory.contract.Trajectory`)
    breaks the trajectory contract.

    Prints ``"<source>: <key> = <found> is invalid: allowed <allowed>"`` on one line.

    Args:
        source: the file path (or ``"Trajectory"`` for arrays built in memory).
        key: the contract key or file part at fault, e.g. ``com_pos``, ``meta.gravity``, ``row 12``.
        found: what was found, as text (a shape, a dtype, a value and where it is).
        allowed: what the contract allows there.
    """

    def __init__(self, source: str, key: str, found: str, allowed: str):
        super().__init__(f"{source}: {key}", found, allowed)
        self.source = source
        self.key = key
        self.args = (f"{source}: {key} = {found} is invalid: allowed {allowed}",)


class InfeasibleError(GaitshiftError):
    """The inputs are well-formed but no physical solution exists (e.g. no real stiffness root,
    ZMP cannot stay in the support polygon, a foot out of reach)."""


class StiffnessError(InfeasibleError, InputError):
    """No physical stiffness T solves eqs. (9)-(14) of paper 001 for the given timings."""

    def __init__(self, field: str, value: object, allowed: str):
        InputError.__init__(self, field, value, allowed)
