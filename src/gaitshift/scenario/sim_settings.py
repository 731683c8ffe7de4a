"""The ``sim:`` block of a scenario: how ``gaitshift simulate`` runs it (sensing, latency, floor).

Every key is optional; a key left out keeps the simulator's default (``SimOptions``), and a command-line
flag overrides the key. Example::

    sim: {state: estimated, noise: rl-peer, noise_scale: 0.5, latency: 4, friction: 0.35, seed: 3}

The allowed values live here (the lowest layer) and the simulator checks its options against them.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import Field, Strict

from gaitshift.scenario.fields import StrictModel

#: what the controller sees: the estimator's state, or the simulator's truth
STATE_SOURCES = ("estimated", "oracle")
#: sensor noise profiles (``none``: exact readings)
NOISE_PROFILES = ("none", "typical", "rl-peer")
#: friction coefficients (floor, assumed), inclusive
FRICTION_RANGE = (0.01, 5.0)
#: noise scale factor, inclusive
NOISE_SCALE_RANGE = (0.0, 1000.0)
#: loop latency, ticks, inclusive
LATENCY_RANGE = (0, 50)

Friction = Annotated[float, Strict(), Field(ge=FRICTION_RANGE[0], le=FRICTION_RANGE[1], allow_inf_nan=False)]


class SimSettings(StrictModel):
    """Simulation settings of a scenario (module docstring); None = the simulator's default."""

    state: Literal["estimated", "oracle"] | None = None
    noise: Literal["none", "typical", "rl-peer"] | None = None
    noise_scale: (
        Annotated[float, Strict(), Field(ge=NOISE_SCALE_RANGE[0], le=NOISE_SCALE_RANGE[1], allow_inf_nan=False)] | None
    ) = None
    latency: Annotated[int, Strict(), Field(ge=LATENCY_RANGE[0], le=LATENCY_RANGE[1])] | None = None
    friction: Friction | None = None
    assumed_friction: Friction | None = None
    seed: Annotated[int, Strict(), Field(ge=0, le=2**32 - 1)] | None = None

    def given(self) -> dict[str, Any]:
        """The keys set in the scenario, as ``SimOptions`` keyword arguments."""
        return {k: v for k, v in self.model_dump().items() if v is not None}
