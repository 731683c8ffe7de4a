"""Bumps on the floor: box obstacles added to the simulated world only (``SimOptions.bumps``).

A bump at ``x`` is a box on the floor plane spanning ``[x, x + length]`` along the world x axis,
``[-half_width, half_width]`` along y, and ``[0, height]`` in z, with the MJCF's default geom contact
parameters (``SimOptions.friction`` sets its friction with the floor's:
:func:`gaitshift.sim.world.with_floor_friction`). It is
added to the plant's MuJoCo model before compilation. The controller is never told: it plans on flat
ground, and its own copy of the model has contacts disabled (:class:`gaitshift.control.state.ControllerState`),
so the bump acts only through the contact forces on the real feet (or a fall when a shin hits it).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from gaitshift.errors import InputError

#: allowed bump height and length, m (inclusive upper bounds; both > 0)
MAX_BUMP_HEIGHT = 0.5
MAX_BUMP_LENGTH = 10.0
#: default length along x and half width along y of a bump, m
DEFAULT_BUMP_LENGTH = 0.2
BUMP_HALF_WIDTH = 2.0

__all__ = ["Bump", "add_bumps", "check_bumps", "parse_bump"]


@dataclass(frozen=True)
class Bump:
    """A box ``height`` m high from ``x`` to ``x + length`` m along the world x axis (module docstring)."""

    x: float
    height: float
    length: float = DEFAULT_BUMP_LENGTH

    def check(self, field: str = "bumps") -> Bump:
        """This bump if its numbers are finite and in range, else :class:`InputError` on ``field``."""
        ok = all(
            isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)
            for v in (self.x, self.height, self.length)
        )
        if not ok or not (0 < self.height <= MAX_BUMP_HEIGHT and 0 < self.length <= MAX_BUMP_LENGTH):
            raise InputError(field, f"{self.x},{self.height},{self.length}", _ALLOWED)
        return self


_ALLOWED = f"X,HEIGHT[,LENGTH] in m: X finite, 0 < HEIGHT <= {MAX_BUMP_HEIGHT:g}, 0 < LENGTH <= {MAX_BUMP_LENGTH:g}"


def check_bumps(bumps: Any) -> tuple[Bump, ...]:
    """``bumps`` as a tuple of checked :class:`Bump`, or :class:`InputError` naming ``bumps``."""
    if not isinstance(bumps, tuple | list) or not all(isinstance(b, Bump) for b in bumps):
        raise InputError("bumps", bumps, "a tuple of Bump(x, height, length)")
    return tuple(b.check() for b in bumps)


def parse_bump(text: str, flag: str = "--bump") -> Bump:
    """A ``--bump X,HEIGHT[,LENGTH]`` value (m) as a checked :class:`Bump`."""
    try:
        vals = [float(v) for v in text.split(",")]
    except ValueError:
        raise InputError(flag, text, _ALLOWED) from None
    if not 2 <= len(vals) <= 3:
        raise InputError(flag, text, _ALLOWED)
    try:
        return Bump(*vals).check(flag)
    except InputError:
        raise InputError(flag, text, _ALLOWED) from None


def add_bumps(spec: Any, bumps: tuple[Bump, ...]) -> None:
    """Add one box geom per bump to the world body of ``spec`` (an ``MjSpec``), named ``bump<i>``."""
    import mujoco

    for i, b in enumerate(bumps):
        g = spec.worldbody.add_geom(
            name=f"bump{i}",
            type=mujoco.mjtGeom.mjGEOM_BOX,
            size=[b.length / 2, BUMP_HALF_WIDTH, b.height / 2],
            pos=[b.x + b.length / 2, 0.0, b.height / 2],
            rgba=[0.55, 0.45, 0.35, 1.0],
        )
        builtin = mujoco.MjSpec().default.geom
        g.contype, g.conaffinity = builtin.contype, builtin.conaffinity
        g.condim = max(g.condim, builtin.condim)
