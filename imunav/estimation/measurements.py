"""Aiding measurements of the error-state filter: one class per aid, as pyins keeps them.

Each measurement knows its **prediction** from the navigation state (and the estimates of its
own error states), its **Jacobian** ``H`` with respect to the error state of
:mod:`imunav.estimation.error_model` (``φ``, ``δv``, ``δp`` at :data:`PHI`, :data:`DV`,
:data:`DP`, then the sensor states, then the aids' own states), its **noise** ``R``, and its
lever arm where it has one. The filter forms ``z = predicted − measured`` and hands ``(z, H, R)``
to :func:`imunav.estimation.kalman.update`.

Error conventions (those of the error model): ``φ`` with ``C_est = (I − [φ×]) C_nb``,
``δv = v_est − v``, ``δp = p_est − p``; a state of a sensor or aid error ``x = s − ŝ`` (the true
error minus its estimate), so that ``δu = M x`` is what is left in a compensated signal. Hence
``predicted − measured ≈ H e − noise`` to first order (tested against finite differences).

=========  ===============================  ============================================
class      reading (SI)                     prediction
=========  ===============================  ============================================
GnssFix    antenna position [, velocity]    ``p + v dt + C l + ĉ`` [, ``v + C (ω × l)``]
Baro       altitude                         ``−(p_z + v_z dt) + b̂``
Heading    yaw                              ``atan2(C₁₀, C₀₀)`` (innovation wrapped)
Nhc        lateral, vertical body velocity  ``(Cᵀ v)_{y,z}``
Zupt       velocity                         ``v``
=========  ===============================  ============================================

``ĉ`` (a Gauss–Markov GNSS position error) and ``b̂`` (the barometer's random-walk bias) are the
estimates of the aids' own states (:class:`AidStates`), carried by the filter beside the IMU's.

May import: ``imunav.core``, ``imunav.estimation.error_model``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from imunav.core.kernels import FloatArray, quat_to_dcm, skew
from imunav.estimation.error_model import DP, DV, PHI

__all__ = ["AidStates", "Baro", "GnssFix", "Heading", "Measurement", "NavPoint", "Nhc", "Zupt",
           "euler_jacobian", "yaw_of"]


@dataclass
class NavPoint:
    """The navigation state a measurement is predicted from.

    Attributes
    ----------
    q : ndarray, shape (4,)
        ``q_nb``.
    v, p : ndarray, shape (3,)
        Velocity (m/s) and position (m), navigation frame.
    omega : ndarray, shape (3,)
        Body rate ``ω_b`` (rad/s), compensated.
    dt : float
        Reading time minus the state's time (s).
    estimates : ndarray, shape (n,)
        The filter's estimates of the sensor and aid error states (``ŝ``; zeros in the
        navigation entries).
    gyro_input : ndarray, shape (3, n)
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
        """``C_nb`` (3, 3).

        Returns
        -------
        ndarray
        """
        return quat_to_dcm(self.q)


@dataclass
class AidStates:
    """Error states of an aid itself: ``ẋ = diag(D) x + w``, ``E[w wᵀ] = diag(Qs) δ``.

    Attributes
    ----------
    name : str
        ``"gnss.correlated"``, ``"baro.bias"``.
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
    """One aid: prediction, Jacobian, noise.

    Subclasses set :attr:`name`, :attr:`columns` and implement :meth:`predict`,
    :meth:`jacobian` and :meth:`noise`; an aid with error states of its own lists them in
    :attr:`states` and is told where they sit in the filter's state by :meth:`bind`.

    Attributes
    ----------
    name : str
        ``"gnss"``, ``"baro"``, ``"heading"``, ``"nhc"``, ``"zupt"``.
    columns : tuple of str
        The reading's components.
    states : list of AidStates
        The aid's own error states.
    angular : bool
        Whether the innovation is an angle (wrapped to [−π, π)).
    """

    name = ""
    columns: tuple[str, ...] = ()
    angular = False

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
        predicted, reading : ndarray, shape (m,)

        Returns
        -------
        ndarray, shape (m,)
        """
        d = np.asarray(predicted, float) - np.asarray(reading, float)
        return (d + np.pi) % (2 * np.pi) - np.pi if self.angular else d

    def _H(self, nav: NavPoint) -> FloatArray:
        return np.zeros((self.size, nav.estimates.size))


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

    def _correlated(self, nav: NavPoint) -> FloatArray:
        sl = self.offsets.get("gnss.correlated")
        return np.zeros(3) if sl is None else nav.estimates[sl]

    def predict(self, nav):
        # ``p + v dt + C l + ĉ`` [, ``v + C (ω × l)``].
        C = nav.C
        pos = nav.p + nav.v * nav.dt + C @ self.lever + self._correlated(nav)
        if self.velocity_sigma is None:
            return pos
        return np.concatenate([pos, nav.v + C @ np.cross(nav.omega, self.lever)])

    def jacobian(self, nav):
        # position rows [(C l)×] φ + δp + dt δv − x_c;
        # velocity rows [(C (ω × l))×] φ + δv − C [l×] δω
        H = self._H(nav)
        C = nav.C
        H[0:3, PHI] = skew(C @ self.lever)
        H[0:3, DP] = np.eye(3)
        H[0:3, DV] = nav.dt * np.eye(3)
        sl = self.offsets.get("gnss.correlated")
        if sl is not None:
            H[0:3, sl] = -np.eye(3)
        if self.velocity_sigma is not None:
            H[3:6, PHI] = skew(C @ np.cross(nav.omega, self.lever))
            H[3:6, DV] = np.eye(3)
            H[3:6] -= C @ skew(self.lever) @ nav.gyro_input
        return H

    def noise(self):
        # White position (and velocity) variances.
        r = [self.position_sigma ** 2] * 3
        if self.velocity_sigma is not None:
            r += [self.velocity_sigma ** 2] * 3
        return np.diag(r)


class Baro(Measurement):
    """Barometric altitude ``−z`` with a random-walk bias.

    Parameters
    ----------
    sigma : float
        White noise (m).
    bias_drift : float
        Random-walk density of the bias (m/√s); 0: no bias state.
    """

    name, columns = "baro", ("alt",)

    def __init__(self, sigma: float, bias_drift: float = 0.0):
        super().__init__()
        self.sigma = float(sigma)
        if bias_drift > 0:
            self.states = [AidStates("baro.bias", np.zeros(1), np.zeros((1, 1)),
                                     np.array([bias_drift ** 2]))]

    def predict(self, nav):
        # ``−(p_z + v_z dt) + b̂``.
        sl = self.offsets.get("baro.bias")
        b = 0.0 if sl is None else float(nav.estimates[sl][0])
        return np.array([-(nav.p[2] + nav.v[2] * nav.dt) + b])

    def jacobian(self, nav):
        # ``−δp_z − dt δv_z − x_b``.
        H = self._H(nav)
        H[0, 8], H[0, 5] = -1.0, -nav.dt
        sl = self.offsets.get("baro.bias")
        if sl is not None:
            H[0, sl] = -1.0
        return H

    def noise(self):
        # ``σ²``.
        return np.array([[self.sigma ** 2]])


class Heading(Measurement):
    """A yaw reference.

    Parameters
    ----------
    sigma : float
        White noise (rad).
    """

    name, columns, angular = "heading", ("yaw",), True

    def __init__(self, sigma: float):
        super().__init__()
        self.sigma = float(sigma)

    def predict(self, nav):
        # ``atan2(C₁₀, C₀₀)``.
        return np.array([float(yaw_of(nav.C))])

    def jacobian(self, nav):
        # The yaw row of :func:`euler_jacobian`.
        H = self._H(nav)
        H[0, PHI] = euler_jacobian(nav.C)[0]
        return H

    def noise(self):
        # ``σ²``.
        return np.array([[self.sigma ** 2]])


class Nhc(Measurement):
    """The non-holonomic constraint: zero lateral and vertical velocity in the body frame.

    Parameters
    ----------
    sigma : float
        How well it holds (m/s).
    """

    name, columns = "nhc", ("vy", "vz")

    def __init__(self, sigma: float):
        super().__init__()
        self.sigma = float(sigma)

    def predict(self, nav):
        # ``(Cᵀ v)_{y,z}``.
        return (nav.C.T @ nav.v)[1:3]

    def jacobian(self, nav):
        # Rows y, z of ``−Cᵀ [v×] φ + Cᵀ δv``.
        H = self._H(nav)
        CT = nav.C.T
        H[:, PHI] = (-CT @ skew(nav.v))[1:3]
        H[:, DV] = CT[1:3]
        return H

    def noise(self):
        # ``σ² I₂``.
        return self.sigma ** 2 * np.eye(2)


class Zupt(Measurement):
    """A zero-velocity update.

    Parameters
    ----------
    sigma : float
        m/s.
    """

    name, columns = "zupt", ("vx", "vy", "vz")

    def __init__(self, sigma: float):
        super().__init__()
        self.sigma = float(sigma)

    def predict(self, nav):
        # ``v``.
        return np.asarray(nav.v, dtype=float).copy()

    def jacobian(self, nav):
        # ``δv``.
        H = self._H(nav)
        H[:, DV] = np.eye(3)
        return H

    def noise(self):
        # ``σ² I₃``.
        return self.sigma ** 2 * np.eye(3)

