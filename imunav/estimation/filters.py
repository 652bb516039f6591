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

**On the rotating Earth** (``earth="wgs84"``) the navigation runs in the inertial frame ``i``
that coincides with ECEF at the record's start (:mod:`imunav.strapdown.earth`), and so does the
error state (:class:`~imunav.estimation.error_model.EarthErrorModel`: φ, δv, δr in ``i``, with
the gravity gradient Γ). The strapdown's body-frame side is the algorithm's own, its
navigation side an :class:`~imunav.strapdown.earth.EarthIntegrator` whose inertial state the
feedback corrects. A reading is predicted by the same measurement classes in the local NED
frame at the estimated position (GNSS positions as their NED offset from it, altitudes above
the ellipsoid, the body rate relative to the Earth for the lever arm), and its Jacobian with
respect to the local errors is carried onto the inertial ones by the exact first-order map
``[φ_n, δv_n, δp_n] = M [φ, δv, δr]`` of :meth:`EarthErrorModel.local
<imunav.estimation.error_model.EarthErrorModel.local>` (``H = H_local M``); the reported
covariances (and the smoother's corrections) are mapped by the same ``M``.

May import: ``imunav.core``, ``imunav.earth``, ``imunav.sensors``, ``imunav.strapdown``,
``imunav.estimation``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
import numpy.typing as npt
from scipy.stats import chi2

from imunav.core.kernels import (
    FloatArray,
    quat_conj,
    quat_exp,
    quat_mul,
    quat_rotate,
    quat_to_dcm,
    skew,
)
from imunav.core.rotations import quat_normalize
from imunav.core.states import States
from imunav.core.threads import limit_blas
from imunav.core.validation import ImunavError, as_float_array, check_positive
from imunav.earth import (
    OMEGA_E,
    curvature_matrix,
    dcm_ecef_to_inertial,
    dcm_ned_to_ecef,
    earth_rate_ned,
    ecef_to_geodetic,
    geodetic_to_ecef,
    gravitation_gradient,
    ned_difference,
    quat_ecef_to_inertial,
    quat_ned_to_ecef,
    radii,
)
from imunav.estimation.discretisation import GAUSS_LEGENDRE, phi_functions
from imunav.estimation.error_model import (
    DP,
    DV,
    EARTH,
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
from imunav.strapdown.earth import EarthIntegrator
from imunav.strapdown.registry import resolve

__all__ = ["SD_COLUMNS", "AidedSystem", "FilterResult", "Innovations", "StepBlocks",
           "build_measurements", "nav_sd", "predict_blocks", "run_filter"]

#: The standard-deviation columns of the filter's output, in order (m, m/s, rad).
SD_COLUMNS = ("sd_pn", "sd_pe", "sd_pd", "sd_vn", "sd_ve", "sd_vd", "sd_roll", "sd_pitch",
              "sd_yaw")


def predict_blocks(P: FloatArray, F: FloatArray, G: FloatArray, E: FloatArray,
                   Qnn: FloatArray, Qns: FloatArray, qss: FloatArray) -> FloatArray:
    """``Φ P Φᵀ + Q_d`` with ``Φ = [[F, G], [0, diag(E)]]`` and ``Q_d`` in the blocks of
    :class:`StepBlocks` — one step of the filter (:meth:`AidedSystem.predict_step`) or a batch
    ``P`` (…, n, n) of the covariance analysis, whose blocks broadcast per row.

    Parameters
    ----------
    P : ndarray, shape (..., n, n)
    F : ndarray, shape (9, 9)
    G : ndarray, shape (9, n − 9)
    E : ndarray, shape (n − 9,)
    Qnn, Qns, qss : ndarray
        ``Q_d``'s navigation block, navigation–sensor block and sensor diagonal (broadcast
        against ``P``'s blocks).

    Returns
    -------
    ndarray, shape of ``P``
    """
    k = NAV
    Pnn, Pns, Pss = P[..., :k, :k], P[..., :k, k:], P[..., k:, k:]
    X = F @ Pns + G @ Pss
    Y = F @ Pnn + G @ np.swapaxes(Pns, -1, -2)
    nn = Y @ F.T + X @ G.T
    out = np.empty_like(P)
    out[..., :k, :k] = 0.5 * (nn + np.swapaxes(nn, -1, -2)) + Qnn
    out[..., :k, k:] = X * E + Qns
    out[..., k:, :k] = np.swapaxes(out[..., :k, k:], -1, -2)
    ss = Pss * (E[:, None] * E[None, :])
    m = E.size
    ss[..., range(m), range(m)] += qss
    out[..., k:, k:] = ss
    return out


@dataclass
class StepBlocks:
    """The discrete system of N steps in blocks (:meth:`AidedSystem.steps`).

    Attributes
    ----------
    Phi : ndarray, shape (N, n, n) or None
        The whole transition (only when asked for).
    F : ndarray, shape (N, 9, 9)
        The navigation block of ``Φ``.
    G : ndarray, shape (N, 9, n − 9)
        ``Γ``: how the sensor and aid states enter the navigation errors over a step.
    E : ndarray, shape (N, n − 9)
        ``e^{D h}``, the diagonal of the sensor block of ``Φ``.
    Qnn : ndarray, shape (N, 9, 9)
        The navigation block of ``Q_d`` (symmetrised).
    Qns : ndarray, shape (N, 9, n − 9)
        Its navigation–sensor block.
    qss : ndarray, shape (n − 9,)
        The diagonal of its sensor block (the same for every step).
    """

    Phi: FloatArray | None
    F: FloatArray
    G: FloatArray
    E: FloatArray
    Qnn: FloatArray
    Qns: FloatArray
    qss: FloatArray


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

    def discretise(self, traj: Trajectory, h: float | None = None, Qc: FloatArray | None = None
                   ) -> tuple[FloatArray, FloatArray]:
        """The exact discrete system of each step of ``traj``.

        Parameters
        ----------
        traj : Trajectory
            The linearisation (the estimate in the filter, the truth in an analysis).
        h : float, optional
            The step (s); default ``traj.h``.
        Qc : ndarray, shape (n,), optional
            Another diagonal PSD of the white inputs (default :attr:`Qc`): ``Q_d`` is linear in
            it, so an analysis can split the process noise by its sources.

        Returns
        -------
        Phi, Qd : ndarray, shape (N, n, n)
            ``Φ`` in closed form for the motion held at each step's linearisation point;
            ``Q_d = ∫₀ʰ Φ(s) Qc Φ(s)ᵀ ds`` by 6-node Gauss–Legendre.
        """
        st = self.steps(traj, h, Qc, full=True)
        n, N = self.n, traj.steps
        Qd = np.zeros((N, n, n))
        Qd[:, :NAV, :NAV] = st.Qnn
        if n > NAV:
            Qd[:, :NAV, NAV:] = st.Qns
            Qd[:, NAV:, :NAV] = np.swapaxes(st.Qns, 1, 2)
            Qd[:, range(NAV, n), range(NAV, n)] = st.qss
        return st.Phi, Qd

    def steps(self, traj: Trajectory, h: float | None = None, Qc: FloatArray | None = None,
              full: bool = False) -> StepBlocks:
        """:meth:`discretise` in the blocks the prediction uses: the same numbers, without
        the ``(N, n, n)`` arrays that are zero but for a diagonal.

        ``Φ = [[F, Γ], [0, diag(E)]]``; ``Q_d = [[Q_nn, Q_ns], [Q_nsᵀ, diag(q_ss)]]`` (the
        sensor and aid states are driven only by their own white noise, so their block of
        ``Q_d`` is diagonal and the same for every step).

        Parameters
        ----------
        traj : Trajectory
        h : float, optional
            The step (s); default ``traj.h``.
        Qc : ndarray, shape (n,), optional
            As :meth:`discretise`.
        full : bool
            Also the whole ``Φ`` (the smoother's gain needs it).

        Returns
        -------
        StepBlocks
        """
        h = traj.h if h is None else float(h)
        B = self.sensor_input(traj)
        n, N, m = self.n, traj.steps, self.n - NAV
        rows_at = self._flat_rows(traj, B) if self.model is FLAT else None
        x, w = GAUSS_LEGENDRE
        xs, ws = (x + 1) / 2 * h, w / 2 * h
        if rows_at is not None:
            # every node's rows at once, and unless the whole Φ is asked for those at s = h:
            # the rows of Φ (the same operations)
            at = rows_at(xs if full else np.append(xs, h))
        if rows_at is not None and not full:
            r = at[-1]
            Phi, F, G = None, r[:, :, :NAV], r[:, :, NAV:]
            E = np.broadcast_to(np.exp(self.D * h), (N, m))
        else:
            Phi = self.model.transition(traj, B, self.D, h)
            F, G = Phi[:, :NAV, :NAV], Phi[:, :NAV, NAV:]
            E = np.diagonal(Phi, axis1=1, axis2=2)[:, NAV:]
        Qnn = np.zeros((N, NAV, NAV))
        Qns = np.zeros((N, NAV, m))
        qss = np.zeros(m)
        Qc = self.Qc if Qc is None else np.asarray(Qc, dtype=float)
        nz = self._noisy if Qc is self.Qc else np.nonzero(Qc)[0]
        if nz.size:
            # The sensor rows of Φ(s) are [0, diag(e^{D s})] (the sensor states evolve on their
            # own), so only the navigation rows of Φ(s) need products: the blocks of
            # Φ Qc Φᵀ are Φ_n Qc Φ_nᵀ, Γ diag(Qs e^{Ds}) and diag(Qs e^{2Ds}).
            q = Qc[nz]
            qs = Qc[NAV:]
            if rows_at is not None:                             # every node at once
                S = xs.size
                Pn = at[:S, :, :, nz]
                W = ws[:, None, None, None]
                QQ = W * (Pn * q) @ np.swapaxes(Pn, -1, -2)
                e = np.exp(np.outer(xs, self.D))
                QN = W * at[:S, :, :, NAV:] * (qs * e)[:, None, None, :] if n > NAV else None
                for i, wi in enumerate(ws):                     # summed in the nodes' order
                    Qnn += QQ[i]
                    if n > NAV:
                        Qns += QN[i]
                        qss += wi * qs * e[i] * e[i]
            for xi, wi in zip(xs, ws, strict=True) if rows_at is None else ():
                rows = self.model.transition(traj, B, self.D, xi)[:, :NAV]   # (N, 9, n)
                Pn = rows[:, :, nz]
                Qnn += wi * (Pn * q) @ np.swapaxes(Pn, 1, 2)
                if n > NAV:
                    e = np.exp(self.D * xi)
                    Qns += wi * rows[:, :, NAV:] * (qs * e)
                    qss += wi * qs * e * e
        return StepBlocks(Phi, F, G, E, 0.5 * (Qnn + np.swapaxes(Qnn, 1, 2)), Qns, qss)

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

        def phis(s):
            key = float(s)
            phi = self._phi.get(key)
            if phi is None:
                if len(self._phi) > 256:
                    self._phi.clear()
                phi = self._phi[key] = phi_functions(self.D, key)
            return phi

        def rows(s):
            """At one ``s`` (N, 9, n); at an array of them (S, N, 9, n): the same numbers."""
            one = np.ndim(s) == 0
            sv = np.atleast_1d(np.asarray(s, dtype=float))
            p0, p1, p2 = (np.stack(p)[:, None, None, :] for p in zip(*map(phis, sv),
                                                                      strict=True))
            sv = sv[:, None, None, None]
            out = np.zeros((sv.shape[0], N, NAV, self.n))
            out[:, :, 0:3, 0:3] = I3
            out[:, :, 3:6, 0:3] = F * sv
            out[:, :, 3:6, 3:6] = I3
            out[:, :, 6:9, 0:3] = F * (sv * sv / 2)
            out[:, :, 6:9, 3:6] = I3 * sv
            out[:, :, 6:9, 6:9] = I3
            G = out[..., NAV:]
            G += B * p0
            G[:, :, 3:6] += FB * p1
            G[:, :, 6:9] += Bv * p1 + FB * p2
            return out[0] if one else out

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

    def predict_step(self, P: FloatArray, st: StepBlocks, i: int) -> FloatArray:
        """:meth:`predict` of step ``i`` of :meth:`steps`: the same numbers (the same products,
        ``Q_d`` added block by block).

        Parameters
        ----------
        P : ndarray, shape (n, n)
        st : StepBlocks
        i : int

        Returns
        -------
        ndarray, shape (n, n)
        """
        k = NAV
        F = st.F[i]
        if self.n == k:
            out = F @ P @ F.T + st.Qnn[i]
            return 0.5 * (out + out.T)
        return predict_blocks(P, F, st.G[i], st.E[i], st.Qnn[i], st.Qns[i], st.qss)

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
        The navigation-error covariance (``φ``, ``δv``, ``δp``) at each epoch (after its update);
        on the Earth that of the local NED errors (``δp`` in metres north, east, down).
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
        ``{"gnss": GnssFix, "baro": Baro, …}`` for the aids present, as the filter assumes them
        (``[gnss] correlated_model = "white"``: no correlated states, the white σ
        ``√(position_sigma² + correlated_sigma²)``).
    """
    out: dict[str, Measurement] = {}
    if aiding.gnss:
        g = aiding.gnss
        if g.correlated_model == "white" and g.correlated_sigma > 0:
            # the correlated error treated as white: its variance added, no states
            out["gnss"] = GnssFix(float(np.hypot(g.position_sigma, g.correlated_sigma)),
                                  g.velocity_sigma, g.lever_arm)
        else:
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


def _schedule(signals: ImuSignals, aiding: AidingConfig, data: AidingData,
              meas: dict[str, Measurement], align: int) -> _Schedule:
    """Every reading the filter uses, mapped to the IMU nodes (GNSS fixes inside the outages
    left out; NHC without readings at its rate; ZUPT over the stance intervals)."""
    kind, h, g = signals.kind, 1.0 / signals.rate, signals.g
    M = len(signals)
    N = M if kind == "increments" else M - 1
    t_nodes = signals.state_times()
    t0 = float(t_nodes[0])
    sched = _Schedule(t0, h, N, align)
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
    return sched


@limit_blas
def run_filter(signals: ImuSignals, q0: npt.ArrayLike, v0: npt.ArrayLike, p0: npt.ArrayLike,
               aiding: AidingConfig, data: AidingData, *, imu: ImuModel | None = None,
               algorithm: str | None = None, covariance_step: float = 0.1,
               gate: float | None = 0.9999, smooth: bool = False,
               model: FlatErrorModel | None = None, earth: str = "flat") -> FilterResult:
    """Aided navigation: the error-state Kalman filter (and, with ``smooth``, the RTS smoother).

    Parameters
    ----------
    signals : ImuSignals
        The IMU record (rates or increments).
    q0 : array_like, shape (4,)
        Initial attitude ``q_nb`` at ``signals.t0`` (on the Earth: relative to local NED).
    v0, p0 : array_like, shape (3,)
        Initial velocity (m/s) and position (m), NED; on the Earth the velocity relative to
        the Earth in local NED and ``p0 = [lat, lon, h]`` (rad, rad, m).
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
    model : FlatErrorModel, optional
        The error model (default the frame's: ``FLAT`` or ``EARTH``).
    earth : {"flat", "wgs84"}
        The navigation frame. On ``"wgs84"`` the GNSS readings are ``[lat, lon, h]`` (rad, rad,
        m) [and NED velocity relative to the Earth], the barometer's the height above the
        ellipsoid, the states and standard deviations those of local NED (positions
        ``[lat, lon, h]``, σ in metres).

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
    if earth not in ("flat", "wgs84"):
        raise ImunavError(f"earth must be 'flat' or 'wgs84', got {earth!r}", argument="earth")
    model = model or (EARTH if earth == "wgs84" else FLAT)
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
    if aiding.gnss is not None:
        aiding.gnss.check_within(t0, float(t_nodes[-1]))
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
    E = _Earth(h, t0, q0, v0, p0) if earth == "wgs84" else None

    # ---------------------------------------------------------------- the readings
    sched = _schedule(signals, aiding, data, meas, algo.align)
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
                            s_hat, system, meas, P, gate, logs, E, t0)
        q_nodes[0], v_nodes[0], p_nodes[0] = (
            _inject(q_nodes[0], v_nodes[0], p_nodes[0], x_hat[:NAV]) if E is None
            else E.correct(t0, x_hat[:NAV]))
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
        bounds = list(range(a, b, m_cov)) + [b]      # covariance steps a = e0 < … < eK = b
        with np.errstate(all="ignore"):
            if E is None:
                q, v, p = algo.func(gw * scale, aw * scale, h, q_nodes[a], v_nodes[a],
                                    p_nodes[a], g, a - w0, b - a)
                ok = (np.isfinite(q[-1]).all() and np.isfinite(v[-1]).all()
                      and np.isfinite(p[-1]).all())
            else:
                qI, vT, loc = E.advance(algo, gw * scale, aw * scale, h, a - w0, b - a)
                ok = loc is not None
        if not ok:
            raise ImunavError(f"navigation became non-finite between t = {t_nodes[a]:.9g} and "
                              f"{t_nodes[b]:.9g} s: the signals are too large to integrate")
        if E is None:
            q_nodes[a + 1:b + 1], v_nodes[a + 1:b + 1], p_nodes[a + 1:b + 1] = q[1:], v[1:], p[1:]
            traj, lens = _linearisation(bounds, q_nodes, v_nodes, gw, aw, a - w0, kind, h, g)
        else:
            q_nodes[a + 1:b + 1], v_nodes[a + 1:b + 1], p_nodes[a + 1:b + 1] = loc
            # in the inertial frame: C_ib, the thrust's mean f_i (g = 0), Γ at the midpoints
            traj, lens = _linearisation([k - a for k in bounds], qI, vT, gw, aw, a - w0, kind,
                                        h, 0.0)
            mid = np.asarray(bounds[:-1]) + np.asarray(lens) // 2
            r_mid = E.r_inertial(t_nodes[mid], p_nodes[mid])
            traj = Trajectory(h, traj.t + t_nodes[a] - t0, traj.C, traj.f_n, traj.omega,
                              traj.f_b, traj.max_rate, traj.max_force, "wgs84",
                              gravitation_gradient(r_mid))
        P_steps = []
        for lo, hi, L in _groups(lens):
            st = system.steps(traj.piece(lo, hi), L * h)
            for i in range(hi - lo):
                P = system.predict_step(P, st, i)
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
                                s_hat, system, meas, P, gate, logs, E, t_nodes[b])
            q_nodes[b], v_nodes[b], p_nodes[b] = (
                _inject(q_nodes[b], v_nodes[b], p_nodes[b], x_hat[:NAV]) if E is None
                else E.correct(t_nodes[b], x_hat[:NAV]))
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
    M_ep = None
    if E is not None:                                # inertial errors → local NED ones
        M_ep = E.output_map(t_nodes[ep_idx], p_nodes[ep_idx], v_nodes[ep_idx])
        MT = np.swapaxes(M_ep, 1, 2)
        ep_post, ep_prior = M_ep @ ep_post @ MT, M_ep @ ep_prior @ MT
    states = States(t_nodes, p_nodes, v_nodes, q_nodes, algo.name, frame=earth)
    sd = _node_sd(ep_idx, ep_post, ep_prior, q_nodes, t_nodes)
    innov = {name: _log(name, rows) for name, rows in logs.items()}
    result = FilterResult(states, sd, ep_idx, ep_post, innov, np.asarray(ep_est), system.layout,
                          warnings=warnings)
    if smooth:
        result.smoothed = _smooth(result, segs, x_hat, P, system, M_ep)
    return result


class _Earth:
    """The navigation side of the filter on the rotating Earth: the inertial state the feedback
    corrects (an :class:`~imunav.strapdown.earth.EarthIntegrator`), and the map of inertial
    errors onto local NED ones."""

    def __init__(self, h: float, t0: float, q0, v0, p0):
        self.t0 = float(t0)
        self.integ = EarthIntegrator(h, t0, q0, v0, p0)

    def advance(self, algo, gw, aw, h, first, count):
        """The body-frame algorithm (g = 0, from zero velocity and position) and the Earth
        integrator over ``count`` intervals: the inertial attitudes and thrust velocities (for
        the linearisation) and the local states at the new nodes."""
        zero = np.zeros(3)
        qI, vT, pT = algo.func(gw, aw, h, self.integ.q_ib, zero, zero, 0.0, first, count)
        if not (np.isfinite(qI[-1]).all() and np.isfinite(vT[-1]).all()
                and np.isfinite(pT[-1]).all()):
            return qI, vT, None
        return qI, vT, self.integ.advance(qI, vT, pT)

    def local(self, t, q_ib, v_i, r_i):
        """Inertial states → ``q_nb``, NED velocity relative to the Earth, ``[lat, lon, h]``."""
        C_ei = np.swapaxes(dcm_ecef_to_inertial(t, self.t0), -1, -2)
        r_e = np.einsum("...ij,...j->...i", C_ei, r_i)
        lat, lon, alt = ecef_to_geodetic(r_e)
        q_in = quat_mul(quat_ecef_to_inertial(t, self.t0), quat_ned_to_ecef(lat, lon))
        v_rel = v_i - np.cross(np.array([0.0, 0.0, OMEGA_E]), r_i)
        v_n = quat_rotate(quat_conj(q_in), v_rel)
        q_nb = quat_mul(quat_conj(q_in), q_ib)
        return q_nb, v_n, np.stack([lat, lon, alt], axis=-1)

    def state(self, t):
        """The integrator's inertial state (the current node) and its local form."""
        ig = self.integ
        return (ig.q_ib, ig.v, ig.r), self.local(t, ig.q_ib, ig.v, ig.r)

    def correct(self, t, e):
        """Feed back the inertial error ``e`` (9,) at the current node; its local state."""
        ig = self.integ
        q = quat_mul(quat_exp(e[PHI]), ig.q_ib)
        ig.q_ib = q / np.linalg.norm(q)
        ig.v = ig.v - e[DV]
        dr = e[DP]
        # the gravitation history of the integrator's multistep rule, moved with the position
        ig.hist = ig.hist - gravitation_gradient(ig.r) @ dr
        ig.r = ig.r - dr
        return self.local(t, ig.q_ib, ig.v, ig.r)

    def reading(self, t, inertial, x, omega, dt, est, gyro_input, name, values):
        """What a measurement class predicts a reading from on the Earth: the state
        ``inertial = (q_ib, v_i, r_i)`` corrected by the navigation error ``x`` (9,) in local
        NED, its origin on the ellipsoid below the estimate (a GNSS fix becomes its NED offset
        from there), the body rate relative to the Earth (an antenna's velocity); and ``M``,
        which carries the local Jacobian onto the inertial errors.

        Returns
        -------
        nav : NavPoint
        values : ndarray
            The reading in those coordinates.
        M : ndarray, shape (9, 9)
        """
        q_i, v_i, r_i = inertial
        qc = quat_mul(quat_exp(x[PHI]), q_i)
        q, v, lla = self.local(t, qc / np.linalg.norm(qc), v_i - x[DV], r_i - x[DP])
        w_rel = omega - quat_to_dcm(q).T @ earth_rate_ned(lla[0])
        nav = NavPoint(q, v, np.array([0.0, 0.0, -lla[2]]), w_rel, dt, est, gyro_input)
        if name == "gnss":
            ref = np.array([lla[0], lla[1], 0.0])
            values = np.concatenate([ned_difference(values[:3], ref), values[3:]])
        return nav, values, self.output_map(t, lla, v)

    def output_map(self, t, lla, v_n):
        """``M`` (…, 9, 9): local NED errors ``[φ_n, δv_n, δp_n]`` of the inertial ones."""
        t = np.asarray(t, dtype=float)
        lat, lon, alt = lla[..., 0], lla[..., 1], lla[..., 2]
        C_in = dcm_ecef_to_inertial(t, self.t0) @ dcm_ned_to_ecef(lat, lon)
        C_ni = np.swapaxes(C_in, -1, -2)
        K = curvature_matrix(lat, alt) @ C_ni
        M = np.zeros(np.shape(lat) + (NAV, NAV))
        M[..., PHI, PHI] = C_ni
        M[..., PHI, DP] = K
        M[..., DV, DV] = C_ni
        M[..., DV, DP] = -C_ni @ skew(np.array([0.0, 0.0, OMEGA_E])) + skew(v_n) @ K
        M[..., DP, DP] = C_ni
        return M

    def r_inertial(self, t, lla):
        """Inertial positions of ``[lat, lon, h]`` at times ``t``."""
        r_e = geodetic_to_ecef(lla[..., 0], lla[..., 1], lla[..., 2])
        return np.einsum("...ij,...j->...i", dcm_ecef_to_inertial(t, self.t0), r_e)


def _inject_local(q, v, lla, e):
    """Local states ``q_nb``, NED velocity, ``[lat, lon, h]`` corrected by the local NED error
    ``e`` (…, 9) (``δp`` in metres)."""
    q = quat_mul(quat_exp(e[..., PHI]), q)
    rn, re = radii(lla[..., 0])
    dp = e[..., DP]
    out = lla.copy()
    out[..., 0] = lla[..., 0] - dp[..., 0] / (rn + lla[..., 2])
    out[..., 1] = lla[..., 1] - dp[..., 1] / ((re + lla[..., 2]) * np.cos(lla[..., 0]))
    out[..., 2] = lla[..., 2] + dp[..., 2]
    return q / np.linalg.norm(q, axis=-1, keepdims=True), v - e[..., DV], out


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
             meas, P, gate, logs, earth=None, t=0.0):
    """Every reading at node ``k``, one after another; returns the correction and ``P``.
    On the Earth (``earth`` the :class:`_Earth` at node ``k``, time ``t``) each reading is
    predicted in local NED at the estimate and ``H`` carried onto the inertial errors."""
    n = system.n
    est = np.concatenate([np.zeros(NAV), s_hat])
    i = min(k, gyro_raw.shape[0] - 1)
    u = gyro_raw[i:i + 1]
    f = accel_raw[i:i + 1]
    Mg = system.triad_input("gyro", u, f)[0]
    omega = u[0] - Mg[:, NAV:] @ s_hat
    x = np.zeros(n)
    if earth is not None:
        (q_i, v_i, r_i), _ = earth.state(t)
    for name, values, dt, t_read in readings:
        m = meas[name]
        est_x = est + np.concatenate([np.zeros(NAV), x[NAV:]])
        if earth is None:
            qk, vk, pk = _inject(q_nodes[k], v_nodes[k], p_nodes[k], x[:NAV])
            nav = NavPoint(qk, vk, pk, omega, dt, est_x, Mg)
        else:
            nav, values, M = earth.reading(t, (q_i, v_i, r_i), x[:NAV], omega, dt, est_x, Mg,
                                           name, values)
        z = m.residual(m.predict(nav), values)
        H = m.jacobian(nav)
        if earth is not None:
            H[:, :NAV] = H[:, :NAV] @ M
        # the state already holds x: the innovation is taken about the corrected state
        up = update(x, P, z + H @ x, H, m.noise(), gate=gate)
        logs[name].append((t_read, up.innovation, up.S, up.nis, up.accepted))
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


def _smooth(res: FilterResult, segs, x_last, P_last, system: AidedSystem, M_ep=None
            ) -> FilterResult:
    """The RTS backward pass over the stored segments (see the module docstring); on the
    Earth ``M_ep`` (E, 9, 9) maps each epoch's inertial errors onto local NED ones."""
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
            st = system.steps(traj.piece(lo, hi), L * system.h, full=True)
            for i in range(hi - lo):
                Phis.append(st.Phi[i])
                Pk = system.predict_step(Pk, st, i)
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
    if M_ep is not None:
        err = np.einsum("nij,nj->ni", M_ep, err)
        err_prior = np.einsum("nij,nj->ni", M_ep, err_prior)
        P_s = M_ep @ P_s @ np.swapaxes(M_ep, 1, 2)
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
    q, v, p = (_inject(q, v, p, e_nodes) if M_ep is None else
               _inject_local(q, v, p, e_nodes))
    sm = States(t, p, v, q, states.algorithm, frame=states.frame)
    return FilterResult(sm, np.sqrt(var_nodes), ep, P_s, res.innovations, res.estimates,
                        res.layout, warnings=res.warnings)



# ----------------------------------------------------------------------------- many runs at once

@dataclass
class BatchResult:
    """What the filter estimated in each of R runs filtered at once (:func:`run_filter_batch`).

    Attributes
    ----------
    t : ndarray, shape (N + 1,)
        Node times (s).
    quaternion : ndarray, shape (N + 1, R, 4)
    velocity, position : ndarray, shape (N + 1, R, 3)
        The estimates at every node.
    epochs : ndarray of int, shape (E,)
        The covariance epochs (node indices).
    P_nav : ndarray, shape (E, R, 9, 9)
        The navigation-error covariance at each epoch after its readings.
    readings : dict
        ``{sensor: readings per run}``.
    rejected : dict
        ``{sensor: (R,) readings the gate rejected}``.
    algorithm : str
    warnings : list of str
    """

    t: FloatArray
    quaternion: FloatArray
    velocity: FloatArray
    position: FloatArray
    epochs: np.ndarray
    P_nav: FloatArray
    readings: dict
    rejected: dict
    algorithm: str
    warnings: list = field(default_factory=list)


@limit_blas
def run_filter_batch(signals: list[ImuSignals], q0: npt.ArrayLike, v0: npt.ArrayLike,
                     p0: npt.ArrayLike, aiding: AidingConfig, data: list[AidingData], *,
                     imu: ImuModel | None = None, algorithm: str | None = None,
                     covariance_step: float = 0.1, gate: float | None = 0.9999,
                     model: FlatErrorModel = FLAT) -> BatchResult:
    """:func:`run_filter` on R runs at once — the same filter, its loop vectorised across runs
    (what a Monte Carlo of the filter needs: the per-step work of one run is mostly call
    overhead).

    Every step is :func:`run_filter`'s, per run: the strapdown of the compensated samples (the
    algorithms take R runs at once), the covariance steps linearised along each run's own
    estimate (one discretisation for all runs' steps), the readings one after another with each
    run's own χ² gate, the feedback. The runs must share the record (kind, rate, times) and the
    reading times (their values differ); the states agree with :func:`run_filter` of each run
    to rounding (``tests/test_aided_assess.py``).

    Parameters
    ----------
    signals : list of ImuSignals
        One record per run.
    q0 : array_like, shape (R, 4) or (4,)
    v0, p0 : array_like, shape (R, 3) or (3,)
        The initial states.
    aiding : AidingConfig
    data : list of AidingData
        One per run.
    imu, algorithm, covariance_step, gate, model
        As :func:`run_filter`.

    Returns
    -------
    BatchResult

    Raises
    ------
    ImunavError
        As :func:`run_filter`, and for runs whose records or reading times differ (a SHOE
        detector on noisy runs: filter them one by one).
    """
    R = len(signals)
    if R < 1 or len(data) != R:
        raise ImunavError(f"run_filter_batch needs one AidingData per run: {R} signals, "
                          f"{len(data)} data", argument="data")
    s0 = signals[0]
    for s in signals:
        if not isinstance(s, ImuSignals):
            raise ImunavError(f"signals must be ImuSignals, got {type(s).__name__}")
        if (s.kind, s.rate, s.g, len(s)) != (s0.kind, s0.rate, s0.g, len(s0)) or \
                not np.array_equal(s.t, s0.t):
            raise ImunavError("run_filter_batch needs runs of one record (kind, rate, g, times)",
                              argument="signals")
    check_positive(covariance_step, "covariance_step")
    algo = resolve(s0.kind, algorithm)
    q0 = np.broadcast_to(quat_normalize(as_float_array(q0, "q0", last=4), "q0"), (R, 4)).copy()
    v0 = np.broadcast_to(as_float_array(v0, "v0", last=3), (R, 3)).copy()
    p0 = np.broadcast_to(as_float_array(p0, "p0", last=3), (R, 3)).copy()
    kind, h, g = s0.kind, 1.0 / s0.rate, s0.g
    M = len(s0)
    N = M if kind == "increments" else M - 1
    if N < 1:
        raise ImunavError(f"{kind} signals need at least {algo.min_samples} samples")
    t_nodes = s0.state_times()
    div = h if kind == "increments" else 1.0
    gyro_raw = np.stack([s.gyro for s in signals], axis=1) / div          # (M, R, 3)
    accel_raw = np.stack([s.accel for s in signals], axis=1) / div
    imu = imu or ImuModel(name="ideal")
    meas = build_measurements(aiding)
    peaks = (float(np.linalg.norm(gyro_raw, axis=-1).max()),
             float(np.linalg.norm(accel_raw, axis=-1).max()))
    system = AidedSystem(imu, list(meas.values()), h=h, kind=kind,
                         decimate=imu.decimation(s0.rate), peaks=peaks,
                         initial=aiding.initial, model=model)
    n = system.n
    # ---------------------------------------------------------------- the readings
    scheds = [_schedule(s, aiding, d, meas, algo.align) for s, d in zip(signals, data,
                                                                       strict=True)]
    at: dict[int, list] = {}
    for k, rows in scheds[0].at.items():
        others = [sc.at.get(k) for sc in scheds[1:]]
        if any(o is None or [(r[0], r[2], r[3]) for r in o] != [(r[0], r[2], r[3])
                                                                  for r in rows]
               for o in others):
            raise ImunavError("run_filter_batch needs the same reading times in every run",
                              argument="data")
        at[k] = [(name, np.stack([rows[i][1]] + [o[i][1] for o in others]), dt, t)
                 for i, (name, _, dt, t) in enumerate(rows)]
    if any(set(sc.at) != set(at) for sc in scheds[1:]):
        raise ImunavError("run_filter_batch needs the same reading times in every run",
                          argument="data")
    gate = None if gate is None or gate >= 1 else gate
    readings = {name: 0 for name in meas}
    rejected = {name: np.zeros(R, dtype=int) for name in meas}

    # ---------------------------------------------------------------- the loop
    m_cov = max(1, int(round(covariance_step / h)))
    m_cov = max(algo.align, m_cov // algo.align * algo.align)
    updates = sorted(k for k in at if k > 0)
    if not updates or updates[-1] != N:
        updates.append(N)
    before, after = algo.context
    own = 1 if kind == "rates" else 0
    q_nodes = np.empty((N + 1, R, 4))
    v_nodes = np.empty((N + 1, R, 3))
    p_nodes = np.empty((N + 1, R, 3))
    q_nodes[0], v_nodes[0], p_nodes[0] = q0, v0, p0
    s_hat = np.zeros((R, n - NAV))
    P = np.repeat(system.P0[None], R, axis=0)
    ep_idx, ep_P = [0], [P[:, :NAV, :NAV].copy()]

    def readings_at(k, P, s_hat):
        x, P = _updates_batch(at[k], k, q_nodes, v_nodes, p_nodes, gyro_raw, accel_raw, s_hat,
                              system, meas, P, gate, readings, rejected)
        q_nodes[k], v_nodes[k], p_nodes[k] = _inject(q_nodes[k], v_nodes[k], p_nodes[k],
                                                     x[:, :NAV])
        return P, s_hat + x[:, NAV:]

    if 0 in at:
        P, s_hat = readings_at(0, P, s_hat)
        ep_P[0] = P[:, :NAV, :NAV].copy()
    a = 0
    comp_sl = [(system.layout[s.name], s.states) for s in system.sources]
    for b in updates:
        w0, w1 = max(0, a - before), min(M, b + own + after)
        W = w1 - w0
        tw = t_nodes[w0:w1] + (h / 2 if kind == "increments" else 0.0)
        decay = system.decay(tw - t_nodes[a])                      # (W, n − 9)
        gw, aw = gyro_raw[w0:w1].copy(), accel_raw[w0:w1].copy()
        for sl, st in comp_sl:
            cols = slice(sl.start - NAV, sl.stop - NAV)
            s_loc = decay[:, None, cols] * s_hat[None, :, cols]      # (W, R, k)
            u = gyro_raw[w0:w1] if st.triad == "gyro" else accel_raw[w0:w1]
            Mx = st.input_matrix(u.reshape(-1, 3), accel_raw[w0:w1].reshape(-1, 3))
            corr = np.einsum("nik,nk->ni", Mx, s_loc.reshape(W * R, -1)).reshape(W, R, 3)
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
        bounds = list(range(a, b, m_cov)) + [b]
        traj, lens = _linearisation_batch(bounds, q_nodes, v_nodes, gw, aw, a - w0, kind, h, g)
        for lo, hi, L in _groups(lens):
            st = system.steps(traj.piece(lo * R, hi * R), L * h)
            for i in range(hi - lo):
                P = _predict_batch_step(P, st, slice(i * R, (i + 1) * R))
                ep_idx.append(bounds[lo + i + 1])
                ep_P.append(P[:, :NAV, :NAV].copy())
        s_hat = s_hat * system.decay(np.array([t_nodes[b] - t_nodes[a]]))
        if b in at:
            P, s_hat = readings_at(b, P, s_hat)
            ep_P[-1] = P[:, :NAV, :NAV].copy()
        a = b
    return BatchResult(t_nodes, q_nodes, v_nodes, p_nodes, np.asarray(ep_idx),
                       np.asarray(ep_P), readings, rejected, algo.name, list(system.warnings))


@lru_cache(maxsize=64)
def _chi2_quantile(p: float, dof: int) -> float:
    """The gate's χ² quantile (the same as :func:`~imunav.estimation.kalman.update` uses)."""
    return float(chi2.ppf(p, dof))


def _linearisation_batch(bounds, q_nodes, v_nodes, gw, aw, off, kind, h, g
                         ) -> tuple[Trajectory, list[int]]:
    """:func:`_linearisation` of R runs (nodes (N + 1, R, ·), samples (W, R, 3)): the steps of
    every run side by side, step-major (step i of run r at ``i·R + r``)."""
    lo = np.asarray(bounds[:-1])
    hi = np.asarray(bounds[1:])
    L = hi - lo
    mid = lo + L // 2
    qa = q_nodes[mid]                                          # (K, R, 4)
    odd = L % 2 == 1
    if odd.any():
        qb = q_nodes[np.minimum(mid + 1, q_nodes.shape[0] - 1)]
        sgn = np.sign(np.einsum("krj,krj->kr", qa, qb))[..., None]
        qm = qa + sgn * qb
        qa = np.where(odd[:, None, None], qm / np.linalg.norm(qm, axis=-1, keepdims=True), qa)
    H = (L * h)[:, None, None]
    f_n = (v_nodes[hi] - v_nodes[lo]) / H - np.array([0.0, 0.0, g])
    a0 = bounds[0]
    Lr = L[:, None, None]
    if kind == "increments":
        cg = np.concatenate([np.zeros((1,) + gw.shape[1:]), np.cumsum(gw[off:], axis=0)])
        ca = np.concatenate([np.zeros((1,) + aw.shape[1:]), np.cumsum(aw[off:], axis=0)])
    else:
        cg = np.concatenate([np.zeros((1,) + gw.shape[1:]),
                             np.cumsum((gw[off:-1] + gw[off + 1:]) / 2, axis=0)])
        ca = np.concatenate([np.zeros((1,) + aw.shape[1:]),
                             np.cumsum((aw[off:-1] + aw[off + 1:]) / 2, axis=0)])
    om = (cg[hi - a0] - cg[lo - a0]) / Lr
    fb = (ca[hi - a0] - ca[lo - a0]) / Lr
    K, R = qa.shape[:2]
    traj = Trajectory(h, np.zeros(K * R + 1), quat_to_dcm(qa.reshape(K * R, 4)),
                      f_n.reshape(K * R, 3), om.reshape(K * R, 3), fb.reshape(K * R, 3))
    return traj, L.tolist()


def _predict_batch_step(P: FloatArray, st: StepBlocks, rows: slice) -> FloatArray:
    """:meth:`AidedSystem.predict_step` of R runs at once: P (R, n, n), the blocks of steps
    ``rows`` of :meth:`AidedSystem.steps` (one step per run)."""
    k = NAV
    F = st.F[rows]
    if P.shape[-1] == k:
        out = F @ P @ np.swapaxes(F, 1, 2) + st.Qnn[rows]
        return 0.5 * (out + np.swapaxes(out, 1, 2))
    G, E = st.G[rows], st.E[rows]
    Pnn, Pns, Pss = P[:, :k, :k], P[:, :k, k:], P[:, k:, k:]
    X = F @ Pns + G @ Pss
    Y = F @ Pnn + G @ np.swapaxes(Pns, 1, 2)
    out = np.empty_like(P)
    nn = Y @ np.swapaxes(F, 1, 2) + X @ np.swapaxes(G, 1, 2)
    out[:, :k, :k] = 0.5 * (nn + np.swapaxes(nn, 1, 2)) + st.Qnn[rows]
    out[:, :k, k:] = X * E[:, None, :] + st.Qns[rows]
    out[:, k:, :k] = np.swapaxes(out[:, :k, k:], 1, 2)
    ss = Pss * (E[:, :, None] * E[:, None, :])
    m = ss.shape[-1]
    ss[:, range(m), range(m)] += st.qss
    out[:, k:, k:] = ss
    return out


def _updates_batch(readings, k, q_nodes, v_nodes, p_nodes, gyro_raw, accel_raw, s_hat, system,
                   meas, P, gate, counts, rejected):
    """:func:`_updates` of R runs: each reading of node ``k`` in turn, every run's own gate."""
    n = system.n
    R = P.shape[0]
    est = np.concatenate([np.zeros((R, NAV)), s_hat], axis=1)
    i = min(k, gyro_raw.shape[0] - 1)
    u, f = gyro_raw[i], accel_raw[i]                                 # (R, 3)
    Mg = system.triad_input("gyro", u, f)                            # (R, 3, n)
    omega = u - np.einsum("rik,rk->ri", Mg[:, :, NAV:], s_hat)
    x = np.zeros((R, n))
    eye = np.eye(n)
    for name, values, dt, _t in readings:
        m = meas[name]
        qk, vk, pk = _inject(q_nodes[k], v_nodes[k], p_nodes[k], x[:, :NAV])
        z = np.empty((R, m.size))
        H = np.empty((R, m.size, n))
        for r in range(R):
            nav = NavPoint(qk[r], vk[r], pk[r], omega[r], dt,
                           est[r] + np.concatenate([np.zeros(NAV), x[r, NAV:]]), Mg[r])
            z[r] = m.residual(m.predict(nav), values[r])
            H[r] = m.jacobian(nav)
        Rn = m.noise()
        Hx = np.einsum("rmn,rn->rm", H, x)
        nu = (z + Hx) - Hx                     # about the corrected state, as update() does
        PHt = P @ np.swapaxes(H, 1, 2)                              # (R, n, m)
        S = H @ PHt + Rn
        S = 0.5 * (S + np.swapaxes(S, 1, 2))
        try:
            np.linalg.cholesky(S)
        except np.linalg.LinAlgError:
            raise ImunavError("the innovation covariance H P Hᵀ + R is not positive definite "
                              "(check R)") from None
        Sinv_nu = np.linalg.solve(S, nu[..., None])[..., 0]
        nis = np.einsum("rm,rm->r", nu, Sinv_nu)
        ok = np.ones(R, dtype=bool) if gate is None else nis <= _chi2_quantile(gate, m.size)
        K = np.swapaxes(np.linalg.solve(S, np.swapaxes(PHt, 1, 2)), 1, 2)   # P Hᵀ S⁻¹
        A = eye - K @ H
        Pn = A @ P @ np.swapaxes(A, 1, 2) + K @ Rn @ np.swapaxes(K, 1, 2)
        Pn = 0.5 * (Pn + np.swapaxes(Pn, 1, 2))
        x = np.where(ok[:, None], x + np.einsum("rnm,rm->rn", K, nu), x)
        P = np.where(ok[:, None, None], Pn, P)
        counts[name] += 1
        rejected[name] += ~ok
    return x, P
