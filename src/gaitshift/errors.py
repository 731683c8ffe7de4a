"""The exception hierarchy of gaitshift.

Every error a user can cause derives from :class:`GaitshiftError`. The CLI prints its message on one
line and exits with code 2; library callers catch the base class. Messages always name the field, the
offending value and what is allowed.
"""

from __future__ import annotations


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


class ScenarioError(InputError):
    """A scenario file or name is invalid (unknown key, wrong type, unknown built-in)."""


class InfeasibleError(GaitshiftError):
    """The inputs are well-formed but no physical solution exists (e.g. no real stiffness root,
    ZMP cannot stay in the support polygon, a foot out of reach)."""


class StiffnessError(InfeasibleError, InputError):
    """No physical stiffness T solves eqs. (9)-(14) of paper 001 for the given timings."""

    def __init__(self, field: str, value: object, allowed: str):
        InputError.__init__(self, field, value, allowed)
