"""The measurement contract: what the filter calls of an aid — its :class:`Measurement`
(prediction from a :class:`NavPoint`, Jacobian, noise, own :class:`AidStates`), with its
readings as an :class:`Aid` (or a spec's :class:`Readings`) — and the attitude helpers the aids'
Jacobians share. Error conventions: see :mod:`imunav.sensors.aids.base`, which re-exports every
name (as does :mod:`imunav.estimation.measurements`).

May import: ``imunav.core``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from imunav.core.kernels import FloatArray, quat_to_dcm
from imunav.core.validation import ImunavError

__all__ = ["Aid", "AidStates", "Measurement", "NavPoint", "Readings", "euler_jacobian",
           "wrap_angle", "yaw_of"]


def wrap_angle(a):
    """An angle (array) wrapped to [−π, π).

    Parameters
    ----------
    a : array_like
        Radians.

    Returns
    -------
    ndarray or float
    """
    return (np.asarray(a, dtype=float) + np.pi) % (2 * np.pi) - np.pi


# ----------------------------------------------------------------------------- readings

@dataclass
class Readings:
    """One sensor's readings: times and values.

    Attributes
    ----------
    t : ndarray, shape (n,)
        Times (s), strictly increasing.
    values : ndarray, shape (n, m)
        The readings (SI): GNSS ``x, y, z[, vx, vy, vz]``, baro ``alt``, heading ``yaw``,
        NHC ``vy, vz``, odometer ``speed``.
    sigma : ndarray, shape (n, m), optional
        Each reading's own standard deviations (an RTKLIB solution gives them); None: the
        aid's configured noise.
    """

    t: FloatArray
    values: FloatArray
    sigma: FloatArray | None = None

    def __len__(self) -> int:
        return int(self.t.shape[0])


# ----------------------------------------------------------------------------- the measurement

@dataclass
class NavPoint:
    """The navigation state a measurement is predicted from.

    In a batch of ``R`` runs every array has a leading run axis (``q`` (R, 4), …); a
    measurement whose :attr:`Measurement.batched` is True handles that, any other is called
    once per run.

    Attributes
    ----------
    q : ndarray, shape ([R,] 4)
        ``q_nb``.
    v, p : ndarray, shape ([R,] 3)
        Velocity (m/s) and position (m), navigation frame (on the Earth: local NED, the
        position the offset from the ellipsoid below the estimate, so ``-p_z`` is the height).
    omega : ndarray, shape ([R,] 3)
        Body rate ``ω_b`` (rad/s), compensated (on the Earth: relative to the Earth).
    dt : float
        Reading time minus the state's time (s).
    estimates : ndarray, shape ([R,] n)
        The filter's estimates of the sensor and aid error states (``ŝ``; zeros in the
        navigation entries).
    gyro_input : ndarray, shape ([R,] 3, n)
        ``δω = gyro_input @ x``: how the sensor states enter the gyro's error.
    """

    q: FloatArray
    v: FloatArray
    p: FloatArray
    omega: FloatArray
    dt: float
    estimates: FloatArray
    gyro_input: FloatArray

    @property
    def C(self) -> FloatArray:
        """``C_nb`` ([R,] 3, 3).

        Returns
        -------
        ndarray
        """
        return quat_to_dcm(self.q)

    def run(self, r: int) -> NavPoint:
        """Run ``r`` of a batch.

        Parameters
        ----------
        r : int

        Returns
        -------
        NavPoint
        """
        return NavPoint(self.q[r], self.v[r], self.p[r], self.omega[r], self.dt,
                        self.estimates[r], self.gyro_input[r])


@dataclass
class AidStates:
    """Error states of an aid itself: ``ẋ = diag(D) x + w``, ``E[w wᵀ] = diag(Qs) δ``.

    Attributes
    ----------
    name : str
        ``"gnss.correlated"``, ``"baro.bias"``, ``"odometer.scale"``.
    D, Qs : ndarray, shape (k,)
        Decay rates (1/s) and driving PSD.
    P0 : ndarray, shape (k, k)
        Initial covariance.
    """

    name: str
    D: FloatArray
    P0: FloatArray
    Qs: FloatArray

    @property
    def size(self) -> int:
        """Number of states.

        Returns
        -------
        int
        """
        return int(self.D.size)


def yaw_of(C: FloatArray) -> FloatArray:
    """Yaw ``atan2(C₁₀, C₀₀)`` of ``C_nb`` (…, 3, 3).

    Parameters
    ----------
    C : ndarray, shape (..., 3, 3)

    Returns
    -------
    ndarray
    """
    return np.arctan2(C[..., 1, 0], C[..., 0, 0])


def euler_jacobian(C: FloatArray) -> FloatArray:
    """``∂[yaw, pitch, roll]/∂φ`` of ``C_est = (I − [φ×]) C`` at ``φ = 0``.

    A rotation ``ε`` in the navigation frame changes the Z-Y-X angles by ``E⁻¹ ε`` with
    ``E = [e_z, R_z(ψ) e_y, R_z(ψ) R_y(θ) e_x]``; the error ``φ`` is the rotation ``−φ``.

    Parameters
    ----------
    C : ndarray, shape (..., 3, 3)
        ``C_nb``.

    Returns
    -------
    ndarray, shape (..., 3, 3)
        Rows yaw, pitch, roll (singular at pitch ±90°).
    """
    psi = np.arctan2(C[..., 1, 0], C[..., 0, 0])
    theta = -np.arcsin(np.clip(C[..., 2, 0], -1.0, 1.0))
    cp, sp, ct, st = np.cos(psi), np.sin(psi), np.cos(theta), np.sin(theta)
    E = np.zeros(C.shape)
    E[..., 2, 0] = 1.0
    E[..., 0, 1], E[..., 1, 1] = -sp, cp
    E[..., 0, 2], E[..., 1, 2], E[..., 2, 2] = cp * ct, sp * ct, -st
    return -np.linalg.inv(E)


class Measurement:
    """One aid's measurement model: prediction, Jacobian, noise.

    Subclasses set :attr:`name`, :attr:`columns` and implement :meth:`predict`,
    :meth:`jacobian` and :meth:`noise`; an aid with error states of its own lists them in
    :attr:`states` and is told where they sit in the filter's state by :meth:`bind`. That is
    the whole contract: the filter (:func:`~imunav.estimation.filters.run_filter`), its
    smoother, the aided covariance analysis and the aided Monte Carlo take any subclass.

    Attributes
    ----------
    name : str
        ``"gnss"``, ``"baro"``, … (a user's own: any name not already used in one run).
    columns : tuple of str
        The reading's components.
    states : list of AidStates
        The aid's own error states.
    angular : bool
        Whether the innovation is an angle (wrapped to [−π, π)).
    gated : bool
        Whether the filter's χ² gate applies to its readings (False: a constraint a detector
        has already decided on, as a zero-velocity update: rejecting it would leave the drift
        it exists to stop unbounded).
    batched : bool
        Whether :meth:`predict` and :meth:`jacobian` take a :class:`NavPoint` of ``R`` runs
        (arrays with a leading run axis) and return ``(R, m)`` and ``(R, m, n)``; False (a
        user's class, by default): the filter calls them run by run.
    """

    name = ""
    columns: tuple[str, ...] = ()
    angular = False
    gated = True
    batched = False

    def __init__(self):
        self.states: list[AidStates] = []
        self.offsets: dict[str, slice] = {}

    @property
    def size(self) -> int:
        """Components of a reading.

        Returns
        -------
        int
        """
        return len(self.columns)

    def bind(self, offsets: dict[str, slice]) -> None:
        """Where the aid's own states sit in the filter's error state.

        Parameters
        ----------
        offsets : dict
            ``{state name: slice}`` of the filter's layout.
        """
        self.offsets = {s.name: offsets[s.name] for s in self.states}

    def predict(self, nav: NavPoint) -> FloatArray:
        """The reading predicted from the navigation state.

        Parameters
        ----------
        nav : NavPoint

        Returns
        -------
        ndarray, shape (m,)
        """
        raise NotImplementedError

    def jacobian(self, nav: NavPoint) -> FloatArray:
        """``H``: ``predicted(est) − predicted(true) ≈ H e``.

        Parameters
        ----------
        nav : NavPoint

        Returns
        -------
        ndarray, shape (m, n)
        """
        raise NotImplementedError

    def noise(self) -> FloatArray:
        """``R`` (m, m).

        Returns
        -------
        ndarray
        """
        raise NotImplementedError

    def residual(self, predicted: FloatArray, reading: FloatArray) -> FloatArray:
        """``predicted − reading`` (angles wrapped).

        Parameters
        ----------
        predicted, reading : ndarray, shape (..., m)

        Returns
        -------
        ndarray, shape (..., m)
        """
        d = np.asarray(predicted, float) - np.asarray(reading, float)
        return (d + np.pi) % (2 * np.pi) - np.pi if self.angular else d

    def localise(self, values: FloatArray, lla: FloatArray) -> FloatArray:
        """A reading made on the WGS-84 Earth in the coordinates :meth:`predict` uses there
        (local NED at the estimate, its origin on the ellipsoid below it): the identity,
        unless the reading holds a geodetic position (GNSS).

        Parameters
        ----------
        values : ndarray, shape ([R,] m)
        lla : ndarray, shape ([R,] 3)
            The estimate's ``[lat, lon, h]`` (rad, rad, m).

        Returns
        -------
        ndarray, shape ([R,] m)
        """
        return values

    def zeros_H(self, nav: NavPoint) -> FloatArray:
        """A zero Jacobian of the right shape for ``nav`` (``(m, n)``, or ``(R, m, n)``).

        Parameters
        ----------
        nav : NavPoint

        Returns
        -------
        ndarray
        """
        return np.zeros(nav.estimates.shape[:-1] + (self.size, nav.estimates.shape[-1]))


@dataclass
class Aid:
    """An aid as the filter takes it: a measurement model and its readings.

    Parameters
    ----------
    measurement : Measurement
        The model (any subclass: imunav's own or a user's).
    t : array_like, shape (N,)
        Reading times (s), non-decreasing.
    values : array_like, shape (N, m)
        The readings (``m = measurement.size``).
    sigma : array_like, shape (N, m), optional
        Each reading's own standard deviations (uncorrelated components); None: the
        measurement's ``noise()``.

    Raises
    ------
    ImunavError
        For a measurement that is not a :class:`Measurement`, shapes that do not fit,
        non-finite values, times out of order, or a non-positive σ.
    """

    measurement: Measurement
    t: FloatArray
    values: FloatArray
    sigma: FloatArray | None = None
    name: str = field(init=False)

    def __post_init__(self):
        m = self.measurement
        if not isinstance(m, Measurement):
            raise ImunavError(f"measurement must be a Measurement (imunav.estimation."
                              f"measurements), got {type(m).__name__}", argument="measurements")
        self.name = m.name or type(m).__name__
        t = np.asarray(self.t, dtype=float).reshape(-1)
        v = np.asarray(self.values, dtype=float)
        if v.ndim == 1 and m.size == 1:
            v = v[:, None]
        if v.shape != (t.size, m.size):
            raise ImunavError(f"aid {self.name}: values must have shape ({t.size}, {m.size}) "
                              f"(one row per reading time, columns {', '.join(m.columns)}), "
                              f"got {v.shape}", argument="measurements")
        if not (np.isfinite(t).all() and np.isfinite(v).all()):
            raise ImunavError(f"aid {self.name}: times and values must be finite",
                              argument="measurements")
        if np.any(np.diff(t) < 0):
            raise ImunavError(f"aid {self.name}: reading times must be in order",
                              argument="measurements")
        if self.sigma is not None:
            s = np.asarray(self.sigma, dtype=float)
            if s.shape != v.shape or not np.isfinite(s).all() or np.any(s <= 0):
                raise ImunavError(f"aid {self.name}: sigma must be positive and finite, shape "
                                  f"{v.shape}", argument="measurements")
            self.sigma = s
        self.t, self.values = t, v

    def __len__(self) -> int:
        return int(self.t.size)
