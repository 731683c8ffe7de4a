"""Command limits of a streaming running generator: speed, change per step and stride.

* :func:`speed_limit`: the largest sustainable |command| per axis: the scenario's ``max_speed`` and
  the speeds at which the steady strides (x: ``v T_step``; y: ``step_width +/- v T_step``) stay within
  ``max_stride`` and keep the feet one foot width apart.
* :func:`clip_change`: at most ``max_accel_per_step`` change of the take-off velocity per step.
* :func:`stride_window` and :func:`clamp_by_strides`: the foothold that a take-off velocity implies is
  affine in that velocity (Algorithm 1 in closed form, ``p = K - v1 V_0``); the velocity is clamped
  so that the new foothold stays within the stride window of the previous one.

All velocities in m/s, lengths in m, arrays (2,) per axis [x, y].
"""

from __future__ import annotations

import numpy as np

from gaitshift.models.arrays import FloatArray

__all__ = ["clamp_by_strides", "clip_change", "speed_limit", "stride_window"]


def clip_change(cmd: FloatArray, last: FloatArray, dv: FloatArray) -> FloatArray:
    """Clamp ``cmd`` to ``last +/- dv``; changes within ``dv`` up to rounding pass unchanged."""
    ok = np.abs(cmd - last) <= dv * (1 + 1e-9) + 1e-12
    return np.where(ok, cmd, np.clip(cmd, last - dv, last + dv))


def speed_limit(
    max_speed: FloatArray, max_stride: float, step_period: float, width: float, foot_width: float
) -> tuple[FloatArray, list[str]]:
    """Largest sustainable |command| per axis (2,) and, per axis, the limit that sets it
    (``limits.max_speed`` or ``steady strides within limits``)."""
    T = step_period
    stride = np.array([max_stride / T, max(0.0, min(width - foot_width, max_stride - width)) / T])
    lim = np.asarray(max_speed, float)
    vmax = np.minimum(lim, stride)
    return vmax, ["limits.max_speed" if vmax[k] >= lim[k] else "steady strides within limits" for k in range(2)]


def stride_window(sign: float, max_stride: float, foot_width: float) -> tuple[FloatArray, FloatArray]:
    """Bounds (lo, hi) of the step from the previous foothold to the new one: forward within
    +/- ``max_stride``; lateral on the new foot's side (``sign`` +1: left, -1: right), at least one foot
    width away and at most ``max_stride``."""
    lo_d = np.array([-max_stride, -np.inf])
    hi_d = np.array([max_stride, np.inf])
    if sign > 0:
        lo_d[1], hi_d[1] = foot_width, max_stride
    else:
        lo_d[1], hi_d[1] = -max_stride, -foot_width
    return lo_d, hi_d


def clamp_by_strides(
    v1: FloatArray, K: FloatArray, V0: float, lo_d: FloatArray, hi_d: FloatArray, last: FloatArray, dv: FloatArray
) -> FloatArray:
    """The take-off velocity ``v1`` clamped so that the foothold ``K - v1 V_0`` stays within
    ``[lo_d, hi_d]`` of the previous one, but never by more than ``dv`` from ``last``: a stride clamp
    that needs more would feed back into ever larger corrections (the horizontal dynamics are
    unstable); the stride then gives. Values within 1e-12 of ``v1`` are returned as ``v1``."""
    slack = 1e-9 * abs(V0)
    v_lo, v_hi = (K - hi_d) / V0, (K - lo_d) / V0
    v1c = np.clip(v1, np.minimum(v_lo, v_hi) - slack, np.maximum(v_lo, v_hi) + slack)
    v1c = clip_change(v1c, last, dv)
    return np.where(np.abs(v1c - v1) <= 1e-12, v1, v1c)
