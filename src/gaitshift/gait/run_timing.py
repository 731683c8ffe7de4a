"""Running timings per speed: a shorter stance and a longer flight as the speed rises.

Human running data (Weyand, Sternlight, Bellizzi and Wright 2000, "Faster top running speeds are
achieved with greater ground forces not more rapid leg movements", J. Appl. Physiol. 89: 1991-1999):
from moderate to top speed the ground-contact time falls roughly as the inverse of the speed, while the
swing time of a leg (lift-off to its next touchdown) stays nearly the same. Both rules follow from a leg
that sweeps a bounded arc on the ground (the contact length ``L_c``: the distance the body travels over
one stance) and a swing limited by how fast the leg can be brought forward. For a symmetric run of
single-support time ``T_s`` and flight time ``T_f`` per step, the swing of one leg lasts
``T_sw = T_s + 2 T_f`` (its own flight, the other leg's stance, the next flight), so

    T_s(v) = min(T_s0, L_c / v),        T_f(v) = (T_sw0 - T_s(v)) / 2,        T_sw0 = T_s0 + 2 T_f0,   (1)

with ``(T_s0, T_f0)`` the nominal running timing: below ``v* = L_c / T_s0`` the timing is the nominal
one; above it the stance shrinks to keep the contact length, and the flight grows by what the stance
lost so the swing time is unchanged. The step frequency ``1 / (T_s + T_f) = 2 / (T_s + T_sw0)`` rises
with the speed (as in Weyand et al.'s data), and the stride ``v (T_s + T_f)`` grows.
"""

from __future__ import annotations

import numpy as np


def running_timing(
    speed: float | np.ndarray, single: float, flight: float, contact_length: float
) -> tuple[np.ndarray, np.ndarray]:
    """Single-support and flight times (s) at forward speed ``speed`` (m/s, any shape), eq. (1), from
    the nominal running timing ``single``, ``flight`` (s) and the contact length (m). A contact length
    of ``inf`` keeps the nominal timing at every speed."""
    if single <= 0 or flight < 0 or contact_length <= 0:
        raise ValueError(f"need single > 0, flight >= 0, contact_length > 0 (got {single}, {flight}, {contact_length})")
    v = np.abs(np.asarray(speed, float))
    with np.errstate(divide="ignore"):
        ts = np.minimum(single, contact_length / v)
    return ts, 0.5 * (single + 2.0 * flight - ts)


def running_stride(speed: float | np.ndarray, single: float, flight: float, contact_length: float) -> np.ndarray:
    """The stride (m, one step's advance) of the run at ``speed`` with the timing of eq. (1):
    ``v (T_s(v) + T_f(v))``."""
    ts, tf = running_timing(speed, single, flight, contact_length)
    stride: np.ndarray = np.abs(np.asarray(speed, float)) * (ts + tf)
    return stride
