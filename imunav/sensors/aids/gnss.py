"""GNSS: position fixes (and velocity) at an antenna with a body-frame lever arm.

``[gnss]`` of ``AIDING.toml``: ``rate`` (Hz), ``position_sigma`` (m, white), ``velocity_sigma``
(m/s, white; no velocity without it), ``correlated_sigma`` (m) and ``correlation_time`` (s) of a
first-order Gauss–Markov position error, ``correlated_model = "state" | "white"`` (how the
filter treats it: three states of its own, the default, or as white noise of variance
``position_sigma² + correlated_sigma²``, a common simplification whose cost ``imunav assess``
measures), ``lever_arm`` (m, body frame), ``outages = [[t0, t1], …]`` (s: no fix with
``t0 ≤ t ≤ t1``).

Reading ``x, y, z[, vx, vy, vz]`` (flat, NED) or ``lat, lon, alt[, vn, ve, vd]`` (WGS-84;
degrees in ``gnss.csv``, radians in memory). Prediction ``p + v dt + C l + ĉ``
[, ``v + C (ω × l)``], ``ĉ`` the estimate of the Gauss–Markov error.

May import: ``imunav.core``, ``imunav.earth``, ``imunav.motion``, ``imunav.sensors.aids.base``.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from imunav.core.kernels import FloatArray, cross, quat_conj, quat_rotate, skew
from imunav.core.layout import DP, DV, PHI
from imunav.core.validation import ImunavError
from imunav.earth import dcm_ned_to_ecef, earth_rate_ned, ecef_to_geodetic, geodetic_to_ecef, ned_difference
from imunav.sensors.aids.base import (
    AidSpec,
    AidStates,
    Key,
    Measurement,
    Readings,
    TableConfig,
    reading_times,
    register,
)

__all__ = ["GnssConfig", "GnssFix"]


@dataclass(frozen=True)
class GnssConfig(TableConfig):
    """A GNSS receiver: position fixes (and velocity) at ``rate``.

    Attributes
    ----------
    rate : float
        Hz.
    position_sigma : float
        White position noise (m, per axis).
    velocity_sigma : float or None
        White velocity noise (m/s, per axis); None: no velocity.
    correlated_sigma : float
        Stationary σ of a first-order Gauss–Markov position error (m, per axis); 0: none.
    correlation_time : float or None
        Its correlation time (s).
    lever_arm : tuple of float
        The antenna in the body frame (m).
    outages : tuple of (float, float)
        Intervals (s) without fixes, ends included.
    correlated_model : {"state", "white"}
        How the filter treats the correlated error: as three Gauss–Markov states of its own, or
        as white noise (its variance added to ``position_sigma²``) — the simulation draws it
        correlated either way.
    file : str or None
        A GNSS solution to read instead of ``gnss.csv`` (``--gnss``), relative to the
        ``AIDING.toml``.
    format : {"csv", "rtklib"}
        Its format: an RTKLIB ``.pos`` gives each epoch's own σ (``position_sigma`` and
        ``velocity_sigma`` are then optional floors), scaled by ``float_scale`` for a float
        solution and ``single_scale`` for a single, DGPS or SBAS one.
    float_scale, single_scale : float
    min_quality : int
        The worst RTKLIB quality used (1 fixed, 2 float, 3 SBAS, 4 DGPS, 5 single, 6 PPP).
    velocity_delay : float or "auto"
        Seconds the receiver stamps its velocity late (its readings are taken that much later);
        ``"auto"``: estimated from the solution's own positions.
    """

    rate: float
    position_sigma: float | None
    velocity_sigma: float | None = None
    correlated_sigma: float = 0.0
    correlation_time: float | None = None
    lever_arm: tuple[float, float, float] = (0.0, 0.0, 0.0)
    outages: tuple[tuple[float, float], ...] = ()
    correlated_model: str = "state"
    file: str | None = None
    format: str = "csv"
    float_scale: float = 10.0
    single_scale: float = 100.0
    min_quality: int = 6
    velocity_delay: float | str = 0.0

    TABLE = "gnss"
    FIELDS = (
        Key("rate", "Hz", "GNSS rate", required=True, hi=100.0),
        Key("position_sigma", "m", "GNSS position σ", hi=1e4),
        Key("velocity_sigma", "m/s", "GNSS velocity σ", hi=100.0),
        Key("correlated_sigma", "m", "correlated position σ", default=0.0, positive=False,
            hi=1e4),
        Key("correlation_time", "s", "correlation time", hi=1e6),
        Key("lever_arm", "m, body frame", "lever arm", kind="vector",
            default=(0.0, 0.0, 0.0), hi=100.0),
        Key("outages", "s", "outage", kind="intervals", default=()),
        Key("correlated_model", "", "treatment of the correlated error", kind="choice",
            default="state", choices=("state", "white")),
        Key("file", "", "GNSS solution file (relative to the AIDING.toml)", kind="path"),
        Key("format", "", "the file's format", kind="choice", default="csv",
            choices=("csv", "rtklib")),
        Key("float_scale", "", "σ factor of a float solution (RTKLIB Q = 2)", default=10.0,
            hi=1e6),
        Key("single_scale", "", "σ factor of a single/DGPS/SBAS solution (Q ≥ 3)",
            default=100.0, hi=1e6),
        Key("min_quality", "", "the worst RTKLIB quality used (1 fixed, 2 float, … 6 PPP)",
            kind="integer", default=6, hi=6),
        Key("velocity_delay", "s", "how late the receiver stamps its velocity (or \"auto\")",
            kind="delay", default=0.0),
    )

    #: How the filter may treat the correlated error.
    CORRELATED_MODELS = ("state", "white")

    def checked(self) -> GnssConfig:
        """A correlated error needs its correlation time (dropped without one).

        Returns
        -------
        GnssConfig

        Raises
        ------
        ImunavError
            For a correlated error without its correlation time.
        """
        if self.correlated_sigma > 0 and self.correlation_time is None:
            raise ImunavError("[gnss] correlated_sigma needs correlation_time (s)")
        if self.position_sigma is None and self.format != "rtklib":
            raise ImunavError("[gnss] position_sigma (m) is required")
        if self.correlated_sigma == 0 and self.correlation_time is not None:
            return dataclasses.replace(self, correlation_time=None)
        return self

    def check_within(self, start: float, end: float) -> None:
        """Refuse an outage that lies wholly outside the record ``[start, end]`` (s).

        An outage running past the end is kept (GNSS lost until the end); one that starts at or
        after the end, or ends before the start, would silently change nothing.

        Parameters
        ----------
        start, end : float
            The record's first and last time (s).

        Raises
        ------
        ImunavError
            Naming ``[gnss] outages[i]`` and the record's span.
        """
        for i, (t0, t1) in enumerate(self.outages):
            if t0 >= end or t1 <= start:
                raise ImunavError(f"[gnss] outages[{i}] = [{t0:g}, {t1:g}] s lies outside the "
                                  f"record ({start:g} … {end:g} s)", argument="aiding")

    def in_outage(self, t: FloatArray) -> np.ndarray:
        """Whether each time lies in an outage.

        Parameters
        ----------
        t : ndarray
            Times (s).

        Returns
        -------
        ndarray of bool
        """
        t = np.asarray(t, dtype=float)
        bad = np.zeros(t.shape, dtype=bool)
        for t0, t1 in self.outages:
            bad |= (t >= t0) & (t <= t1)
        return bad


def _mv(C: FloatArray, x: FloatArray) -> FloatArray:
    """``C x`` for matrices (…, 3, 3) and vectors (…, 3)."""
    return np.einsum("...ij,...j->...i", C, x)


class GnssFix(Measurement):
    """A GNSS position fix (and velocity) at an antenna with a body-frame lever arm.

    Parameters
    ----------
    position_sigma : float
        White position noise (m).
    velocity_sigma : float, optional
        White velocity noise (m/s); None: position only.
    lever_arm : array_like, shape (3,)
        Antenna in the body frame (m).
    correlated_sigma : float
        Stationary σ (m) of a Gauss–Markov position error, modelled as 3 states; 0: none.
    correlation_time : float, optional
        Its correlation time (s).
    """

    name = "gnss"
    batched = True

    def __init__(self, position_sigma: float, velocity_sigma: float | None = None,
                 lever_arm=(0.0, 0.0, 0.0), correlated_sigma: float = 0.0,
                 correlation_time: float | None = None):
        super().__init__()
        self.position_sigma = float(position_sigma)
        self.velocity_sigma = None if velocity_sigma is None else float(velocity_sigma)
        self.lever = np.asarray(lever_arm, dtype=float)
        self.columns = ("x", "y", "z") + (("vx", "vy", "vz") if velocity_sigma else ())
        if correlated_sigma > 0:
            s2, tau = correlated_sigma ** 2, float(correlation_time)
            self.states = [AidStates("gnss.correlated", np.full(3, -1.0 / tau),
                                     s2 * np.eye(3), np.full(3, 2 * s2 / tau))]

    def _correlated(self, nav) -> FloatArray:
        sl = self.offsets.get("gnss.correlated")
        return np.zeros(3) if sl is None else nav.estimates[..., sl]

    def predict(self, nav):
        # ``p + v dt + C l + ĉ`` [, ``v + C (ω × l)``].
        C = nav.C
        pos = nav.p + nav.v * nav.dt + C @ self.lever + self._correlated(nav)
        if self.velocity_sigma is None:
            return pos
        return np.concatenate([pos, nav.v + _mv(C, np.cross(nav.omega, self.lever))], axis=-1)

    def jacobian(self, nav):
        # position rows [(C l)×] φ + δp + dt δv − x_c;
        # velocity rows [(C (ω × l))×] φ + δv − C [l×] δω
        H = self.zeros_H(nav)
        C = nav.C
        H[..., 0:3, PHI] = skew(C @ self.lever)
        H[..., 0:3, DP] = np.eye(3)
        H[..., 0:3, DV] = nav.dt * np.eye(3)
        sl = self.offsets.get("gnss.correlated")
        if sl is not None:
            H[..., 0:3, sl] = -np.eye(3)
        if self.velocity_sigma is not None:
            H[..., 3:6, PHI] = skew(_mv(C, np.cross(nav.omega, self.lever)))
            H[..., 3:6, DV] = np.eye(3)
            H[..., 3:6, :] -= C @ skew(self.lever) @ nav.gyro_input
        return H

    def noise(self):
        # White position (and velocity) variances.
        r = [self.position_sigma ** 2] * 3
        if self.velocity_sigma is not None:
            r += [self.velocity_sigma ** 2] * 3
        return np.diag(r)

    def localise(self, values, lla):
        # The fix's NED offset from the ellipsoid point below the estimate.
        ref = np.stack([lla[..., 0], lla[..., 1], np.zeros(lla.shape[:-1])], axis=-1)
        return np.concatenate([ned_difference(values[..., :3], ref), values[..., 3:]], axis=-1)


class Gnss(AidSpec):
    """The GNSS aid (see the module docstring)."""

    name = "gnss"
    summary = "GNSS position fixes (and velocity) at an antenna"
    config = GnssConfig
    file = "gnss.csv"
    headers = {"flat": (("t", "x", "y", "z", "vx", "vy", "vz"), ("t", "x", "y", "z")),
               "wgs84": (("t", "lat", "lon", "alt", "vn", "ve", "vd"),
                         ("t", "lat", "lon", "alt"))}
    degrees = ("lat", "lon")
    stream = 0

    def units(self, config):
        return ("m",) * 3 + (("m/s",) * 3 if config.velocity_sigma is not None else ())

    def measurement(self, config, *, truth=False):
        g = config
        if g.position_sigma is None:                 # each epoch's own σ (Aid.sigma)
            g = dataclasses.replace(g, position_sigma=1.0,
                                    velocity_sigma=1.0 if g.velocity_sigma is None else
                                    g.velocity_sigma)
        if g.correlated_model == "white" and g.correlated_sigma > 0 and not truth:
            # the correlated error treated as white: its variance added, no states
            return GnssFix(float(np.hypot(g.position_sigma, g.correlated_sigma)),
                           g.velocity_sigma, g.lever_arm)
        return GnssFix(g.position_sigma, g.velocity_sigma, g.lever_arm, g.correlated_sigma,
                       g.correlation_time)

    def simulate(self, motion, config, t0, duration, rng, imu_rate):
        c = config
        earth = getattr(motion, "frame", "flat") == "wgs84"
        c.check_within(t0, t0 + duration)
        t = reading_times(c.rate, duration, t0)
        q = motion.attitude(t)
        lever = np.asarray(c.lever_arm)
        arm = quat_rotate(q, np.broadcast_to(lever, (t.size, 3)))         # NED
        pos = motion.position(t)
        if not earth:
            pos = pos + arm
        white = rng.normal(0.0, c.position_sigma, (t.size, 3))
        corr = np.zeros((t.size, 3))
        if c.correlated_sigma > 0 and t.size:
            e = rng.normal(0.0, c.correlated_sigma, 3)             # stationary start
            dts = np.diff(np.concatenate([[t0], t]))
            for i, dt in enumerate(dts):
                a = math.exp(-dt / c.correlation_time)
                e = a * e + math.sqrt(1 - a * a) * c.correlated_sigma * rng.normal(0.0, 1.0, 3)
                corr[i] = e
        if earth:                     # the antenna and its NED errors, exactly on the ellipsoid
            C_en = dcm_ned_to_ecef(pos[:, 0], pos[:, 1])
            r = geodetic_to_ecef(pos[:, 0], pos[:, 1], pos[:, 2])
            r = r + np.einsum("nij,nj->ni", C_en, arm + white + corr)
            vals = [np.stack(ecef_to_geodetic(r), axis=-1)]
        else:
            vals = [pos + white + corr]
        if c.velocity_sigma is not None:
            w = motion.angular_rate(t)
            if earth:                 # the body rate relative to the Earth
                w = w - quat_rotate(quat_conj(q), earth_rate_ned(pos[:, 0]))
            vel = motion.velocity(t) + quat_rotate(q, cross(w, np.broadcast_to(lever, w.shape)))
            vals.append(vel + rng.normal(0.0, c.velocity_sigma, (t.size, 3)))
        keep = ~c.in_outage(t)
        return Readings(t[keep], np.concatenate(vals, axis=1)[keep])

    def readings(self, config, data, signals):
        r = super().readings(config, data, signals)
        tn = signals.state_times()
        config.check_within(float(tn[0]), float(tn[-1]))
        if config.velocity_sigma is not None and r.values.shape[1] < 6:
            raise ImunavError("[gnss] velocity_sigma is set but the GNSS readings have no "
                              "velocity", argument="data")
        m = 6 if config.velocity_sigma is not None else 3
        keep = ~config.in_outage(r.t)
        return Readings(r.t[keep], r.values[keep, :m],
                        None if r.sigma is None else r.sigma[keep, :m])


register(Gnss())
