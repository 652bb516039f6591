"""Aided navigation: the error-state (feedback) Kalman filter that fuses the strapdown with
GNSS, a barometer, a heading reference, vehicle constraints and zero-velocity updates, and its
Rauch–Tung–Striebel smoother.

The error state (:class:`AidedSystem`) is the navigation error of
:mod:`~imunav.estimation.error_model` (``φ``, ``δv``, ``δp``), then every sensor-error state the
IMU model has — each term's own linearisation (:meth:`imunav.sensors.terms.Term.linearise`:
biases, Gauss–Markov banks, random walks, scale factors, misalignments, g-sensitivity) — then
the aids' own states (a Gauss–Markov GNSS position error, the barometer's bias;
:mod:`~imunav.estimation.measurements`). Its continuous dynamics along a trajectory are the
error model's ``[[A, B], [0, diag(D)]]`` with every source's ``B`` side by side, and a step is
discretised exactly as in the covariance analysis: ``Φ`` in closed form
(:meth:`~imunav.estimation.error_model.FlatErrorModel.transition`), ``Q_d`` by 6-node
Gauss–Legendre on that exact transition (only the columns with white inputs).

The loop (:func:`run_filter`):

1. the strapdown (any algorithm of the family, :mod:`imunav.strapdown.registry`) integrates
   the IMU samples, compensated by the current estimates of the sensor errors, from one
   measurement epoch to the next, at the IMU rate;
2. the covariance is propagated on its own step (``covariance_step``, default 0.1 s, ending at
   every measurement epoch), linearised along the estimated trajectory of that step (its
   midpoint attitude, its mean specific force ``Δv_n/h − g_n``, its mean body rate and force);
3. at an epoch each reading is predicted from the navigation state (a reading between two IMU
   samples from the nearest one, moved by ``v·dt``), gated (χ² of its innovation, probability
   ``gate``; rejections counted) and used in a Joseph-form update
   (:func:`~imunav.estimation.kalman.update`), one sensor after another;
4. the estimate is fed back: the navigation state corrected (``q ← exp(φ̂) ⊗ q``,
   ``v ← v − δv̂``, ``p ← p − δp̂``), the sensor and aid estimates moved by their part
   (``ŝ ← ŝ + x̂``; between epochs a Gauss–Markov estimate decays as its state does), and the
   error state starts again from zero.

Standard deviations are exact at the covariance epochs; at the IMU samples in between they are
interpolated linearly in variance. The smoother keeps, per measurement epoch, the filtered
covariance, the correction and the linearisation of each covariance step; its backward pass
rebuilds the steps' ``(Φ, Q_d)`` and applies :func:`~imunav.estimation.smoother.rts_step` in the
coordinates of the uncorrected state at each epoch (there the predicted error is zero and the
filtered one is the correction ``x̂``), so the smoothed error of the corrected state is
``x^s − x̂``.

May import: ``imunav.core``, ``imunav.sensors``, ``imunav.strapdown``, ``imunav.estimation``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from imunav.core.kernels import FloatArray, quat_exp, quat_mul, quat_to_dcm, skew
from imunav.core.rotations import quat_normalize
from imunav.core.states import States
from imunav.core.threads import limit_blas
from imunav.core.validation import ImunavError, as_float_array, check_positive
from imunav.estimation.discretisation import GAUSS_LEGENDRE, phi_functions
from imunav.estimation.error_model import (
    DP,
    DV,
    FLAT,
    NAV,
    PHI,
    TRIAD_ROWS,
    ErrorSource,
    FlatErrorModel,
    Trajectory,
    linearise,
)
from imunav.estimation.kalman import update
from imunav.estimation.measurements import (
    Baro,
    GnssFix,
    Heading,
    Measurement,
    NavPoint,
    Nhc,
    Zupt,
    euler_jacobian,
)
from imunav.estimation.smoother import rts_gain
from imunav.sensors.aiding import AidingConfig, AidingData, InitialConfig, Readings, shoe_intervals
from imunav.sensors.models import ImuModel
from imunav.sensors.signals import ImuSignals
from imunav.strapdown.registry import resolve

__all__ = ["SD_COLUMNS", "AidedSystem", "FilterResult", "Innovations", "build_measurements",
           "nav_sd", "run_filter"]

#: The standard-deviation columns of the filter's output, in order (m, m/s, rad).
SD_COLUMNS = ("sd_pn", "sd_pe", "sd_pd", "sd_vn", "sd_ve", "sd_vd", "sd_roll", "sd_pitch",
              "sd_yaw")


class AidedSystem:
    """The filter's error state and its exact discrete dynamics.

    Parameters
    ----------
    imu : ImuModel or None
        The IMU model the filter assumes (None: ideal).
    measurements : list of Measurement
        The aids (their own states are appended after the IMU's).
    h : float
        IMU sample interval (s).
    kind : {"rates", "increments"}
        The signal kind.
    decimate : int
        Internal samples per output sample of the IMU.
    peaks : tuple of float
        Largest ``|ω_b|`` and ``|f_b|`` of the record (range warnings).
    initial : InitialConfig, optional
        Initial navigation uncertainty (default none).
    model : FlatErrorModel
        The error model (its ``sensor_input`` and ``transition``).

    Attributes
    ----------
    n : int
        Size of the error state.
    layout : dict
        ``{name: slice}``: ``"nav"`` (9), then each sensor term (``"gyro.bias"``, …), then each
        aid state (``"gnss.correlated"``, ``"baro.bias"``).
    sources : list of ErrorSource
        The IMU sources with states, in layout order.
    Qc : ndarray, shape (n,)
        Diagonal PSD of the white inputs (the IMU's white noise on the φ and δv rows, the
        driving noise of every state).
    P0 : ndarray, shape (n, n)
    warnings : list of str
        From the terms without a linear model.
    """

    def __init__(self, imu: ImuModel | None, measurements: list[Measurement], *, h: float,
                 kind: str = "increments", decimate: int = 1, peaks=(0.0, 0.0),
                 initial: InitialConfig | None = None, model: FlatErrorModel = FLAT):
        imu = imu or ImuModel(name="ideal")
        self.model, self.h, self.imu = model, float(h), imu
        traj0 = Trajectory(self.h, np.zeros(1), np.zeros((0, 3, 3)), np.zeros((0, 3)),
                           np.zeros((0, 3)), np.zeros((0, 3)), float(peaks[0]), float(peaks[1]))
        sources, self.warnings = linearise(imu, traj0, kind, decimate)
        q_nav = np.zeros(NAV)
        self.sources: list[ErrorSource] = []
        for s in sources:
            if s.differenced:
                # a quantised increment's carried residual is bounded; the filter treats it as
                # the white noise of quantised rate samples (q²h/12 per sample: conservative)
                q_nav[TRIAD_ROWS[s.states.triad]] += s.states.differenced_white / self.h
                continue
            q_nav += s.noise_psd()[:NAV]
            if s.size:
                self.sources.append(s)
        self.layout: dict[str, slice] = {"nav": slice(0, NAV)}
        D, Qs, P0s = [], [], []
        i = NAV
        for s in self.sources:
            self.layout[s.name] = slice(i, i + s.size)
            D.append(s.states.D)
            Qs.append(s.states.Qs)
            P0s.append(s.states.P0)
            i += s.size
        self.sensor_end = i
        for m in measurements:
            for a in m.states:
                self.layout[a.name] = slice(i, i + a.size)
                D.append(a.D)
                Qs.append(a.Qs)
                P0s.append(a.P0)
                i += a.size
        self.n = i
        for m in measurements:
            m.bind(self.layout)
        self.D = np.concatenate(D) if D else np.zeros(0)
        self.Qc = np.concatenate([q_nav] + Qs)
        self.P0 = np.zeros((self.n, self.n))
        j = NAV
        for P in P0s:
            k = P.shape[0]
            self.P0[j:j + k, j:j + k] = P
            j += k
        init = initial or InitialConfig()
        self.P0[PHI, PHI] = init.attitude_sigma ** 2 * np.eye(3)
        self.P0[DV, DV] = init.velocity_sigma ** 2 * np.eye(3)
        self.P0[DP, DP] = init.position_sigma ** 2 * np.eye(3)
        self._noisy = np.nonzero(self.Qc)[0]
        self._phi: dict[float, tuple] = {}

    def state_names(self) -> list[str]:
        """The blocks of the error state, in order.

        Returns
        -------
        list of str
        """
        return list(self.layout)

    def sensor_input(self, traj: Trajectory) -> FloatArray:
        """``B`` of every state (sensor and aid) along ``traj``.

        Parameters
        ----------
        traj : Trajectory

        Returns
        -------
        ndarray, shape (N, 9, n − 9)
        """
        B = np.zeros((traj.steps, NAV, self.n - NAV))
        for s in self.sources:
            sl = self.layout[s.name]
            B[:, :, sl.start - NAV:sl.stop - NAV] = self.model.sensor_input(traj, s.states)
        return B

    def discretise(self, traj: Trajectory, h: float | None = None
                   ) -> tuple[FloatArray, FloatArray]:
        """The exact discrete system of each step of ``traj``.

        Parameters
        ----------
        traj : Trajectory
            The linearisation (the estimate in the filter, the truth in an analysis).
        h : float, optional
            The step (s); default ``traj.h``.

        Returns
        -------
        Phi, Qd : ndarray, shape (N, n, n)
            ``Φ`` in closed form for the motion held at each step's linearisation point;
            ``Q_d = ∫₀ʰ Φ(s) Qc Φ(s)ᵀ ds`` by 6-node Gauss–Legendre.
        """
        h = traj.h if h is None else float(h)
        B = self.sensor_input(traj)
        Phi = self.model.transition(traj, B, self.D, h)
        n = self.n
        Qd = np.zeros_like(Phi)
        nz = self._noisy
        if nz.size:
            # The sensor rows of Φ(s) are [0, diag(e^{D s})] (the sensor states evolve on their
            # own), so only the navigation rows of Φ(s) need products: the blocks of
            # Φ Qc Φᵀ are Φ_n Qc Φ_nᵀ, Γ diag(Qs e^{Ds}) and diag(Qs e^{2Ds}).
            q = self.Qc[nz]
            qs = self.Qc[NAV:]
            x, w = GAUSS_LEGENDRE
            rows_at = self._flat_rows(traj, B) if self.model is FLAT else None
            for xi, wi in zip((x + 1) / 2 * h, w / 2 * h, strict=True):
                rows = (rows_at(xi) if rows_at is not None else
                        self.model.transition(traj, B, self.D, xi)[:, :NAV])   # (N, 9, n)
                Pn = rows[:, :, nz]
                Qd[:, :NAV, :NAV] += wi * (Pn * q) @ np.swapaxes(Pn, 1, 2)
                if n > NAV:
                    e = np.exp(self.D * xi)
                    Qd[:, :NAV, NAV:] += wi * rows[:, :, NAV:] * (qs * e)
                    Qd[:, range(NAV, n), range(NAV, n)] += wi * qs * e * e
            Qd[:, NAV:, :NAV] = np.swapaxes(Qd[:, :NAV, NAV:], 1, 2)
        return Phi, 0.5 * (Qd + np.swapaxes(Qd, 1, 2))

    def _flat_rows(self, traj: Trajectory, B: FloatArray):
        """``s → Φ(s)[:9]`` of the flat model, its products with ``B`` formed once: the rows of
        :func:`~imunav.estimation.discretisation.flat_transition` (``[I, 0, 0; F s, I, 0;
        F s²/2, I s, I]`` and ``Γ = B φ0 + A B φ1 + A² B φ2``), the φ-functions of each ``s``
        remembered (``tests/test_estimation_filter.py`` checks it against the model's own)."""
        F = skew(traj.f_n)
        N = F.shape[0]
        FB = F @ B[:, 0:3]                                      # A B rows δv, A² B rows δp
        Bv = B[:, 3:6]
        I3 = np.eye(3)

        def rows(s):
            key = float(s)
            phi = self._phi.get(key)
            if phi is None:
                if len(self._phi) > 256:
                    self._phi.clear()
                phi = self._phi[key] = phi_functions(self.D, key)
            p0, p1, p2 = phi
            out = np.zeros((N, NAV, self.n))
            out[:, 0:3, 0:3] = I3
            out[:, 3:6, 0:3] = F * s
            out[:, 3:6, 3:6] = I3
            out[:, 6:9, 0:3] = F * (s * s / 2)
            out[:, 6:9, 3:6] = I3 * s
            out[:, 6:9, 6:9] = I3
            G = out[:, :, NAV:]
            G += B * p0
            G[:, 3:6] += FB * p1
            G[:, 6:9] += Bv * p1 + FB * p2
            return out

        return rows

    def predict(self, P: FloatArray, Phi: FloatArray, Qd: FloatArray) -> FloatArray:
        """``Φ P Φᵀ + Q_d`` for one step, using the structure ``Φ = [[F, Γ], [0, diag(E)]]``
        (the same numbers as the full product, about ``n/9`` times fewer operations).

        Parameters
        ----------
        P, Phi, Qd : ndarray, shape (n, n)

        Returns
        -------
        ndarray, shape (n, n)
        """
        k = NAV
        if self.n == k:
            out = Phi @ P @ Phi.T + Qd
            return 0.5 * (out + out.T)
        F, G = Phi[:k, :k], Phi[:k, k:]
        E = np.diagonal(Phi)[k:]
        Pnn, Pns, Pss = P[:k, :k], P[:k, k:], P[k:, k:]
        X = F @ Pns + G @ Pss                                   # (9, m)
        Y = F @ Pnn + G @ Pns.T                                 # (9, 9)
        out = np.empty_like(P)
        nn = Y @ F.T + X @ G.T
        out[:k, :k] = 0.5 * (nn + nn.T)
        out[:k, k:] = X * E
        out[k:, :k] = out[:k, k:].T
        out[k:, k:] = Pss * np.outer(E, E)
        return out + Qd

    def triad_input(self, triad: str, u: FloatArray, f: FloatArray) -> FloatArray:
        """How the sensor states enter ``triad``'s error: ``δu = M x`` with ``M`` (N, 3, n).

        Parameters
        ----------
        triad : {"gyro", "accel"}
        u : ndarray, shape (N, 3)
            What the triad measures (rate units).
        f : ndarray, shape (N, 3)
            The specific force (the gyro's g-sensitivity).

        Returns
        -------
        ndarray, shape (N, 3, n)
        """
        M = np.zeros((u.shape[0], 3, self.n))
        for s in self.sources:
            if s.states.triad == triad:
                M[:, :, self.layout[s.name]] = s.states.input_matrix(u, f)
        return M

    def decay(self, dt: FloatArray) -> FloatArray:
        """``e^{D dt}`` of the sensor and aid states for each ``dt`` (how their estimates
        evolve between epochs).

        Parameters
        ----------
        dt : ndarray, shape (N,)

        Returns
        -------
        ndarray, shape (N, n − 9)
        """
        return np.exp(np.outer(dt, self.D))


@dataclass
class Innovations:
    """One sensor's innovations over a run.

    Attributes
    ----------
    name : str
    t : ndarray, shape (k,)
        Reading times (s).
    innovation : ndarray, shape (k, m)
        ``predicted − measured``.
    S : ndarray, shape (k, m, m)
        Their covariances ``H P Hᵀ + R``.
    nis : ndarray, shape (k,)
        ``νᵀ S⁻¹ ν``.
    accepted : ndarray of bool, shape (k,)
        False where the gate rejected the reading.
    """

    name: str
    t: FloatArray
    innovation: FloatArray
    S: FloatArray
    nis: FloatArray
    accepted: np.ndarray

    @property
    def normalised(self) -> FloatArray:
        """Whitened innovations ``L⁻¹ ν`` (``S = L Lᵀ``): independent N(0, 1) components for a
        consistent filter.

        Returns
        -------
        ndarray, shape (k, m)
        """
        if not len(self.t):
            return np.zeros_like(self.innovation)
        L = np.linalg.cholesky(self.S)
        return np.linalg.solve(L, self.innovation[..., None])[..., 0]

    def lag1(self) -> FloatArray:
        """Lag-1 autocorrelation of each whitened component over the accepted readings.

        Returns
        -------
        ndarray, shape (m,)
            NaN with fewer than 3 readings.
        """
        z = self.normalised[self.accepted]
        if z.shape[0] < 3:
            return np.full(self.innovation.shape[1], np.nan)
        z = z - z.mean(axis=0)
        return (z[1:] * z[:-1]).sum(axis=0) / (z * z).sum(axis=0)

    def stats(self) -> dict:
        """The statistics ``imunav filter`` prints.

        Returns
        -------
        dict
            ``readings``, ``rejected``, ``dof``, ``mean_nis`` (expected ``dof``), ``rms``
            (per component), ``lag1`` (per component; 95 % band ``±1.96/√readings``).
        """
        acc = self.accepted
        return {"readings": int(len(self.t)), "rejected": int((~acc).sum()),
                "dof": int(self.innovation.shape[1]),
                "mean_nis": float(self.nis[acc].mean()) if acc.any() else float("nan"),
                "rms": np.sqrt((self.innovation[acc] ** 2).mean(axis=0)).tolist()
                if acc.any() else [],
                "lag1": self.lag1().tolist()}


@dataclass
class FilterResult:
    """What the filter (or the smoother) estimated.

    Attributes
    ----------
    states : States
        The estimate at every IMU node (times ``signals.state_times()``).
    sd : ndarray, shape (N + 1, 9)
        Standard deviations :data:`SD_COLUMNS` (m, m/s, rad) at every node.
    epochs : ndarray of int, shape (E,)
        The covariance epochs (node indices).
    P_nav : ndarray, shape (E, 9, 9)
        The navigation-error covariance (``φ``, ``δv``, ``δp``) at each epoch (after its update).
    innovations : dict
        ``{sensor: Innovations}``.
    estimates : ndarray, shape (E, n − 9)
        The sensor and aid error estimates ``ŝ`` at each epoch.
    layout : dict
        The error state's blocks (:attr:`AidedSystem.layout`).
    smoothed : FilterResult or None
        The RTS smoother's result (same fields; its ``innovations`` and ``estimates`` are the
        filter's).
    warnings : list of str
    """

    states: States
    sd: FloatArray
    epochs: np.ndarray
    P_nav: FloatArray
    innovations: dict
    estimates: FloatArray
    layout: dict
    smoothed: FilterResult | None = None
    warnings: list = field(default_factory=list)

    @property
    def t(self) -> FloatArray:
        """Node times (s).

        Returns
        -------
        ndarray
        """
        return self.states.t


def nav_sd(P_nav: FloatArray, q: FloatArray) -> FloatArray:
    """Standard deviations in the output's terms from navigation-error covariances.

    Parameters
    ----------
    P_nav : ndarray, shape (E, 9, 9)
        Covariance of ``φ``, ``δv``, ``δp``.
    q : ndarray, shape (E, 4)
        The attitude there (the Euler-angle σ depend on it).

    Returns
    -------
    ndarray, shape (E, 9)
        :data:`SD_COLUMNS`: north, east, down position; velocity; roll, pitch, yaw.
    """
    T = euler_jacobian(quat_to_dcm(q))                       # rows yaw, pitch, roll
    Pe = T @ P_nav[:, PHI, PHI] @ np.swapaxes(T, 1, 2)
    var = np.concatenate([np.diagonal(P_nav[:, DP, DP], axis1=1, axis2=2),
                          np.diagonal(P_nav[:, DV, DV], axis1=1, axis2=2),
                          np.diagonal(Pe, axis1=1, axis2=2)[:, ::-1]], axis=1)
    return np.sqrt(np.maximum(var, 0.0))


def build_measurements(aiding: AidingConfig) -> dict[str, Measurement]:
    """The measurement objects of the aids in ``aiding``.

    Parameters
    ----------
    aiding : AidingConfig

    Returns
    -------
    dict
        ``{"gnss": GnssFix, "baro": Baro, …}`` for the aids present.
    """
    out: dict[str, Measurement] = {}
    if aiding.gnss:
        g = aiding.gnss
        out["gnss"] = GnssFix(g.position_sigma, g.velocity_sigma, g.lever_arm,
                              g.correlated_sigma, g.correlation_time)
    if aiding.baro:
        out["baro"] = Baro(aiding.baro.sigma, aiding.baro.bias_drift)
    if aiding.heading:
        out["heading"] = Heading(aiding.heading.sigma)
    if aiding.nhc:
        out["nhc"] = Nhc(aiding.nhc.sigma)
    if aiding.zupt:
        out["zupt"] = Zupt(aiding.zupt.sigma)
    return out


def _inject(q, v, p, e):
    """The state corrected by the navigation error ``e`` (9,): ``exp(φ) ⊗ q``, ``v − δv``,
    ``p − δp``."""
    q = quat_mul(quat_exp(e[..., PHI]), q)
    return q / np.linalg.norm(q, axis=-1, keepdims=True), v - e[..., DV], p - e[..., DP]


class _Schedule:
    """Readings mapped to IMU nodes: ``{node: [(sensor, values, dt, t), …]}``."""

    def __init__(self, t0: float, h: float, N: int, align: int):
        self.t0, self.h, self.N, self.align = t0, h, N, align
        self.at: dict[int, list] = {}

    def node(self, t: FloatArray, name: str) -> tuple[np.ndarray, FloatArray]:
        t = np.asarray(t, dtype=float)
        end = self.t0 + self.N * self.h
        tol = 1e-9 * max(1.0, abs(end))
        bad = (t < self.t0 - tol) | (t > end + tol)
        if bad.any():
            i = int(np.argmax(bad))
            raise ImunavError(f"{name} reading {i} at t = {t[i]:.9g} s lies outside the IMU "
                              f"record ({self.t0:.9g} … {end:.9g} s)", argument=name)
        k = np.rint((t - self.t0) / self.h / self.align).astype(int) * self.align
        k = np.clip(k, 0, self.N)
        return k, t - (self.t0 + k * self.h)

    def add(self, name: str, t: FloatArray, values: FloatArray) -> None:
        k, dt = self.node(t, name)
        for j in range(k.size):
            self.at.setdefault(int(k[j]), []).append((name, values[j], float(dt[j]), float(t[j])))


def _zupt_times(intervals: FloatArray, t_nodes: FloatArray) -> FloatArray:
    """The node times inside stance intervals."""
    keep = np.zeros(t_nodes.size, dtype=bool)
    for a, b in np.asarray(intervals, dtype=float).reshape(-1, 2):
        keep |= (t_nodes >= a - 1e-12) & (t_nodes <= b + 1e-12)
    return t_nodes[keep]


def _rates(t0: float, end: float, rate: float) -> FloatArray:
    n = int(np.floor((end - t0) * rate * (1 + 1e-12)))
    return t0 + np.arange(1, n + 1) / rate


@limit_blas
def run_filter(signals: ImuSignals, q0: npt.ArrayLike, v0: npt.ArrayLike, p0: npt.ArrayLike,
               aiding: AidingConfig, data: AidingData, *, imu: ImuModel | None = None,
               algorithm: str | None = None, covariance_step: float = 0.1,
               gate: float | None = 0.9999, smooth: bool = False,
               model: FlatErrorModel = FLAT) -> FilterResult:
    """Aided navigation: the error-state Kalman filter (and, with ``smooth``, the RTS smoother).

    Parameters
    ----------
    signals : ImuSignals
        The IMU record (rates or increments).
    q0 : array_like, shape (4,)
        Initial attitude ``q_nb`` at ``signals.t0``.
    v0, p0 : array_like, shape (3,)
        Initial velocity (m/s) and position (m).
    aiding : AidingConfig
        The aids' noise models (what the filter assumes) and the initial uncertainty; GNSS
        readings inside its ``outages`` are not used.
    data : AidingData
        The readings. NHC without readings: the constraint (zero) at ``[nhc] rate``; ZUPT with
        the ``shoe`` detector: stance from the IMU data, else from ``data.zupt``.
    imu : ImuModel, optional
        The IMU model the filter assumes (default ideal: no sensor states).
    algorithm : str, optional
        Strapdown algorithm (default the most accurate for the kind).
    covariance_step : float
        Longest covariance step (s), rounded to whole IMU intervals.
    gate : float or None
        Probability of the χ² innovation gate (None: no gate).
    smooth : bool
        Also run the RTS smoother (``result.smoothed``).
    model : FlatErrorModel
        The error model.

    Returns
    -------
    FilterResult

    Raises
    ------
    ImunavError
        For a reading outside the IMU record, missing readings of a configured aid, GNSS
        velocity readings missing while ``velocity_sigma`` is set, a non-positive
        ``covariance_step``, or a navigation that turns non-finite.
    """
    if not isinstance(signals, ImuSignals):
        raise ImunavError(f"signals must be ImuSignals, got {type(signals).__name__}")
    check_positive(covariance_step, "covariance_step")
    algo = resolve(signals.kind, algorithm)
    q0 = quat_normalize(as_float_array(q0, "q0", ndim=1, last=4), "q0")
    v0 = as_float_array(v0, "v0", ndim=1, last=3)
    p0 = as_float_array(p0, "p0", ndim=1, last=3)
    kind, h, g = signals.kind, 1.0 / signals.rate, signals.g
    M = len(signals)
    N = M if kind == "increments" else M - 1                   # intervals
    if N < 1:
        raise ImunavError(f"{kind} signals need at least {algo.min_samples} samples")
    t_nodes = signals.state_times()
    t0 = float(t_nodes[0])
    gyro_raw = signals.gyro / h if kind == "increments" else signals.gyro     # rate units
    accel_raw = signals.accel / h if kind == "increments" else signals.accel
    imu = imu or ImuModel(name="ideal")
    meas = build_measurements(aiding)
    peaks = (float(np.linalg.norm(gyro_raw, axis=1).max()),
             float(np.linalg.norm(accel_raw, axis=1).max()))
    system = AidedSystem(imu, list(meas.values()), h=h, kind=kind,
                         decimate=imu.decimation(signals.rate), peaks=peaks,
                         initial=aiding.initial, model=model)
    n = system.n
    warnings = list(system.warnings)

    # ---------------------------------------------------------------- the readings
    sched = _Schedule(t0, h, N, algo.align)
    end = t0 + N * h
    if "gnss" in meas:
        r = data.gnss
        if r is None:
            raise ImunavError("aiding has [gnss] but no GNSS readings were given", argument="data")
        vals = r.values
        if aiding.gnss.velocity_sigma is not None and vals.shape[1] < 6:
            raise ImunavError("[gnss] velocity_sigma is set but the GNSS readings have no "
                              "velocity", argument="data")
        keep = ~aiding.gnss.in_outage(r.t)
        sched.add("gnss", r.t[keep], vals[keep, :meas["gnss"].size])
    for name in ("baro", "heading"):
        if name in meas:
            r = getattr(data, name)
            if r is None:
                raise ImunavError(f"aiding has [{name}] but no {name} readings were given",
                                  argument="data")
            sched.add(name, r.t, r.values)
    if "nhc" in meas:
        r = data.nhc
        if r is None:
            tn = _rates(t0, end, aiding.nhc.rate)
            r = Readings(tn, np.zeros((tn.size, 2)))
        sched.add("nhc", r.t, r.values)
    if "zupt" in meas:
        if aiding.zupt.detector == "shoe":
            w = signals.gyro / h if kind == "increments" else signals.gyro
            a = signals.accel / h if kind == "increments" else signals.accel
            ts = signals.t - (h / 2 if kind == "increments" else 0.0)
            intervals = shoe_intervals(ts, w, a, g=g, window=aiding.zupt.window,
                                       threshold=aiding.zupt.threshold)
        else:
            if data.zupt is None:
                raise ImunavError("[zupt] detector = \"truth\" needs the stance intervals "
                                  "(zupt.csv)", argument="data")
            intervals = data.zupt
        tz = _zupt_times(intervals, t_nodes)
        sched.add("zupt", tz, np.zeros((tz.size, 3)))
    gate = None if gate is None or gate >= 1 else gate
    logs: dict[str, list] = {name: [] for name in meas}

    # ---------------------------------------------------------------- the loop
    m_cov = max(1, int(round(covariance_step / h)))
    m_cov = max(algo.align, m_cov // algo.align * algo.align)
    updates = sorted(k for k in sched.at if k > 0)
    if not updates or updates[-1] != N:
        updates.append(N)
    before, after = algo.context
    own = 1 if kind == "rates" else 0
    q_nodes = np.empty((N + 1, 4))
    v_nodes = np.empty((N + 1, 3))
    p_nodes = np.empty((N + 1, 3))
    q_nodes[0], v_nodes[0], p_nodes[0] = q0, v0, p0
    s_hat = np.zeros(n - NAV)                       # sensor and aid estimates ŝ
    P = system.P0.copy()
    ep_idx, ep_post, ep_prior, ep_est = [0], [P[:NAV, :NAV].copy()], [P[:NAV, :NAV].copy()], \
        [s_hat.copy()]
    segs = []                                       # what the smoother needs per segment
    x_hat = np.zeros(n)
    if 0 in sched.at:                                # readings at the very start
        x_hat, P = _updates(sched.at[0], 0, q_nodes, v_nodes, p_nodes, gyro_raw, accel_raw,
                            s_hat, system, meas, P, gate, logs)
        q_nodes[0], v_nodes[0], p_nodes[0] = _inject(q_nodes[0], v_nodes[0], p_nodes[0],
                                                     x_hat[:NAV])
        s_hat = s_hat + x_hat[NAV:]
        ep_post[0], ep_est[0] = P[:NAV, :NAV].copy(), s_hat.copy()
    a = 0
    comp_sl = [(system.layout[s.name], s.states) for s in system.sources]
    for b in updates:
        x_first, P_first = x_hat, P.copy()
        # strapdown a → b with the compensated samples
        w0, w1 = max(0, a - before), min(M, b + own + after)
        tw = t_nodes[w0:w1] + (h / 2 if kind == "increments" else 0.0)
        decay = system.decay(tw - t_nodes[a])
        gw, aw = gyro_raw[w0:w1].copy(), accel_raw[w0:w1].copy()
        for sl, st in comp_sl:
            s_loc = decay[:, sl.start - NAV:sl.stop - NAV] * s_hat[sl.start - NAV:sl.stop - NAV]
            Mx = st.input_matrix(gyro_raw[w0:w1] if st.triad == "gyro" else accel_raw[w0:w1],
                                 accel_raw[w0:w1])
            corr = np.einsum("nik,nk->ni", Mx, s_loc)
            if st.triad == "gyro":
                gw -= corr
            else:
                aw -= corr
        scale = h if kind == "increments" else 1.0
        with np.errstate(all="ignore"):
            q, v, p = algo.func(gw * scale, aw * scale, h, q_nodes[a], v_nodes[a], p_nodes[a], g,
                                a - w0, b - a)
        if not (np.isfinite(q[-1]).all() and np.isfinite(v[-1]).all()
                and np.isfinite(p[-1]).all()):
            raise ImunavError(f"navigation became non-finite between t = {t_nodes[a]:.9g} and "
                              f"{t_nodes[b]:.9g} s: the signals are too large to integrate")
        q_nodes[a + 1:b + 1], v_nodes[a + 1:b + 1], p_nodes[a + 1:b + 1] = q[1:], v[1:], p[1:]
        # covariance steps a = e0 < e1 < … < eK = b
        bounds = list(range(a, b, m_cov)) + [b]
        traj, lens = _linearisation(bounds, q_nodes, v_nodes, gw, aw, a - w0, kind, h, g)
        P_steps = []
        for lo, hi, L in _groups(lens):
            Phi, Qd = system.discretise(traj.piece(lo, hi), L * h)
            for i in range(hi - lo):
                P = system.predict(P, Phi[i], Qd[i])
                P_steps.append(P)
        s_decayed = s_hat * system.decay(t_nodes[bounds[1:]] - t_nodes[a])
        for j, Pj in enumerate(P_steps[:-1]):
            ep_idx.append(bounds[j + 1])
            ep_post.append(Pj[:NAV, :NAV].copy())
            ep_prior.append(Pj[:NAV, :NAV].copy())
            ep_est.append(s_decayed[j])
        s_hat = s_decayed[-1]
        P_prior = P.copy()
        x_hat = np.zeros(n)
        if b in sched.at:
            x_hat, P = _updates(sched.at[b], b, q_nodes, v_nodes, p_nodes, gyro_raw, accel_raw,
                                s_hat, system, meas, P, gate, logs)
            q_nodes[b], v_nodes[b], p_nodes[b] = _inject(q_nodes[b], v_nodes[b], p_nodes[b],
                                                         x_hat[:NAV])
            s_hat = s_hat + x_hat[NAV:]
        ep_idx.append(b)
        ep_prior.append(P_prior[:NAV, :NAV].copy())
        ep_post.append(P[:NAV, :NAV].copy())
        ep_est.append(s_hat.copy())
        if smooth:
            segs.append((x_first, P_first, traj, lens))
        a = b
    ep_idx = np.asarray(ep_idx)
    ep_post, ep_prior = np.asarray(ep_post), np.asarray(ep_prior)
    states = States(t_nodes, p_nodes, v_nodes, q_nodes, algo.name)
    sd = _node_sd(ep_idx, ep_post, ep_prior, q_nodes, t_nodes)
    innov = {name: _log(name, rows) for name, rows in logs.items()}
    result = FilterResult(states, sd, ep_idx, ep_post, innov, np.asarray(ep_est), system.layout,
                          warnings=warnings)
    if smooth:
        result.smoothed = _smooth(result, segs, x_hat, P, system)
    return result


def _groups(lens: list[int]) -> list[tuple[int, int, int]]:
    """Consecutive runs of equal step lengths: ``(lo, hi, length)``."""
    out, lo = [], 0
    for i in range(1, len(lens) + 1):
        if i == len(lens) or lens[i] != lens[lo]:
            out.append((lo, i, lens[lo]))
            lo = i
    return out


def _linearisation(bounds, q_nodes, v_nodes, gw, aw, off, kind, h, g
                   ) -> tuple[Trajectory, list[int]]:
    """The estimated motion over each covariance step: midpoint attitude, mean ``f_n``, mean
    compensated ``ω_b`` and ``f_b``."""
    lo = np.asarray(bounds[:-1])
    hi = np.asarray(bounds[1:])
    L = hi - lo
    mid = lo + L // 2
    qa = q_nodes[mid]
    odd = L % 2 == 1
    if odd.any():
        qb = q_nodes[np.minimum(mid + 1, q_nodes.shape[0] - 1)]
        sgn = np.sign(np.einsum("ij,ij->i", qa, qb))[:, None]
        qm = qa + sgn * qb
        qa = np.where(odd[:, None], qm / np.linalg.norm(qm, axis=1, keepdims=True), qa)
    H = L * h
    f_n = (v_nodes[hi] - v_nodes[lo]) / H[:, None] - np.array([0.0, 0.0, g])
    a0 = bounds[0]
    if kind == "increments":
        cg = np.concatenate([np.zeros((1, 3)), np.cumsum(gw[off:], axis=0)])
        ca = np.concatenate([np.zeros((1, 3)), np.cumsum(aw[off:], axis=0)])
        om = (cg[hi - a0] - cg[lo - a0]) / L[:, None]
        fb = (ca[hi - a0] - ca[lo - a0]) / L[:, None]
    else:                                       # trapezoid over the rate samples
        tg = np.concatenate([np.zeros((1, 3)), np.cumsum((gw[off:-1] + gw[off + 1:]) / 2, axis=0)])
        ta = np.concatenate([np.zeros((1, 3)), np.cumsum((aw[off:-1] + aw[off + 1:]) / 2, axis=0)])
        om = (tg[hi - a0] - tg[lo - a0]) / L[:, None]
        fb = (ta[hi - a0] - ta[lo - a0]) / L[:, None]
    traj = Trajectory(h, np.concatenate([lo, hi[-1:]]) * h, quat_to_dcm(qa), f_n, om, fb)
    return traj, L.tolist()


def _updates(readings, k, q_nodes, v_nodes, p_nodes, gyro_raw, accel_raw, s_hat, system,
             meas, P, gate, logs):
    """Every reading at node ``k``, one after another; returns the correction and ``P``."""
    n = system.n
    est = np.concatenate([np.zeros(NAV), s_hat])
    i = min(k, gyro_raw.shape[0] - 1)
    u = gyro_raw[i:i + 1]
    f = accel_raw[i:i + 1]
    Mg = system.triad_input("gyro", u, f)[0]
    omega = u[0] - Mg[:, NAV:] @ s_hat
    x = np.zeros(n)
    for name, values, dt, t in readings:
        m = meas[name]
        qk, vk, pk = _inject(q_nodes[k], v_nodes[k], p_nodes[k], x[:NAV])
        nav = NavPoint(qk, vk, pk, omega, dt, est + np.concatenate([np.zeros(NAV), x[NAV:]]), Mg)
        z = m.residual(m.predict(nav), values)
        H = m.jacobian(nav)
        # the state already holds x: the innovation is taken about the corrected state
        up = update(x, P, z + H @ x, H, m.noise(), gate=gate)
        logs[name].append((t, up.innovation, up.S, up.nis, up.accepted))
        x, P = up.x, up.P
    return x, P


def _log(name: str, rows: list) -> Innovations:
    if not rows:
        return Innovations(name, np.zeros(0), np.zeros((0, 0)), np.zeros((0, 0, 0)), np.zeros(0),
                           np.zeros(0, dtype=bool))
    t, nu, S, nis, acc = zip(*rows, strict=True)
    return Innovations(name, np.array(t), np.array(nu), np.array(S), np.array(nis),
                       np.array(acc, dtype=bool))


def _node_sd(ep_idx, ep_post, ep_prior, q_nodes, t_nodes) -> FloatArray:
    """σ at every node: exact at the epochs, variance interpolated linearly in between."""
    N1 = t_nodes.size
    var_post = nav_sd(ep_post, q_nodes[ep_idx]) ** 2
    var_prior = nav_sd(ep_prior, q_nodes[ep_idx]) ** 2
    out = np.empty((N1, 9))
    out[ep_idx] = var_post
    for j in range(ep_idx.size - 1):
        a, b = ep_idx[j], ep_idx[j + 1]
        if b - a > 1:
            w = ((t_nodes[a + 1:b] - t_nodes[a]) / (t_nodes[b] - t_nodes[a]))[:, None]
            out[a + 1:b] = (1 - w) * var_post[j] + w * var_prior[j + 1]
    return np.sqrt(out)


def _smooth(res: FilterResult, segs, x_last, P_last, system: AidedSystem) -> FilterResult:
    """The RTS backward pass over the stored segments (see the module docstring)."""
    xs, Ps = x_last.copy(), P_last.copy()              # at the last node: smoothed = filtered
    n_ep = res.epochs.size
    err = np.zeros((n_ep, NAV))                         # smoothed error of the corrected state
    err_prior = np.zeros((n_ep, NAV))                   # … of the uncorrected (prior) state
    P_s = np.zeros((n_ep, NAV, NAV))
    j = n_ep - 1
    err[j], err_prior[j], P_s[j] = 0.0, x_last[:NAV], P_last[:NAV, :NAV]
    for x_first, P_first, traj, lens in reversed(segs):
        # forward again through the segment's steps: Φ_i and the predicted P_i
        Phis, Pf = [], [P_first]
        Pk = P_first
        for lo, hi, L in _groups(lens):
            Phi, Qd = system.discretise(traj.piece(lo, hi), L * system.h)
            for i in range(hi - lo):
                Phis.append(Phi[i])
                Pk = system.predict(Pk, Phi[i], Qd[i])
                Pf.append(Pk)
        K = len(Phis)
        # backward: epoch j is this segment's end (prior: Pf[K]); then its inner epochs
        for i in range(K - 1, -1, -1):
            x_f = x_first if i == 0 else np.zeros(system.n)
            A = rts_gain(Pf[i], Phis[i], Pf[i + 1])
            xs = x_f + A @ xs
            Ps = Pf[i] + A @ (Ps - Pf[i + 1]) @ A.T
            Ps = 0.5 * (Ps + Ps.T)
            j -= 1
            err_prior[j] = xs[:NAV]
            err[j] = xs[:NAV] - x_f[:NAV]
            P_s[j] = Ps[:NAV, :NAV]
    states = res.states
    q, v, p = states.quaternion.copy(), states.velocity.copy(), states.position.copy()
    t = states.t
    ep = res.epochs
    e_nodes = np.zeros((t.size, NAV))
    var_nodes = np.empty((t.size, 9))
    var_ep = nav_sd(P_s, q[ep]) ** 2
    e_nodes[ep] = err
    var_nodes[ep] = var_ep
    for k in range(ep.size - 1):
        a, b = ep[k], ep[k + 1]
        if b - a > 1:
            w = ((t[a + 1:b] - t[a]) / (t[b] - t[a]))[:, None]
            e_nodes[a + 1:b] = (1 - w) * err[k] + w * err_prior[k + 1]
            var_nodes[a + 1:b] = (1 - w) * var_ep[k] + w * var_ep[k + 1]
    q, v, p = _inject(q, v, p, e_nodes)
    sm = States(t, p, v, q, states.algorithm)
    return FilterResult(sm, np.sqrt(var_nodes), ep, P_s, res.innovations, res.estimates,
                        res.layout, warnings=res.warnings)

