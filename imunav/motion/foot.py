"""The foot-mounted walk: the motion of an IMU strapped to a shoe, stride after stride.

:class:`FootWalk` (catalog name ``foot_walk``) is a walk of strides. Each stride of period
``T = 120 / cadence`` (cadence in steps per minute, two steps per stride of one foot) is a
*swing* of ``(1 − stance_fraction) T`` followed by a *stance* of ``stance_fraction · T``:

- **stance** (foot flat on the ground): the foot is exactly at rest, ``v = 0`` and ``ω_b = 0``,
  level (pitch and roll 0) — what zero-velocity updates assume, here exactly true;
- **heel-off → toe-off** (the toe rocker, the first 30 % of the swing): the heel rises and the
  foot rolls about its toe, which stays fixed on the ground;
- **swing** (the middle 60 %): the foot flies forward by one stride length, its pitch passing
  through its minimum ``toe_off_pitch`` just after toe-off and its maximum ``heel_strike_pitch``
  just before heel strike, and turns by the stride's share of a turn (yaw);
- **heel strike → foot flat** (the heel rocker, the last 10 %): the foot rolls down about its
  heel, which stays fixed on the ground, until it is flat.

The IMU sits 6 cm above the sole, 15 cm behind the toe and 10 cm ahead of the heel (:data:`TOE`,
:data:`HEEL`). The route: ``turn_every`` strides per leg, the last ``turn_strides`` of them
turning by ``turn_angle`` in all (positive: to the right, NED yaw), so the default walk goes
round a square of about 27 m; it starts after ``rest`` seconds standing still.

Smoothness: the pitch is three septic (degree-7) Hermite pieces between its extremes, the free
flight of the swing a septic Hermite per axis that matches position, velocity, acceleration and
jerk of the rockers at toe-off and heel strike, the yaw of a turn the septic smoothstep
``35s⁴ − 84s⁵ + 70s⁶ − 20s⁷``. So position, velocity, acceleration and jerk are continuous
everywhere (C³; the pitch and yaw C³ too), the body rate and specific force are continuous with
continuous derivatives, and between the phase boundaries (:attr:`FootWalk.breakpoints`)
everything is analytic: the simulation's exact increments integrate piece by piece. The rockers
are exact rigid-body kinematics (``p = p_pivot − C_nb r_pivot``), so the toe or heel contact
point does not move while the foot rolls over it.

May import: ``imunav.core``, ``imunav.motion.base``.
"""

from __future__ import annotations

from math import factorial

import numpy as np
import numpy.typing as npt

from imunav.core.rotations import FloatArray
from imunav.core.states import States
from imunav.core.validation import ImunavError, as_float_array, check_int, check_positive, show
from imunav.motion.base import BaseMotion, times

__all__ = ["HEEL", "PHASES", "TOE", "FootWalk", "foot_walk"]

#: The toe and heel contact points in the body frame (m; x forward, z down, from the IMU).
TOE = np.array([0.15, 0.0, 0.06])
HEEL = np.array([-0.10, 0.0, 0.06])
#: The swing's events as fractions of the swing: toe-off, pitch minimum, pitch maximum,
#: heel strike.
PHASES = (0.28, 0.40, 0.80, 0.88)
#: Evaluating this far outside [0, duration] (s) is accepted (rounding of sample times).
EDGE = 1e-9


def _septic(L: float, y0, y1) -> FloatArray:
    """Coefficients (lowest power first) of the degree-7 polynomial on ``[0, L]`` with value
    and first three derivatives ``y0`` at 0 and ``y1`` at ``L`` (each (4, ...))."""
    y0, y1 = np.asarray(y0, float), np.asarray(y1, float)
    c = np.zeros((8,) + y0.shape[1:])
    for d in range(4):
        c[d] = y0[d] / factorial(d)
    A = np.array([[factorial(j) / factorial(j - d) * L ** (j - d) for j in range(4, 8)]
                  for d in range(4)])
    rhs = np.stack([y1[d] - sum(factorial(j) / factorial(j - d) * c[j] * L ** (j - d)
                                for j in range(d, 4)) for d in range(4)])
    c[4:] = np.linalg.solve(A, rhs.reshape(4, -1)).reshape(rhs.shape)
    return c


def _least_acceleration(c: FloatArray, L: float) -> FloatArray:
    """The degree-9 flight with the end conditions of the septic ``c`` (8, ...) on ``[0, L]``
    and the least ``∫ |p̈|² dt``: ``c + β e₁ + δ e₂``, ``e₁ = τ⁴ (L − τ)⁴ / L⁸``,
    ``e₂ = τ⁵ (L − τ)⁴ / L⁹`` (zero with three derivatives at both ends), by the normal
    equations of the two free coefficients. Returns (10, ...)."""
    from numpy.polynomial import polynomial as P

    base = P.polypow([L, -1.0], 4) / L ** 8                    # (L − τ)⁴ / L⁸
    e = [np.pad(P.polymul([0, 0, 0, 0, 1.0], base), (0, 1)),
         P.polymul([0, 0, 0, 0, 0, 1.0], base) / L]
    e = [np.pad(x, (0, 10 - x.size)) for x in e]

    def dd(x):
        return P.polyder(x, 2)

    def integral(x, y):
        return P.polyval(L, P.polyint(P.polymul(x, y)))

    G = np.array([[integral(dd(a), dd(b)) for b in e] for a in e])
    W = np.array([[integral(dd(a), dd(np.eye(8)[j])) for j in range(8)] for a in e])
    shape = c.shape[1:]
    coef = -np.linalg.solve(G, W @ c.reshape(8, -1))                # (2, m)
    out = np.concatenate([c.reshape(8, -1), np.zeros((2, coef.shape[1]))])
    out += np.stack(e, 1) @ coef
    return out.reshape((10,) + shape)


def _poly(c: FloatArray, tau: FloatArray, nder: int) -> list[FloatArray]:
    """Value and ``nder`` derivatives of the polynomials ``c`` (8, n, ...) at ``tau`` (n,)."""
    out = []
    cur = c
    for _ in range(nder + 1):
        v = np.zeros(cur.shape[1:])
        for j in range(cur.shape[0] - 1, -1, -1):
            v = v * (tau if v.ndim == 1 else tau[:, None]) + cur[j]
        out.append(v)
        cur = cur[1:] * np.arange(1, cur.shape[0]).reshape((-1,) + (1,) * (cur.ndim - 1))
    return out


def _smoothstep(s: FloatArray) -> tuple[FloatArray, FloatArray]:
    """``S(s) = 35s⁴ − 84s⁵ + 70s⁶ − 20s⁷`` and ``S'(s) = 140 s³ (1 − s)³``, in forms that keep
    their relative precision at both ends (``S(s) = 1 − S(1 − s)``)."""
    r = 1.0 - s
    near = np.minimum(s, r)
    low = near ** 4 * (35 - 84 * near + 70 * near ** 2 - 20 * near ** 3)
    return np.where(s <= 0.5, low, 1.0 - low), 140.0 * (s * r) ** 3


def _pivot(r: FloatArray, th: list[FloatArray]) -> list[FloatArray]:
    """``u = R_y(θ) r`` and its time derivatives up to ``len(th) − 1`` (in the heading frame),
    from θ and its time derivatives ``th``."""
    c, s = np.cos(th[0]), np.sin(th[0])
    zero = np.zeros_like(c)
    u = np.stack([r[0] * c + r[2] * s, zero + r[1], -r[0] * s + r[2] * c], -1)
    du = np.stack([-r[0] * s + r[2] * c, zero, -r[0] * c - r[2] * s], -1)  # ∂u/∂θ
    d2 = -u * np.array([1.0, 0.0, 1.0])                                     # ∂²u/∂θ²
    out = [u]
    if len(th) > 1:
        out.append(du * th[1][:, None])
    if len(th) > 2:
        out.append(d2 * (th[1] ** 2)[:, None] + du * th[2][:, None])
    if len(th) > 3:
        out.append(-du * (th[1] ** 3)[:, None] + 3 * d2 * (th[1] * th[2])[:, None]
                   + du * th[3][:, None])
    return out


def _rot_z(psi: FloatArray, x: FloatArray) -> FloatArray:
    c, s = np.cos(psi), np.sin(psi)
    return np.stack([c * x[..., 0] - s * x[..., 1], s * x[..., 0] + c * x[..., 1], x[..., 2]], -1)


class FootWalk(BaseMotion):
    """A foot-mounted IMU on a walk (see the module docstring).

    Parameters
    ----------
    duration : float
        Seconds (the motion is defined on ``[0, duration]``).
    stride_length : float
        Metres the foot advances per stride (heel to heel of the same foot).
    cadence : float
        Steps per minute (a stride is two steps); the default with ``stride_length`` 1.42 m is
        a normal walk of 1.30 m/s.
    stance_fraction : float
        Fraction of each stride the foot stands flat and still (0.05 … 0.8).
    rest : float
        Seconds standing still before the first stride (≥ 0).
    turn_every : int
        Strides per leg of the route (0: walk straight).
    turn_angle : float
        The turn at the end of each leg (rad; positive to the right), |angle| ≤ π.
    turn_strides : int
        Strides a turn is spread over (1 … ``turn_every``).
    toe_off_pitch : float
        The foot's lowest pitch, just after toe-off (rad, −80° … −5°).
    heel_strike_pitch : float
        Its highest pitch, just before heel strike (rad, 0 … 45°).
    heading : float
        Initial yaw (rad).
    name : str

    Raises
    ------
    ImunavError
        For a parameter outside its range (the message names it).
    """

    bounded = True

    def __init__(self, duration: float = 300.0, *, stride_length: float = 1.42,
                 cadence: float = 110.0, stance_fraction: float = 0.3, rest: float = 2.0,
                 turn_every: int = 20, turn_angle: float = np.pi / 2, turn_strides: int = 2,
                 toe_off_pitch: float = np.radians(-45.0),
                 heel_strike_pitch: float = np.radians(20.0), heading: float = 0.0,
                 name: str = "foot_walk"):
        self.duration = check_positive(duration, "duration")
        self.stride_length = check_positive(stride_length, "stride_length")
        self.cadence = check_positive(cadence, "cadence")
        self.stance_fraction = _within(stance_fraction, "stance_fraction", 0.05, 0.8)
        self.rest = _within(rest, "rest", 0.0, np.inf, "s")
        self.turn_every = check_int(turn_every, "turn_every", 0)
        self.turn_strides = check_int(turn_strides, "turn_strides", 1)
        if self.turn_every and self.turn_strides > self.turn_every:
            raise ImunavError(f"turn_strides must be at most turn_every = {self.turn_every}, "
                              f"got {self.turn_strides}")
        self.turn_angle = _within(turn_angle, "turn_angle", -np.pi, np.pi, "rad")
        self.toe_off_pitch = _within(toe_off_pitch, "toe_off_pitch", np.radians(-80),
                                     np.radians(-5), "rad")
        self.heel_strike_pitch = _within(heel_strike_pitch, "heel_strike_pitch", 0.0,
                                         np.radians(45), "rad")
        self.heading = _within(heading, "heading", -np.inf, np.inf, "rad")
        self.name = str(name)
        self.period = 120.0 / self.cadence
        self.swing = (1.0 - self.stance_fraction) * self.period
        sw = self.swing
        self._events = np.array(PHASES) * sw            # toe-off, θ min, θ max, heel strike
        t_off, t_min, t_max, t_hs = self._events
        # --- pitch: septic pieces 0 → t_min → t_max → swing, extremes with the curvature of
        # a cosine between them
        th0, th1 = self.toe_off_pitch, self.heel_strike_pitch
        kappa = (th1 - th0) / 2 * (np.pi / (t_max - t_min)) ** 2
        self._pitch_knots = np.array([0.0, t_min, t_max, sw])
        ends = [[0, 0, 0, 0], [th0, 0, kappa, 0], [th1, 0, -kappa, 0], [0, 0, 0, 0]]
        # each piece twice: in powers of the time from its start and from its end, each used
        # on its own half, so that θ and its rates near a stance (where they vanish like the
        # fourth power) keep their relative precision instead of cancelling large terms
        self._pitch = []
        for i in range(3):
            L = self._pitch_knots[i + 1] - self._pitch_knots[i]
            self._pitch.append((_septic(L, ends[i], ends[i + 1]),
                                _septic(-L, ends[i + 1], ends[i]), L))
        # --- the route: yaw and stance position before each stride
        K = int(np.floor(max(self.duration + EDGE - self.rest, 0.0) / self.period)) + 1
        k = np.arange(K)
        turn = np.zeros(K)
        if self.turn_every:
            turning = k % self.turn_every >= self.turn_every - self.turn_strides
            turn[turning] = self.turn_angle / self.turn_strides
        self._psi = self.heading + np.concatenate([[0.0], np.cumsum(turn)])        # (K+1,)
        mid = self._psi[:-1] + turn / 2
        step = self.stride_length * np.stack([np.cos(mid), np.sin(mid), np.zeros(K)], -1)
        self._stance = np.concatenate([np.zeros((1, 3)), np.cumsum(step, axis=0)])  # (K+1, 3)
        self._toe = self._stance[:-1] + _rot_z(self._psi[:-1], np.broadcast_to(TOE, (K, 3)))
        self._heel = self._stance[1:] + _rot_z(self._psi[1:], np.broadcast_to(HEEL, (K, 3)))
        # --- the free flight toe-off → heel strike: position, velocity, acceleration, jerk of
        # the rockers at both ends
        a = self._rocker_ends(t_off, self._psi[:-1], self._toe, TOE)
        b = self._rocker_ends(t_hs, self._psi[1:], self._heel, HEEL)
        self._flight = _least_acceleration(_septic(t_hs - t_off, a, b), t_hs - t_off)
        self._flight[:, :, 2] -= self._lift()[:, None]
        # per stride, its coefficients and those of its derivatives: (K, 10 − d, 3)
        self._flight_d = []
        c = self._flight
        for _ in range(3):
            self._flight_d.append(np.ascontiguousarray(np.moveaxis(c, 0, 1)))
            c = c[1:] * np.arange(1, c.shape[0])[:, None, None]
        self._strides = K
        self._cache: tuple | None = None

    # ------------------------------------------------------------------------- pieces
    def _pitch_at(self, tau: FloatArray, nder: int) -> list[FloatArray]:
        """θ and its derivatives at swing times ``tau`` (n,)."""
        j = np.clip(np.searchsorted(self._pitch_knots, tau, side="right") - 1, 0, 2)
        out = [np.zeros(tau.shape) for _ in range(nder + 1)]
        for i in range(3):
            m = j == i
            if not m.any():
                continue
            left, right, L = self._pitch[i]
            x = tau[m] - self._pitch_knots[i]
            late = x > L / 2
            for c, sel, origin in ((left, ~late, 0.0), (right, late, L)):
                if sel.any():
                    cc = np.broadcast_to(c[:, None], (8, int(sel.sum()))).copy()
                    idx = np.nonzero(m)[0][sel]
                    for d, v in enumerate(_poly(cc, x[sel] - origin, nder)):
                        out[d][idx] = v
        return out

    def _rocker_ends(self, tau: float, psi, pivot, r) -> FloatArray:
        """``[p, v, a, j]`` (4, K, 3) of the foot rolling about ``pivot`` at swing time ``tau``."""
        th = [x[0] for x in self._pitch_at(np.array([tau]), 3)]
        u = _pivot(r, [np.full(psi.size, x) for x in th])
        return np.stack([pivot - _rot_z(psi, u[0])] + [-_rot_z(psi, x) for x in u[1:]])

    def _lift(self, clearance: float = 0.01) -> FloatArray:
        """The flight's lift: ``B(x) = 256 x⁴ (1 − x)⁴ (α (1 − x) + γ x)`` (m, up), x the
        fraction of the flight, in powers of the flight time (10 coefficients).

        A septic flight that only matches the rockers would carry the toe and the heel through
        the floor; ``B`` (zero with three derivatives at both ends, so the smoothness stays)
        lifts them: the smallest ``α + γ`` (a linear programme) for which the toe and the heel
        stay at least ``clearance · 256 x⁴ (1 − x)⁴`` above the floor (1 cm at mid-flight).
        The vertical profile does not depend on the stride's heading: one lift for all."""
        from numpy.polynomial import polynomial as P
        from scipy.optimize import linprog

        t_off, _, _, t_hs = self._events
        L = t_hs - t_off
        x = np.linspace(0.0, 1.0, 401)[1:-1]
        tau = t_off + x * L
        th = self._pitch_at(tau, 0)[0]
        z = _poly(self._flight[:, :1, 2].repeat(tau.size, 1), x * L, 0)[0]
        B0 = 256 * (x * (1 - x)) ** 4
        A, b = [], []
        for r in (TOE, HEEL):
            gap = r[2] - (z + _pivot(r, [th])[0][:, 2])      # height above the floor (m)
            A.append(-np.stack([B0 * (1 - x), B0 * x], 1))
            b.append(gap - clearance * B0)
        res = linprog([1.0, 1.0], A_ub=np.concatenate(A), b_ub=np.concatenate(b),
                      bounds=[(0, None)] * 2)
        alpha, gamma = res.x
        quartic = P.polypow([0.0, 1.0, -1.0], 4) * 256                 # 256 x⁴ (1 − x)⁴
        c = P.polymul(quartic, [alpha, gamma - alpha])                  # × (α + (γ − α) x)
        return np.pad(c, (0, 10 - c.size)) / L ** np.arange(10)

    def _state(self, t: npt.ArrayLike, nder: int):
        """Position and derivatives (``nder`` + 1 arrays), yaw, pitch and their rates; the last
        result is kept (the simulation asks for ω_b and f_b at the same times)."""
        t = times(t)
        key = (t.shape, hash(t.tobytes()))
        if self._cache is not None and self._cache[0] == key and self._cache[1] >= nder \
                and np.array_equal(self._cache[2], t):
            return self._cache[3]
        out = self._evaluate(t, max(nder, 2))
        self._cache = (key, max(nder, 2), t.copy(), out)
        return out

    def _evaluate(self, t: FloatArray, nder: int):
        if t.size and (t.min() < -EDGE or t.max() > self.duration + EDGE):
            bad = t.min() if t.min() < -EDGE else t.max()
            raise ImunavError(f"{self.name}: the walk is defined from 0 to {self.duration:g} s, "
                              f"asked at t = {bad:.6g} s")
        shape = t.shape
        t = np.clip(t.ravel(), 0.0, self.duration)
        s = t - self.rest
        k = np.where(s < 0, -1, np.floor(s / self.period)).astype(int)
        k = np.minimum(k, self._strides - 1)
        tau = s - k * self.period
        t_off, _, _, t_hs = self._events
        n = t.size
        pos = [np.zeros((n, 3)) for _ in range(nder + 1)]
        ypr = [np.zeros((n, 3)) for _ in range(2)]          # [yaw, pitch, roll] and rates
        # stance: before the first stride, or after a swing
        still = (k < 0) | (tau >= self.swing)
        ks = np.where(k < 0, 0, k + 1)
        pos[0][still] = self._stance[ks[still]]
        ypr[0][still, 0] = self._psi[ks[still]]
        sw = ~still
        if sw.any():
            ksw, tsw = k[sw], tau[sw]
            th = self._pitch_at(tsw, max(nder, 1))
            yaw = self._psi[ksw].copy()
            dyaw = np.zeros(ksw.size)
            fly = (tsw >= t_off) & (tsw < t_hs)
            toe = tsw < t_off
            heel = tsw >= t_hs
            parts = [np.zeros((ksw.size, 3)) for _ in range(nder + 1)]
            if fly.any():
                L = t_hs - t_off
                x = (tsw[fly] - t_off) / L
                S = _smoothstep(x)
                dpsi = self._psi[ksw[fly] + 1] - self._psi[ksw[fly]]
                yaw[fly] += dpsi * S[0]
                dyaw[fly] = dpsi * S[1] / L
                x = (tsw[fly] - t_off)[:, None]
                for d in range(nder + 1):
                    c = self._flight_d[d][ksw[fly]]                     # (m, 10 − d, 3)
                    v = c[:, -1].copy()
                    for j in range(c.shape[1] - 2, -1, -1):
                        v *= x
                        v += c[:, j]
                    parts[d][fly] = v
            for m, piv, r, kk in ((toe, self._toe, TOE, ksw), (heel, self._heel, HEEL, ksw)):
                if m.any():
                    psi = self._psi[kk[m] + (1 if r is HEEL else 0)]
                    yaw[m] = psi
                    u = _pivot(r, [x[m] for x in th[:nder + 1]])
                    parts[0][m] = piv[kk[m]] - _rot_z(psi, u[0])
                    for d in range(1, nder + 1):
                        parts[d][m] = -_rot_z(psi, u[d])
            for d in range(nder + 1):
                pos[d][sw] = parts[d]
            ypr[0][sw, 0], ypr[0][sw, 1] = yaw, th[0]
            ypr[1][sw, 0], ypr[1][sw, 1] = dyaw, th[1]
        return shape, pos, ypr

    # ------------------------------------------------------------------------- interface
    def position(self, t):
        shape, pos, _ = self._state(t, 0)
        return pos[0].reshape(shape + (3,))

    def velocity(self, t):
        shape, pos, _ = self._state(t, 1)
        return pos[1].reshape(shape + (3,))

    def acceleration(self, t):
        shape, pos, _ = self._state(t, 2)
        return pos[2].reshape(shape + (3,))

    def states(self, t):
        t = as_float_array(t, "t", ndim=1)
        shape, pos, _ = self._state(t, 2)
        return States(t, pos[0], pos[1], self.attitude(t))

    def attitude(self, t):
        shape, _, ypr = self._state(t, 0)
        hz, hy = ypr[0][:, 0] / 2, ypr[0][:, 1] / 2
        cz, sz, cy, sy = np.cos(hz), np.sin(hz), np.cos(hy), np.sin(hy)
        q = np.stack([cz * cy, -sz * sy, cz * sy, sz * cy], -1)        # q_z(ψ) ⊗ q_y(θ)
        return q.reshape(shape + (4,))

    def angular_rate(self, t):
        shape, _, ypr = self._state(t, 0)
        th = ypr[0][:, 1]
        dpsi, dth = ypr[1][:, 0], ypr[1][:, 1]
        w = np.stack([-dpsi * np.sin(th), dth, dpsi * np.cos(th)], -1)  # Z-Y-X rates, roll 0
        return w.reshape(shape + (3,))

    @property
    def breakpoints(self) -> FloatArray:
        """The phase boundaries (s) inside ``(0, duration)``: the pieces between them are
        analytic.

        Returns
        -------
        ndarray
        """
        t_off, t_min, t_max, t_hs = self._events
        start = self.rest + np.arange(self._strides) * self.period
        b = (start[:, None] + np.array([0.0, t_off, t_min, t_max, t_hs, self.swing])).ravel()
        return b[(b > 0) & (b < self.duration)]

    def stance_intervals(self) -> FloatArray:
        """The stance phases ``[t0, t1]`` (s), where the foot is exactly at rest, within
        ``[0, duration]``.

        Returns
        -------
        ndarray, shape (k, 2)
        """
        start = self.rest + np.arange(self._strides) * self.period
        iv = np.stack([start + self.swing, start + self.period], -1)
        if self.rest > 0:
            iv = np.concatenate([[[0.0, self.rest]], iv])
        iv = iv[iv[:, 0] < self.duration]
        iv[:, 1] = np.minimum(iv[:, 1], self.duration)
        return iv

    @property
    def speed(self) -> float:
        """Mean walking speed (m/s): stride length / stride period.

        Returns
        -------
        float
        """
        return self.stride_length / self.period

    def __repr__(self) -> str:
        return (f"FootWalk({self.duration:g} s, stride {self.stride_length:g} m, "
                f"{self.cadence:g} steps/min, {self.speed:.3g} m/s)")


def _within(value, name: str, lo: float, hi: float, unit: str = "") -> float:
    if isinstance(value, bool | np.bool_) or not isinstance(value, int | float | np.number):
        raise ImunavError(f"{name} must be a number{f' ({unit})' if unit else ''}, "
                          f"got {show(value)}")
    v = float(value)
    if not np.isfinite(v) or v < lo or v > hi:
        rng = (f"≥ {lo:g}" if hi == np.inf else f"≤ {hi:g}" if lo == -np.inf
               else f"within [{lo:.4g}, {hi:.4g}]")
        raise ImunavError(f"{name} must be a finite number {rng}{f' ({unit})' if unit else ''}, "
                          f"got {show(value)}")
    return v


def foot_walk(duration: float = 300.0, **params) -> FootWalk:
    """The foot-mounted walk of :class:`FootWalk` (catalog name ``foot_walk``).

    Parameters
    ----------
    duration : float
        Seconds.
    **params
        Any keyword parameter of :class:`FootWalk`.

    Returns
    -------
    FootWalk
    """
    return FootWalk(duration, **params)
