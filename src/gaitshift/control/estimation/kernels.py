"""Compiled kernels of the estimator's per-tick math (numba, ``cache=True``): the same equations as the
Python classes they stand in for, on preallocated float64/int64 arrays, plain loops, no Python objects.

One tick of :class:`~gaitshift.control.estimation.estimator.StateEstimator` on the compiled path is
two kernel calls around the five MuJoCo calls of the kinematics (docs/estimation.md "Measured cost")::

    sense:  force trigger (contact.py) and joint filter (joints.py); writes q, qd into the private MjData
    (MuJoCo: mj_kinematics, mj_comPos, 2 mj_jacSite, mj_jacSubtreeCom; Python)
    settle: kinematics in the IMU frame (kinematics.py), InEKF mean step (inekf.py), then, unless the
            tick corrects (Python, numpy), the outputs: world points, slip low-pass (slip.py), lowest
            sole points and fused contact (contact_fusion.py), quaternion and world rate

The state of the force trigger, the fused contact and the slip low-pass lives in two arrays, ``ist``
(int64) and ``fst`` (float64), indexed by the constants below; ``recent`` (2, window) holds the last
force samples (oldest first), ``rates_lp`` (2, 3 + nj) the slip test's low-passed rate vectors.
Every compiled function of the estimator is in this one module: numba's cache checks the source file of
the function it loads only, so a kernel calling into another module's compiled function could load stale
code after an edit there. The quaternion routines are MuJoCo's (``engine_util_spatial.c``), term for term;
MuJoCo's build fuses some products into FMAs (results agree to 1 ulp) and the sums here run in another
order than numpy's, so the compiled tick is not bit-identical to the Python path: the estimates agree to
~1e-14 over a recorded run (tests/control/estimation/test_kernels.py).
"""

from __future__ import annotations

import math

import numba
import numpy as np

# ist: int64 state, two entries each (left, right); I_VETO: the kinematics ruled a load out at the last tick
I_STANCE, I_COUNT, I_FILLED, I_FUSED, I_MOVING, I_VETO = 0, 2, 4, 6, 8, 10
I_STARTED = 12  # the joint filter has started
I_ARMED, I_LAND = 13, 15  # (2,) each: the sole rose off the ground level; a landing holds it on (contact_fusion.py)
I_FLIGHT, I_AIRBORNE = 17, 18  # the body is in a flight; (2,) the sole was on when it began (contact_fusion.py)
IST_SIZE = 20
# fst: float64 state
F_CUSUM, F_VEL_LP, F_SPEED, F_GROUND = 0, 2, 6, 8  # cusum (2), vel_lp (2 x 2), speed (2), ground (NaN: none)
F_OMEGA = 9  # (3,) this tick's bias-corrected IMU rate, rad/s
F_STAND = 12  # (2,) each sole's lowest-point height at its last confident load, m (NaN: none yet)
FST_SIZE = 14
# settle's return code: bits 0-1 fused contact, 2-3 stance (force trigger), SUPPORT << i: sole i's centre
# moves (the support test, in Python, decides its slip flag), FILTER_STANCE << i: the filter's stance flags
# (stance and centre not moving), CORRECT: the InEKF corrects at this tick (then settle(phase=1))
SUPPORT, FILTER_STANCE, CORRECT = 1 << 4, 6, 1 << 8
MINVAL = 1e-15  # MuJoCo's mjMINVAL


@numba.njit(cache=True)
def normalize4(q: np.ndarray) -> None:
    """MuJoCo ``mju_normalize4`` in place: ``q / |q|`` ((1, 0, 0, 0) when ``|q| < 1e-15``)."""
    norm = math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    if norm < MINVAL:
        q[0], q[1], q[2], q[3] = 1.0, 0.0, 0.0, 0.0
    elif abs(norm - 1.0) > MINVAL:
        inv = 1.0 / norm
        for k in range(4):
            q[k] *= inv


@numba.njit(cache=True)
def quat_integrate(q: np.ndarray, w: np.ndarray, dt: float) -> None:
    """MuJoCo ``mju_quatIntegrate``: ``q <- q Exp(w dt)`` (w (3,) rad/s in the body frame), in place."""
    norm = math.sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2])
    ax, ay, az = 1.0, 0.0, 0.0
    if norm >= MINVAL:
        inv = 1.0 / norm
        ax, ay, az = w[0] * inv, w[1] * inv, w[2] * inv
    angle = dt * norm
    r0, r1, r2, r3 = 1.0, 0.0, 0.0, 0.0
    if angle != 0.0:
        s = math.sin(angle * 0.5)
        r0, r1, r2, r3 = math.cos(angle * 0.5), ax * s, ay * s, az * s
    normalize4(q)
    a0, a1, a2, a3 = q[0], q[1], q[2], q[3]
    q[0] = a0 * r0 - a1 * r1 - a2 * r2 - a3 * r3
    q[1] = a0 * r1 + a1 * r0 + a2 * r3 - a3 * r2
    q[2] = a0 * r2 - a1 * r3 + a2 * r0 + a3 * r1
    q[3] = a0 * r3 + a1 * r2 - a2 * r1 + a3 * r0


@numba.njit(cache=True)
def quat_to_mat(m: np.ndarray, q: np.ndarray) -> None:
    """MuJoCo ``mju_quat2Mat``: the rotation matrix (9,) row-major of a unit quaternion (w, x, y, z)."""
    if q[0] == 1.0 and q[1] == 0.0 and q[2] == 0.0 and q[3] == 0.0:
        for k in range(9):
            m[k] = 1.0 if k % 4 == 0 else 0.0
        return
    q00, q01, q02, q03 = q[0] * q[0], q[0] * q[1], q[0] * q[2], q[0] * q[3]
    q11, q12, q13 = q[1] * q[1], q[1] * q[2], q[1] * q[3]
    q22, q23, q33 = q[2] * q[2], q[2] * q[3], q[3] * q[3]
    m[0], m[4], m[8] = q00 + q11 - q22 - q33, q00 - q11 + q22 - q33, q00 - q11 - q22 + q33
    m[1], m[2], m[3] = 2 * (q12 - q03), 2 * (q13 + q02), 2 * (q12 + q03)
    m[5], m[6], m[7] = 2 * (q23 - q01), 2 * (q13 - q02), 2 * (q23 + q01)


@numba.njit(cache=True)
def mat_to_quat(q: np.ndarray, m: np.ndarray) -> None:
    """MuJoCo ``mju_mat2Quat``: the unit quaternion (4,) of a rotation matrix (9,) row-major (the
    largest component first, then normalised)."""
    if m[0] + m[4] + m[8] > 0:
        q[0] = 0.5 * math.sqrt(1 + m[0] + m[4] + m[8])
        q[1], q[2], q[3] = 0.25 * (m[7] - m[5]) / q[0], 0.25 * (m[2] - m[6]) / q[0], 0.25 * (m[3] - m[1]) / q[0]
    elif m[0] > m[4] and m[0] > m[8]:
        q[1] = 0.5 * math.sqrt(1 + m[0] - m[4] - m[8])
        q[0], q[2], q[3] = 0.25 * (m[7] - m[5]) / q[1], 0.25 * (m[1] + m[3]) / q[1], 0.25 * (m[2] + m[6]) / q[1]
    elif m[4] > m[8]:
        q[2] = 0.5 * math.sqrt(1 - m[0] + m[4] - m[8])
        q[0], q[1], q[3] = 0.25 * (m[2] - m[6]) / q[2], 0.25 * (m[1] + m[3]) / q[2], 0.25 * (m[5] + m[7]) / q[2]
    else:
        q[3] = 0.5 * math.sqrt(1 - m[0] - m[4] + m[8])
        q[0], q[1], q[2] = 0.25 * (m[3] - m[1]) / q[3], 0.25 * (m[2] + m[6]) / q[3], 0.25 * (m[5] + m[7]) / q[3]
    normalize4(q)


@numba.njit(cache=True)
def force_means(normal: np.ndarray, recent: np.ndarray, ist: np.ndarray, means: np.ndarray) -> None:
    """Push the force samples ``normal`` (2,) N into ``recent`` (2, window), oldest first, and write the
    mean of the samples held, ``sum / count`` summed oldest first (contact.py, contact_fusion.py)."""
    window = recent.shape[1]
    for i in range(2):
        n = ist[I_FILLED + i]
        if n == window:
            for k in range(window - 1):
                recent[i, k] = recent[i, k + 1]
            n -= 1
        recent[i, n] = normal[i]
        n += 1
        ist[I_FILLED + i] = n
        total = 0.0
        for k in range(n):
            total += recent[i, k]
        means[i] = total / n


@numba.njit(cache=True)
def force_trigger(means: np.ndarray, on: float, off: float, debounce: int, ist: np.ndarray) -> None:
    """The Schmitt trigger with debounce of contact.py on the mean forces ``means`` (2,) N: a sole flips after
    ``debounce`` consecutive ticks past its threshold (on: ``f > on``, off: ``f < off``); a sole the last tick's
    kinematics ruled out (``ist[I_VETO]``) is then off, its debounce cleared (ContactDetector.release)."""
    for i in range(2):
        state = ist[I_STANCE + i] != 0
        crossing = means[i] < off if state else means[i] > on
        count = ist[I_COUNT + i] + 1 if crossing else 0
        if count >= debounce:
            ist[I_STANCE + i] = 0 if state else 1
            count = 0
        if ist[I_VETO + i] != 0:
            ist[I_STANCE + i] = count = 0
        ist[I_COUNT + i] = count


@numba.njit(cache=True)
def joint_filter(a: np.ndarray, gain: np.ndarray, x: np.ndarray, q: np.ndarray, qd: np.ndarray) -> None:
    """The steady-state joint Kalman filter of joints.py, ``x <- A x + K z`` with ``A = (I - K) F`` and
    ``z = [q; qd]``: ``a``, ``gain`` (2, 2), state ``x`` (2, nj) [rad; rad/s], readings (nj,) each."""
    for j in range(x.shape[1]):
        x0, x1 = x[0, j], x[1, j]
        z0, z1 = q[j], qd[j]
        x[0, j] = a[0, 0] * x0 + a[0, 1] * x1 + (gain[0, 0] * z0 + gain[0, 1] * z1)
        x[1, j] = a[1, 0] * x0 + a[1, 1] * x1 + (gain[1, 0] * z0 + gain[1, 1] * z1)


@numba.njit(cache=True)
def imu_frame_points(
    kin_idx: np.ndarray, site_xpos: np.ndarray, com: np.ndarray, p_s: np.ndarray, jac: np.ndarray,
    qvel: np.ndarray, aug: np.ndarray, vel: np.ndarray,
) -> None:  # fmt: skip
    """kinematics.py for an IMU on the base with its axes: ``y = x_B - p_S`` for the soles (sites
    ``kin_idx`` (2,)) and the CoM ``com`` (3,), m, into ``aug[0:3, 0:3]`` (row 3, the base origin
    ``-p_S``, is fixed), and ``dy/dt = J qd`` into ``vel`` (4, 3), m/s (``jac`` (12, nv) @ ``qvel``)."""
    for c in range(3):
        aug[0, c] = site_xpos[kin_idx[0], c] - p_s[c]
        aug[1, c] = site_xpos[kin_idx[1], c] - p_s[c]
        aug[2, c] = com[c] - p_s[c]
    for r in range(12):
        total = 0.0
        for j in range(jac.shape[1]):
            total += jac[r, j] * qvel[j]
        vel[r // 3, r % 3] = total


@numba.njit(cache=True)
def mean_step(
    gyro: np.ndarray, accel: np.ndarray, dt: float, bias: np.ndarray, quat: np.ndarray, rot9: np.ndarray,
    vec: np.ndarray, step: np.ndarray, gravity_step: np.ndarray, omega: np.ndarray,
) -> None:  # fmt: skip
    """The InEKF mean over one tick (inekf.py, Hartley 2018 eq. 4): ``w = w~ - b_g`` into ``omega``,
    ``a_w = R (a~ - b_a)`` into ``vec[4]``, ``[v; p] <- step @ [v, p, d_L, d_R, a_w] + gravity_step``
    (``step`` (2, 5) = [[1, 0, 0, 0, dt], [dt, 1, 0, 0, dt^2/2]]), ``R <- R Exp(w dt)`` (the quaternion
    ``quat`` and its matrix ``rot9`` (9,)). ``vec`` (5, 6): the filter's rows v, p, d_L, d_R, a_w."""
    for c in range(3):
        omega[c] = gyro[c] - bias[c]
    a0, a1, a2 = accel[0] - bias[3], accel[1] - bias[4], accel[2] - bias[5]
    for r in range(3):
        vec[4, r] = rot9[3 * r] * a0 + rot9[3 * r + 1] * a1 + rot9[3 * r + 2] * a2
    for c in range(3):
        v, p = vec[0, c], vec[1, c]
        cols = (v, p, vec[2, c], vec[3, c], vec[4, c])
        for r in range(2):
            total = 0.0
            for k in range(5):
                total += step[r, k] * cols[k]
            vec[r, c] = total + gravity_step[r, c]
    quat_integrate(quat, omega, dt)
    quat_to_mat(rot9, quat)


@numba.njit(cache=True)
def world_points(
    rot9: np.ndarray, omega: np.ndarray, vp: np.ndarray, vel: np.ndarray, aug: np.ndarray, xv: np.ndarray
) -> None:
    """World positions and velocities of the four points (estimator.py): ``x_w = R y + p`` into
    ``xv[0:4]`` and ``v_w = R (dy/dt + w x y) + v`` into ``xv[4:8]``, with the points ``y`` in
    ``aug[0:4, 0:3]``, their velocities ``dy/dt`` in ``vel`` (4, 3), ``vp`` (2, 3) = [v; p] world;
    ``dy/dt + w x y`` is kept in ``aug[4:8, 0:3]`` (as LegKinematics.points_aug documents)."""
    w0, w1, w2 = omega[0], omega[1], omega[2]
    for k in range(4):
        y0, y1, y2 = aug[k, 0], aug[k, 1], aug[k, 2]
        r0 = vel[k, 0] + (w1 * y2 - w2 * y1)
        r1 = vel[k, 1] + (w2 * y0 - w0 * y2)
        r2 = vel[k, 2] + (w0 * y1 - w1 * y0)
        aug[4 + k, 0], aug[4 + k, 1], aug[4 + k, 2] = r0, r1, r2
        for c in range(3):
            m0, m1, m2 = rot9[3 * c], rot9[3 * c + 1], rot9[3 * c + 2]
            xv[k, c] = m0 * y0 + m1 * y1 + m2 * y2 + vp[1, c]
            xv[4 + k, c] = m0 * r0 + m1 * r1 + m2 * r2 + vp[0, c]


@numba.njit(cache=True)
def slip_lowpass(
    stance: np.ndarray, xv: np.ndarray, omega: np.ndarray, qd: np.ndarray, alpha: float, lim: float,
    fst: np.ndarray, ist: np.ndarray, rates_lp: np.ndarray,
) -> int:  # fmt: skip
    """The low-pass part of slip.py, eqs. (2)-(3): per stance sole (``stance`` (2,) 0/1) the first-order
    low-pass (gain ``alpha``) of its horizontal centre velocity (``xv[4 + i]``, m/s) and of the rate
    vector (w (3,) rad/s, qd (nj,) rad/s) into ``rates_lp[i]``; zero in swing. Sets the centre speeds
    ``|LP(v_c)|_xy`` and the ``moving`` flags (the faster sole alone when both exceed ``lim``); returns
    the bits (``SUPPORT << i``) of the soles whose support polygon the caller must test."""
    need = 0
    centre = np.zeros(2)
    n = qd.shape[0]
    for i in range(2):
        lp = F_VEL_LP + 2 * i
        if stance[i] == 0:
            fst[lp] = fst[lp + 1] = fst[F_SPEED + i] = 0.0
            rates_lp[i, :] = 0.0
            continue
        fst[lp] += alpha * (xv[4 + i, 0] - fst[lp])
        fst[lp + 1] += alpha * (xv[4 + i, 1] - fst[lp + 1])
        for k in range(3):
            rates_lp[i, k] += alpha * (omega[k] - rates_lp[i, k])
        for k in range(n):
            rates_lp[i, 3 + k] += alpha * (qd[k] - rates_lp[i, 3 + k])
        centre[i] = fst[F_SPEED + i] = math.sqrt(fst[lp] * fst[lp] + fst[lp + 1] * fst[lp + 1])
        if centre[i] > lim:
            need |= SUPPORT << i
    m0, m1 = centre[0] > lim, centre[1] > lim
    if m0 and m1:
        m0, m1 = centre[0] >= centre[1], centre[1] > centre[0]
    ist[I_MOVING], ist[I_MOVING + 1] = int(m0), int(m1)
    return need


@numba.njit(cache=True)
def lowest_heights(
    rot9: np.ndarray, site_xmat: np.ndarray, kin_idx: np.ndarray, pts: np.ndarray, xv: np.ndarray
) -> np.ndarray:
    """World height (2,) of each sole's lowest contact point (estimator.py): ``z_s + min_j u . p_j``
    with ``u = R_s^T R^T e_z`` (sole orientation ``site_xmat[kin_idx[i]]`` in the IMU frame), the points
    ``pts`` (2, n, 3) m in the sole frame (rows padded with a repeat), ``z_s = xv[i, 2]``."""
    out = np.empty(2)
    for i in range(2):
        s = kin_idx[i]
        u = np.empty(3)
        for c in range(3):
            u[c] = rot9[6] * site_xmat[s, c] + rot9[7] * site_xmat[s, 3 + c] + rot9[8] * site_xmat[s, 6 + c]
        low = np.inf
        for j in range(pts.shape[1]):
            low = min(low, pts[i, j, 0] * u[0] + pts[i, j, 1] * u[1] + pts[i, j, 2] * u[2])
        out[i] = low + xv[i, 2]
    return out


@numba.njit(cache=True)
def fuse_contact(
    normal: np.ndarray, means: np.ndarray, heights: np.ndarray, vel: np.ndarray, planned: int,
    par: np.ndarray, ist: np.ndarray, fst: np.ndarray, a_v: float,
) -> None:  # fmt: skip
    """The rules of contact_fusion.py: per sole, force mean ``means``, latest sample ``normal`` (N),
    lowest-point height ``heights`` (m) against the ground level ``fst[F_GROUND]`` (NaN: none yet), world
    velocity ``vel`` (2, 3) of its centre (m/s: ``vz``, the speed), the plan's flags ``planned`` (bits 0,
    1; -1: no plan), the IMU's vertical specific force ``a_v`` (m/s^2); ``par`` = [on, off, cusum gain,
    cusum half shift, near, still, cusum threshold, lift, swing speed, land speed, flight on, flight off].
    Updates the flags ``ist[I_FUSED]``, ``ist[I_VETO]``, the flight (``ist[I_FLIGHT]``, ``ist[I_AIRBORNE]``),
    the CUSUMs, the ground level (the sole(s) on with ``f > on``) and the soles' stands (those still)."""
    on_f, off_f, gain, half, near_h, still, thresh = par[0], par[1], par[2], par[3], par[4], par[5], par[6]
    lift, swing, land = par[7], par[8], par[9]
    has_plan = planned >= 0
    ground = fst[F_GROUND]
    began = ist[I_FLIGHT] == 0 and a_v < par[10]  # the flight rule's Schmitt trigger (ContactFusion._flight)
    ist[I_FLIGHT] = int(a_v <= par[11]) if ist[I_FLIGHT] != 0 else int(began)
    for i in range(2):
        plan = (not has_plan) or (planned >> i) & 1 == 1
        f, mean = normal[i], means[i]
        near = abs(heights[i] - ground) < near_h  # False while the ground level is NaN
        vz, speed = vel[i, 2], math.sqrt(vel[i, 0] ** 2 + vel[i, 1] ** 2 + vel[i, 2] ** 2)
        rest = near and -still < vz < still
        lifted = heights[i] - fst[F_STAND + i] > lift and vz > still  # NaN: False
        # airborne: on at the flight's start (the last tick's flag), cleared when the flight ends
        airborne = ist[I_AIRBORNE + i] = ist[I_FUSED + i] if began else ist[I_AIRBORNE + i] * ist[I_FLIGHT]
        veto = ist[I_VETO + i] = has_plan and not plan and (lifted or speed > swing or airborne != 0)
        landing = ist[I_LAND + i] != 0 and near
        if veto:
            on = landing = False
            fst[F_CUSUM + i] = 0.0
        elif ist[I_FUSED + i] != 0:
            on = (mean if plan else min(mean, f)) >= off_f or (rest and has_plan) or landing
            fst[F_CUSUM + i] = 0.0
        elif near:
            landing = ist[I_ARMED + i] != 0 and ist[I_FUSED + 1 - i] != 0 and vz > -land
            s = max(0.0, fst[F_CUSUM + i] + gain * (f - half))
            on = mean > on_f or (rest and plan and has_plan) or s > thresh or landing
            fst[F_CUSUM + i] = 0.0 if on else s
        else:
            on = mean > on_f
            fst[F_CUSUM + i] = 0.0
        ist[I_FUSED + i] = int(on)
        ist[I_LAND + i] = int(landing and mean <= on_f)
        ist[I_ARMED + i] = int(not on and (ist[I_ARMED + i] != 0 or heights[i] - ground > lift))  # NaN: False
    loaded_l = ist[I_FUSED] != 0 and normal[0] > on_f
    loaded_r = ist[I_FUSED + 1] != 0 and normal[1] > on_f
    if loaded_l and -still < vel[0, 2] < still:
        fst[F_STAND] = heights[0]
    if loaded_r and -still < vel[1, 2] < still:
        fst[F_STAND + 1] = heights[1]
    if loaded_l and loaded_r:
        fst[F_GROUND] = (heights[0] + heights[1]) / 2
    elif loaded_l or loaded_r:
        fst[F_GROUND] = heights[0 if loaded_l else 1]


@numba.njit(cache=True)
def sense(
    normal: np.ndarray, q: np.ndarray, qd: np.ndarray, trigger: np.ndarray, ist: np.ndarray, recent: np.ndarray,
    means: np.ndarray, a: np.ndarray, gain: np.ndarray, x: np.ndarray, qpos: np.ndarray, qvel: np.ndarray,
    out: np.ndarray,
) -> None:  # fmt: skip
    """First kernel of a tick: force means and trigger (``trigger`` = [on N, off N, debounce ticks]),
    the joint filter on the encoders ``q`` and driver velocities ``qd`` (nj,) (started at the first
    reading when not reset), the filtered q, qd into ``out[0:2 nj]``, ``qpos[7:]`` and ``qvel[6:]``."""
    force_means(normal, recent, ist, means)
    force_trigger(means, trigger[0], trigger[1], int(trigger[2]), ist)
    nj = q.shape[0]
    if ist[I_STARTED] == 0:
        x[0, :], x[1, :] = q, qd
        ist[I_STARTED] = 1
    joint_filter(a, gain, x, q, qd)
    for j in range(nj):
        out[j] = qpos[7 + j] = x[0, j]
        out[nj + j] = qvel[6 + j] = x[1, j]


@numba.njit(cache=True)
def settle(
    phase: int, planned: np.ndarray, has_plan: bool, gyro: np.ndarray, accel: np.ndarray, par: np.ndarray,
    ist: np.ndarray, fst: np.ndarray, means: np.ndarray, normal: np.ndarray, kin_idx: np.ndarray,
    site_xpos: np.ndarray, site_xmat: np.ndarray, com: np.ndarray, p_s: np.ndarray, jac: np.ndarray,
    qvel: np.ndarray, aug: np.ndarray, vel: np.ndarray, quat: np.ndarray, rot9: np.ndarray, vec: np.ndarray,
    bias: np.ndarray, step: np.ndarray, gravity_step: np.ndarray, offset: np.ndarray, ticks: np.ndarray,
    rates_lp: np.ndarray, pts: np.ndarray, out: np.ndarray,
) -> int:  # fmt: skip
    """Second kernel (module docstring): phase 0 from the kinematics, phase 1 after a correction.
    ``par`` = [dt, correct_every, slip alpha, slip speed, then fuse_contact's par]; ``out`` (2 nj + 31,)
    = [q, qd, the world points and velocities (8, 3), quaternion (4,), world rate (3,)]."""
    omega = fst[F_OMEGA : F_OMEGA + 3]
    if phase == 0:
        imu_frame_points(kin_idx, site_xpos, com, p_s, jac, qvel, aug, vel)
        mean_step(gyro, accel, par[0], bias, quat, rot9, vec, step, gravity_step, omega)
        ticks[0] += 1
        if ticks[0] % int(par[1]) == 0:
            s0 = ist[I_STANCE] != 0 and ist[I_MOVING] == 0
            s1 = ist[I_STANCE + 1] != 0 and ist[I_MOVING + 1] == 0
            return CORRECT | int(s0) << FILTER_STANCE | int(s1) << (FILTER_STANCE + 1)
    nj = (out.shape[0] - 31) // 2
    xv = out[2 * nj : 2 * nj + 24].reshape(8, 3)
    vp = vec[0:2, 0:3] + offset
    world_points(rot9, omega, vp, vel, aug, xv)
    stance = ist[I_STANCE : I_STANCE + 2]
    need = slip_lowpass(stance, xv, omega, out[nj : 2 * nj], par[2], par[3], fst, ist, rates_lp)
    heights = lowest_heights(rot9, site_xmat, kin_idx, pts, xv)
    plan = int(planned[0] != 0) | int(planned[1] != 0) << 1 if has_plan else -1
    a_v = rot9[6] * accel[0] + rot9[7] * accel[1] + rot9[8] * accel[2]  # the specific force along the vertical
    fuse_contact(normal, means, heights, xv[4:6], plan, par[4:], ist, fst, a_v)
    o = 2 * nj + 24
    mat_to_quat(out[o : o + 4], rot9)
    for r in range(3):
        out[o + 4 + r] = rot9[3 * r] * omega[0] + rot9[3 * r + 1] * omega[1] + rot9[3 * r + 2] * omega[2]
    flags = ist[I_FUSED] | ist[I_FUSED + 1] << 1 | stance[0] << 2 | stance[1] << 3
    return int(flags) | need
