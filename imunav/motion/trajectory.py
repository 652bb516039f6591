"""Motions from data: timed poses and waypoint routes as smooth, exactly differentiable splines.

Two :class:`~imunav.motion.base.BaseMotion` implementations, so simulation, navigation,
assessment and Monte Carlo take them unchanged:

:class:`PoseMotion` — timed poses (times, NED positions, ``q_nb`` attitudes), e.g. motion
capture or a camera trajectory.

- Position: a quintic spline (``scipy.interpolate.make_interp_spline``, ``k = 5``, not-a-knot
  ends) through every position; velocity, acceleration and so the specific force are its exact
  derivatives, continuous (C⁴). With ``smoothing = σ`` (m) a quintic *smoothing* spline
  (FITPACK ``splrep``, residual sum ``s = n σ²``: FITPACK's rule for noise of standard deviation σ)
  replaces it — needed for real capture data, whose millimetres of noise are amplified by
  ``(π·rate)²`` when differentiated twice (1 mm at 100 Hz: ≈ 100 m/s² of noise in f_b).
- Attitude: scipy's ``RotationSpline`` — a cubic spline in rotation vectors with continuous
  angular rate and angular acceleration, whose angular rate (``order=1``) is the body rate ω_b.
  Chosen over a cumulative B-spline because it *interpolates* (passes through every given
  attitude; a cumulative B-spline approximates its control poses) and gives ω_b and its
  derivative in closed form. With ``attitude_smoothing = σ`` (rad) the quaternion components
  (sign-aligned) are first smoothed by a quintic smoothing spline (``s = n σ²`` per component),
  renormalised, and the spline passes through those.
- Both pass through every given pose (to ~1e-15 without smoothing).
- Times are measured from the first pose (the motion starts at t = 0; ``time_offset`` keeps
  the original start).

:class:`WaypointMotion` — a route of two or more timed waypoints that starts and ends at rest.

- Position: a quintic spline through the waypoints with zero velocity and acceleration at both
  ends (clamped), so a route of two points is already a smooth rest-to-rest move.
- Attitude ``"given"``: yaw, pitch, roll per waypoint (radians; yaw and roll unwrapped) through
  the same clamped quintic, so the body is at rest at both ends too; ω_b from the Euler rates.
- Attitude ``"follow"``: yaw along the horizontal velocity, pitch along the climb
  (``atan2(−v_d, |v_h|)``), roll for a coordinated turn ``atan(|v|·ψ̇/g)``, all with exact
  derivatives from the spline's (ψ̇ and ψ̈ need the jerk and snap, which a quintic has). At the
  rest ends the velocity vanishes like τ² (τ the time from the end), so the direction is taken
  from ``v/τ²`` — a polynomial there — and stays defined and smooth.

Both expose ``breakpoints`` (the pose or waypoint times): the increments quadrature splits its
intervals there, so each piece is smooth and the increments are exact for the spline motion.

May import: ``imunav.core``, ``imunav.motion.base``.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from imunav.core.constants import G0
from imunav.core.rotations import FloatArray, euler_to_quat
from imunav.core.validation import ImunavError, as_float_array, unit_quaternions
from imunav.motion.base import BaseMotion, times

#: Quintic position splines need this many poses (a not-a-knot quintic: 6 coefficients).
MIN_POSES = 6
#: Evaluating this far outside [0, duration] (s) is accepted (rounding of sample times).
EDGE = 1e-9


#: The data's times: intervals of at least a microsecond (no capture or route is denser; a
#: spline's collocation needs them resolved), spans of at most ten years.
MIN_INTERVAL = 1e-6
MAX_SPAN = 3.2e8


def _check_times(t: npt.ArrayLike, what: str, first_row: int = 1) -> FloatArray:
    t = as_float_array(t, "t", ndim=1)
    bad = np.nonzero(np.diff(t) <= 0)[0]
    if bad.size:
        i = int(bad[0]) + 1
        raise ImunavError(f"{what} {i + first_row}: t = {t[i]:.10g} is not after the previous "
                          f"t = {t[i - 1]:.10g} (times must strictly increase)")
    small = np.nonzero(np.diff(t) < MIN_INTERVAL)[0]
    if small.size:
        i = int(small[0]) + 1
        raise ImunavError(f"{what} {i + first_row}: t = {t[i]:.10g} is only "
                          f"{t[i] - t[i - 1]:.3g} s after the previous one (at least "
                          f"{MIN_INTERVAL:g} s apart)")
    if t.size and t[-1] - t[0] > MAX_SPAN:
        raise ImunavError(f"{what} {t.size - 1 + first_row}: t = {t[-1]:.10g} is "
                          f"{t[-1] - t[0]:.3g} s after the first (at most {MAX_SPAN:g} s, ten "
                          "years)")
    return t


class _Spline(BaseMotion):
    """Shared: the time window and its check."""

    time_offset: float = 0.0
    breakpoints: FloatArray
    #: defined on [0, duration] only: runs stop at the last whole sample (``base.span``)
    bounded = True

    def _t(self, t: npt.ArrayLike) -> FloatArray:
        t = times(t)
        if t.size and (t.min() < -EDGE or t.max() > self.duration + EDGE):
            raise ImunavError(f"{self.name}: the motion is defined from 0 to {self.duration:g} s "
                              f"(data end there), asked at t = "
                              f"{(t.min() if t.min() < -EDGE else t.max()):.6g} s")
        return np.clip(t, 0.0, self.duration)

    def position(self, t):
        return self._pos(self._t(t))

    def velocity(self, t):
        return self._pos.derivative(1)(self._t(t))

    def acceleration(self, t):
        return self._pos.derivative(2)(self._t(t))


class PoseMotion(_Spline):
    """Timed poses as a smooth motion (see the module docstring).

    Position is a quintic spline through (or, with ``smoothing``, near) the positions, attitude
    scipy's ``RotationSpline`` through the attitudes; velocity, acceleration, specific force and
    body rate are their exact derivatives. The motion starts at the first pose (its t = 0) and
    is defined only up to the last one: asking outside ``[0, duration]`` raises.

    Parameters
    ----------
    t : array_like, shape (n,)
        Strictly increasing times (s), n ≥ 6 (:data:`MIN_POSES`); any start.
    position : array_like, shape (n, 3)
        Positions (m, NED).
    attitude : array_like, shape (n, 4)
        ``q_nb`` quaternions, scalar first, unit norm to 1e-3 (then normalised; the signs are
        made continuous, since q and −q are the same attitude).
    smoothing : float, optional
        Noise standard deviation of the positions (m): a quintic smoothing spline with
        residual sum ``n σ²`` replaces the interpolating one. None (default): interpolate.
    attitude_smoothing : float, optional
        Noise standard deviation of the attitudes (rad): the quaternion components are
        smoothed the same way first. None (default): interpolate.
    name : str, default "poses"
        A name for reports, plots and error messages.
    row_name : str, default "pose"
        How errors name a pose (``"line"`` for a CSV file).
    first_row : int, default 1
        The number errors give the first pose (2 for a CSV file's first data line).

    Attributes
    ----------
    duration : float
        ``t[-1] − t[0]`` (s).
    time_offset : float
        ``t[0]`` (s): the source time of the motion's t = 0.
    breakpoints : ndarray, shape (n,)
        The pose times from 0 (s): the exact increments are integrated piece by piece between
        them.
    bounded : bool
        True: runs stop at the last whole sample inside the data.

    Raises
    ------
    ImunavError
        If the times are not strictly increasing (naming the pose by ``row_name`` and
        ``first_row``), there are fewer than 6 poses, the arrays are not finite or their
        lengths differ, a quaternion's norm is not 1 to 1e-3 (naming the pose), or a smoothing
        level is not a finite number > 0. Every method raises for times outside
        ``[0, duration]`` (beyond 1e-9 s).

    Examples
    --------
    Poses of a body moving north at 2 m/s, level:

    >>> import numpy as np
    >>> t = np.arange(8.0)
    >>> m = PoseMotion(t, np.c_[2 * t, 0 * t, 0 * t], np.tile([1.0, 0, 0, 0], (8, 1)))
    >>> m.duration, np.round(m.velocity([3.5]), 12)
    (7.0, array([[2., 0., 0.]]))
    """

    def __init__(self, t, position, attitude, *, smoothing: float | None = None,
                 attitude_smoothing: float | None = None, name: str = "poses",
                 row_name: str = "pose", first_row: int = 1):
        from scipy.interpolate import make_interp_spline
        from scipy.spatial.transform import Rotation, RotationSpline

        what = row_name
        t = _check_times(t, what, first_row)
        n = t.size
        if n < MIN_POSES:
            raise ImunavError(f"{n} poses: a quintic spline needs at least {MIN_POSES}")
        p = as_float_array(position, "position", last=3)
        q = as_float_array(attitude, "attitude", last=4)
        if p.shape[0] != n or q.shape[0] != n:
            raise ImunavError(f"{n} times but {p.shape[0]} positions and {q.shape[0]} attitudes")
        q = unit_quaternions(q, what, first_row)
        # sign continuity: q and −q are the same attitude; keep consecutive ones close
        flips = np.cumsum(np.concatenate([[0], np.sum(q[1:] * q[:-1], axis=1) < 0])) % 2
        q = np.where(flips[:, None] == 1, -q, q)
        self.time_offset = float(t[0])
        tt = t - t[0]
        self.duration = float(tt[-1])
        self.name = name
        self.breakpoints = tt
        self.smoothing, self.attitude_smoothing = smoothing, attitude_smoothing
        if smoothing is None:
            self._pos = make_interp_spline(tt, p, k=5)
        else:
            self._pos = _smoothing_spline(tt, p, _positive(smoothing, "smoothing"), "smoothing")
        if attitude_smoothing is not None:
            qs = _smoothing_spline(tt, q, _positive(attitude_smoothing, "attitude_smoothing"),
                                   "attitude_smoothing")(tt)
            q = qs / np.linalg.norm(qs, axis=1, keepdims=True)
        self._rot = RotationSpline(tt, Rotation.from_quat(q, scalar_first=True))

    def attitude(self, t):
        q = self._rot(self._t(t).ravel()).as_quat(scalar_first=True)
        return q.reshape(np.shape(t) + (4,))

    def angular_rate(self, t):
        t = self._t(t)
        return self._rot(t.ravel(), 1).reshape(t.shape + (3,))

    def __repr__(self) -> str:
        return (f"PoseMotion({self.breakpoints.size} poses over {self.duration:g} s, "
                f"smoothing={self.smoothing}, attitude_smoothing={self.attitude_smoothing})")


#: The largest smoothing noise level (m or rad): its square times the pose count stays finite.
MAX_SMOOTHING = 1e6


def _positive(x, name: str) -> float:
    x = float(x)
    if not np.isfinite(x) or x <= 0 or x > MAX_SMOOTHING:
        raise ImunavError(f"{name} must be a positive noise level of at most {MAX_SMOOTHING:g}, "
                          f"got {x!r}", argument=name)
    return x


class _Stack:
    """Several 1-D splines evaluated side by side, with ``derivative`` like a BSpline."""

    def __init__(self, splines):
        self.splines = list(splines)

    def __call__(self, t):
        return np.stack([s(t) for s in self.splines], axis=-1)

    def derivative(self, nu: int = 1) -> _Stack:
        return _Stack(s.derivative(nu) for s in self.splines)


#: Smoothing splines of more poses are refused up front: FITPACK's knot search grows faster
#: than the record (1e5 poses: 6 s a column at best, far more with σ below the noise).
MAX_SMOOTHED_POSES = 200_000


def _smoothing_spline(t: FloatArray, y: FloatArray, sigma: float, what: str = "smoothing"
                      ) -> _Stack:
    """Quintic smoothing splines of each column: residual sum ``n σ²`` (FITPACK's rule).

    FITPACK's own ``splrep`` (Fortran), not ``make_splrep`` (its Python port, same spline to
    1e-13): with σ below the data's noise the knot search nearly interpolates, which took the
    port 84 s on 3001 poses and ``splrep`` 0.8 s (and ``splrep`` 450 s on 10 000 poses). Each
    fit runs in a worker thread (``splrep`` releases the GIL) so that the caller's thread keeps
    answering signals (SIGTERM, Ctrl-C: FITPACK itself cannot be interrupted) and shows a
    progress bar on fits longer than a few seconds."""
    from scipy.interpolate import BSpline, splrep

    if t.size > MAX_SMOOTHED_POSES:
        raise ImunavError(f"{what} of {t.size} poses: too many for a smoothing spline (at "
                          f"most {MAX_SMOOTHED_POSES}: its knot search grows faster than the "
                          "record); decimate the poses or fit them in pieces", argument=what)
    fits = [lambda j=j: splrep(t, y[:, j], k=5, s=t.size * sigma**2) for j in range(y.shape[1])]
    return _Stack(BSpline(*tck, extrapolate=True)
                  for tck in run_in_background(fits, f"{what} spline"))


#: Seconds a background computation runs before its progress bar appears.
PROGRESS_DELAY = 3.0


def run_in_background(jobs, desc: str) -> list:
    """The results of ``jobs`` (callables without arguments), each run in a daemon worker
    thread while this thread waits in short steps: signal handlers (SIGTERM, Ctrl-C) keep
    running here while a job sits in C code that releases the GIL, and a tqdm bar (on stderr,
    not inside a notebook kernel) counts the jobs after :data:`PROGRESS_DELAY` seconds. A job's
    exception is raised here."""
    import sys
    import threading
    import time

    results, start, bar = [], time.monotonic(), None
    try:
        for i, job in enumerate(jobs):
            box: dict = {}

            def work(job=job, box=box):
                try:
                    box["value"] = job()
                except BaseException as exc:          # handed to the waiting thread
                    box["error"] = exc

            worker = threading.Thread(target=work, daemon=True, name=f"imunav {desc}")
            worker.start()
            while worker.is_alive():
                worker.join(0.2)
                if (bar is None and time.monotonic() - start > PROGRESS_DELAY
                        and "ipykernel" not in sys.modules):    # stored notebooks stay as run
                    from tqdm import tqdm

                    bar = tqdm(total=len(jobs), initial=i, desc=desc, unit="fit")
                if bar is not None:
                    bar.refresh()
            if "error" in box:
                raise box["error"]
            results.append(box["value"])
            if bar is not None:
                bar.update(1)
    finally:
        if bar is not None:
            bar.close()
    return results


# --------------------------------------------------------------------------------- waypoints

ORIENTATIONS = ("given", "follow")


def _at_rest_spline(t: FloatArray, y: FloatArray):
    """Quintic through ``y`` with zero first and second derivatives at both ends."""
    from scipy.interpolate import make_interp_spline

    zero = [(1, np.zeros(y.shape[1])), (2, np.zeros(y.shape[1]))]
    return make_interp_spline(t, y, k=5, bc_type=(zero, zero))


def euler_rates_to_body(ypr: FloatArray, rates: FloatArray) -> FloatArray:
    """Body rate ω_b from Z-Y-X Euler angles and their rates.

    ``ω_b = [φ̇ − ψ̇ sin θ,  θ̇ cos φ + ψ̇ cos θ sin φ,  −θ̇ sin φ + ψ̇ cos θ cos φ]`` (the vector
    part of ``2 q* ⊗ q̇`` for ``q = q_z(ψ) ⊗ q_y(θ) ⊗ q_x(φ)``).

    Parameters
    ----------
    ypr : ndarray, shape (..., 3)
        ``[yaw ψ, pitch θ, roll φ]`` (rad).
    rates : ndarray, shape (..., 3)
        ``[ψ̇, θ̇, φ̇]`` (rad/s), same leading shape (not checked: an internal kernel).

    Returns
    -------
    ndarray, shape (..., 3)
        ω_b (rad/s).

    Examples
    --------
    >>> import numpy as np
    >>> euler_rates_to_body(np.zeros(3), np.array([0.1, 0.0, 0.0]))   # yaw rate when level
    array([0. , 0. , 0.1])
    """
    _, th, ph = np.moveaxis(ypr, -1, 0)
    dps, dth, dph = np.moveaxis(rates, -1, 0)
    return np.stack([dph - dps * np.sin(th),
                     dth * np.cos(ph) + dps * np.cos(th) * np.sin(ph),
                     -dth * np.sin(ph) + dps * np.cos(th) * np.cos(ph)], -1)


class WaypointMotion(_Spline):
    """A route of timed waypoints, at rest at both ends (see the module docstring).

    Position is a quintic spline through the waypoints with zero velocity and acceleration at
    both ends. The motion starts at the first waypoint (its t = 0) and is defined only up to
    the last one: asking outside ``[0, duration]`` raises.

    Parameters
    ----------
    t : array_like, shape (n,)
        Strictly increasing times (s), n ≥ 2; any start.
    position : array_like, shape (n, 3)
        Positions (m, NED).
    ypr : array_like, shape (n, 3), optional
        Yaw, pitch, roll (rad) at each waypoint for ``orientation="given"`` (yaw and roll are
        unwrapped, then splined the same way, at rest at both ends). None: all zero. Ignored
        for ``"follow"``.
    orientation : {"given", "follow"}, default "given"
        ``"follow"`` derives the attitude from the path: yaw along the horizontal velocity,
        pitch along the climb ``atan2(−v_d, |v_h|)``, roll of a coordinated turn
        ``atan(|v|·ψ̇/g)``.
    g : float, default G0
        Gravity (m/s²) of the coordinated-turn roll of ``"follow"``.
    name : str, default "waypoints"
        A name for reports, plots and error messages.

    Attributes
    ----------
    duration : float
        ``t[-1] − t[0]`` (s).
    time_offset : float
        ``t[0]`` (s): the source time of the motion's t = 0.
    breakpoints : ndarray, shape (n,)
        The waypoint times from 0 (s).
    bounded : bool
        True: runs stop at the last whole sample inside the route.

    Raises
    ------
    ImunavError
        If the times are not strictly increasing (naming the waypoint), there are fewer than
        2 waypoints, ``orientation`` is unknown, the arrays are not finite or their lengths
        differ, or — for ``"follow"`` — the horizontal velocity vanishes somewhere inside the
        route (the heading is undefined there; checked on a grid of 64 points per leg). Every
        method raises for times outside ``[0, duration]`` (beyond 1e-9 s).

    Examples
    --------
    A 100 m move north in 20 s, facing along the path:

    >>> m = WaypointMotion([0.0, 20.0], [[0, 0, 0], [100, 0, 0]], orientation="follow")
    >>> float(m.velocity([10.0])[0, 0])                   # fastest half-way (m/s)
    9.375
    >>> m.velocity([0.0, 20.0]).tolist()                  # at rest at both ends
    [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]
    """

    def __init__(self, t, position, ypr=None, *, orientation: str = "given", g: float = G0,
                 name: str = "waypoints"):
        t = _check_times(t, "waypoint")
        n = t.size
        if n < 2:
            raise ImunavError(f"{n} waypoint(s): a route needs at least 2")
        if orientation not in ORIENTATIONS:
            raise ImunavError(f"orientation must be one of {ORIENTATIONS}, got {orientation!r}")
        p = as_float_array(position, "position", last=3)
        if p.shape[0] != n:
            raise ImunavError(f"{n} times but {p.shape[0]} positions")
        self.time_offset = float(t[0])
        tt = t - t[0]
        self.duration = float(tt[-1])
        self.name, self.orientation, self.g = name, orientation, float(g)
        self.breakpoints = tt
        self._pos = _at_rest_spline(tt, p)
        if orientation == "given":
            a = np.zeros((n, 3)) if ypr is None else as_float_array(ypr, "ypr", last=3)
            if a.shape[0] != n:
                raise ImunavError(f"{n} waypoints but {a.shape[0]} attitudes")
            a = a.copy()
            a[:, 0] = np.unwrap(a[:, 0])
            a[:, 2] = np.unwrap(a[:, 2])
            self._eul = _at_rest_spline(tt, a)
        else:
            from scipy.interpolate import BSpline, PPoly

            d = self._pos.derivative(1)
            pps = [PPoly.from_spline(BSpline(d.t, d.c[:, i], d.k)) for i in range(3)]
            x = pps[0].x
            keep = np.diff(x) > 0                          # drop the repeated end knots
            c = np.stack([pp.c for pp in pps], axis=-1)    # (k+1, pieces, 3), highest first
            self._pieces = (x[:-1][keep], np.diff(x)[keep], c[::-1][:, keep])
            self._check_heading()

    # ------------------------------------------------------------------ attitude
    def _euler_and_rates(self, t: FloatArray) -> tuple[FloatArray, FloatArray]:
        if self.orientation == "given":
            return self._eul(t), self._eul.derivative(1)(t)
        return self._follow(t)

    def attitude(self, t):
        t = self._t(t)
        return euler_to_quat(self._euler_and_rates(t)[0])

    def angular_rate(self, t):
        t = self._t(t)
        e, r = self._euler_and_rates(t)
        return euler_rates_to_body(e, r)

    def _w(self, t: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray, FloatArray]:
        """The velocity direction carrier ``w`` and its first two derivatives, with
        ``v = s(t)·w``: ``s = τ²`` near a rest end (τ the time from that end: v and a vanish
        there, so v/τ² is a polynomial), 1 elsewhere. Returns ``(w, w', w'', s, s')``."""
        starts, lengths, coef = self._pieces            # coef: (deg+1, m, 3), lowest power first
        shape = t.shape
        t = t.ravel()
        j = np.clip(np.searchsorted(starts, t, side="right") - 1, 0, starts.size - 1)
        tau0 = t - starts[j]
        L = lengths[j]
        a = coef[:, j]                                   # (deg+1, n, 3)
        deg = a.shape[0] - 1
        near_start = (j == 0) & (tau0 <= L / 2)
        near_end = (j == starts.size - 1) & ~near_start
        shift = np.where(near_end, L, 0.0)                # τ = τ0 − shift
        tau = tau0 - shift
        end = near_start | near_end
        b = _reexpand(a, shift)                           # v = Σ b_i τ^i
        m = np.where(end, 2, 0)                           # v = τ^m w
        w = np.zeros((t.size, 3))
        w1 = np.zeros((t.size, 3))
        w2 = np.zeros((t.size, 3))
        for i in range(deg + 1):
            e = i - m                                     # power of τ in w
            ok = e >= 0
            coef_i = np.where(ok[:, None], b[i], 0.0)
            ee = np.maximum(e, 0)
            w += coef_i * (tau ** ee)[:, None]
            w1 += np.where((e >= 1)[:, None], coef_i * (ee * tau ** np.maximum(ee - 1, 0))[:, None], 0)
            w2 += np.where((e >= 2)[:, None],
                           coef_i * (ee * (ee - 1) * tau ** np.maximum(ee - 2, 0))[:, None], 0)
        s = np.where(end, tau ** 2, 1.0)
        s1 = np.where(end, 2 * tau, 0.0)

        def r(x):
            return x.reshape(shape + x.shape[1:])
        return r(w), r(w1), r(w2), r(s), r(s1)

    def _follow(self, t: FloatArray) -> tuple[FloatArray, FloatArray]:
        w, w1, w2, s, s1 = self._w(t)
        wn, we, wd = np.moveaxis(w, -1, 0)
        wn1, we1, wd1 = np.moveaxis(w1, -1, 0)
        wn2, we2, _ = np.moveaxis(w2, -1, 0)
        h2 = wn * wn + we * we
        h = np.sqrt(h2)
        if np.any(h <= 1e-12 * np.maximum(np.linalg.norm(w, axis=-1), 1e-300)):
            k = int(np.argmin(h / np.maximum(np.linalg.norm(w, axis=-1), 1e-300)))
            raise ImunavError(f"orientation \"follow\": the horizontal velocity vanishes near "
                              f"t = {np.ravel(t)[k]:.6g} s (heading undefined); use "
                              "orientation = \"given\"")
        cross = wn * we1 - we * wn1
        yaw = np.arctan2(we, wn)
        dyaw = cross / h2
        dot_h = wn * wn1 + we * we1
        ddyaw = (wn * we2 - we * wn2) / h2 - 2 * cross * dot_h / (h2 * h2)
        pitch = np.arctan2(-wd, h)
        wn_2 = h2 + wd * wd
        dh = dot_h / h
        dpitch = (-wd1 * h + wd * dh) / wn_2
        # speed V = s·|w|, V̇ = s'·|w| + s·(w·w')/|w|
        wabs = np.sqrt(wn_2)
        V = s * wabs
        dV = s1 * wabs + s * (wn * wn1 + we * we1 + wd * wd1) / wabs
        u = V * dyaw / self.g
        roll = np.arctan(u)
        droll = (dV * dyaw + V * ddyaw) / self.g / (1 + u * u)
        return (np.stack([yaw, pitch, roll], -1), np.stack([dyaw, dpitch, droll], -1))

    def _check_heading(self, per_piece: int = 64) -> None:
        x = self.breakpoints
        grid = np.concatenate([np.linspace(a, b, per_piece, endpoint=False)
                               for a, b in zip(x[:-1], x[1:], strict=True)] + [[x[-1]]])
        self._follow(grid)

    def __repr__(self) -> str:
        return (f"WaypointMotion({self.breakpoints.size} waypoints over {self.duration:g} s, "
                f"orientation={self.orientation!r})")


def _reexpand(coef: FloatArray, shift: FloatArray) -> FloatArray:
    """Coefficients of ``Σ a_j (τ + shift)^j`` in powers of τ (lowest first); ``coef``
    (deg+1, n, 3), ``shift`` (n,)."""
    from math import comb

    deg = coef.shape[0] - 1
    out = np.zeros_like(coef)
    for j in range(deg + 1):
        for i in range(j + 1):
            out[i] += comb(j, i) * coef[j] * (shift ** (j - i))[:, None]
    return out
