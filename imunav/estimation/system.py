"""The aided filter's error state and its exact discrete dynamics: :class:`AidedSystem`.

The error state is the navigation error of :mod:`~imunav.estimation.error_model` (``φ``,
``δv``, ``δp``), then every sensor-error state the IMU model has — each term's own
linearisation (:meth:`imunav.sensors.terms.Term.linearise`: biases, Gauss–Markov banks, random
walks, scale factors, misalignments, g-sensitivity) — then the aids' own states (a Gauss–Markov
GNSS position error, the barometer's bias, an odometer's scale factor; each
:class:`~imunav.sensors.aids.Measurement`'s ``states``). Its continuous dynamics along a
trajectory are the error model's ``[[A, B], [0, diag(D)]]`` with every source's ``B`` side by
side, and a step is discretised exactly: ``Φ`` in closed form
(:meth:`~imunav.estimation.error_model.FlatErrorModel.transition`), ``Q_d`` by 6-node
Gauss–Legendre on that exact transition (only the columns with white inputs), in the blocks of
:class:`~imunav.estimation.kalman.StepBlocks`. The filter (linearised along its estimate) and
the covariance analysis (along the truth) use the same system.

May import: ``imunav.core``, ``imunav.sensors``, ``imunav.estimation``.
"""

from __future__ import annotations

import math

import numpy as np

from imunav.core.kernels import FloatArray, skew
from imunav.core.layout import DP, DV, NAV, PHI
from imunav.estimation.discretisation import GAUSS_LEGENDRE, phi_functions
from imunav.estimation.error_model import (
    EARTH,
    EARTH_HOLD,
    FLAT,
    TRIAD_ROWS,
    ErrorSource,
    FlatErrorModel,
    Trajectory,
    linearise,
)
from imunav.estimation.kalman import StepBlocks
from imunav.sensors.aids import InitialConfig, Measurement
from imunav.sensors.models import ImuModel

__all__ = ["AidedSystem"]

#: Above this many bytes the Gauss–Legendre nodes' rows of a batch are formed one node at a time
#: (the same numbers: a cache-sized working set instead of one array of every node).
NODE_BYTES = 1 << 21


def _phi_234(d: FloatArray, h: float) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``φ_i(d) = ∫₀ʰ (h−s)^i/i! e^{d s} ds`` for i = 2, 3, 4: the same arithmetic as the
    Earth model's own (the series below |d h| = 0.5), for the rows of :meth:`AidedSystem.steps`
    (``tests/estimation/test_filters_earth.py`` compares the two)."""
    x = d * h
    small = np.abs(x) < 0.5
    xs = np.where(small, 1.0, x)
    out = []
    for i in (2, 3, 4):
        ser = sum(x**k / math.factorial(k + i + 1) for k in range(18))
        tail = np.expm1(xs) - sum(xs**k / math.factorial(k) for k in range(1, i + 1))
        out.append(np.where(small, h ** (i + 1) * ser, h ** (i + 1) * tail / xs ** (i + 1)))
    return out[0], out[1], out[2]


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
        self._stacked: dict[bytes, list] = {}

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
        return self.steps(traj, h, Qc).full()

    def steps(self, traj: Trajectory, h: float | None = None, Qc: FloatArray | None = None
              ) -> StepBlocks:
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

        Returns
        -------
        StepBlocks
            ``decay`` (n − 9,) and ``Qxx`` (n − 9, n − 9), the same for every step.
        """
        h = traj.h if h is None else float(h)
        B = self.sensor_input(traj)
        n, N, m = self.n, traj.steps, self.n - NAV
        rows_at = (self._flat_rows(traj, B) if self.model is FLAT or
                   (self.model in (EARTH, EARTH_HOLD) and traj.gradient is not None) else None)
        x, w = GAUSS_LEGENDRE
        xs, ws = (x + 1) / 2 * h, w / 2 * h
        # every node's rows at once, and those at s = h: the rows of Φ (the same operations);
        # node by node when they would not fit in a cache (a batch of many runs)
        by_node = rows_at is not None and 7 * N * NAV * n * 8 > NODE_BYTES
        if rows_at is not None:
            at = rows_at(np.append(xs, h)) if not by_node else None
            r = at[-1] if not by_node else rows_at(h)
            F, G = r[:, :, :NAV], r[:, :, NAV:]
            E = np.exp(self.D * h)
        else:
            Phi = self.model.transition(traj, B, self.D, h)
            F, G = Phi[:, :NAV, :NAV], Phi[:, :NAV, NAV:]
            E = np.diagonal(Phi[0])[NAV:].copy() if N else np.exp(self.D * h)
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
            if by_node:                                         # the same sums, node by node
                for i, wi in enumerate(ws):
                    a = rows_at(xs[i])
                    Pn = a[:, :, nz]
                    Qnn += (wi * (Pn * q)) @ np.swapaxes(Pn, -1, -2)
                    if n > NAV:
                        e = np.exp(xs[i] * self.D)
                        Qns += (wi * a[:, :, NAV:]) * (qs * e)
                        qss += wi * qs * e * e
            elif rows_at is not None:                           # every node at once
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
        return StepBlocks(F, G, E, 0.5 * (Qnn + np.swapaxes(Qnn, 1, 2)), Qns, np.diag(qss))

    def _flat_rows(self, traj: Trajectory, B: FloatArray):
        """``s → Φ(s)[:9]`` of the flat model, its products with ``B`` formed once: the rows of
        :func:`~imunav.estimation.discretisation.flat_transition` (``[I, 0, 0; F s, I, 0;
        F s²/2, I s, I]`` and ``Γ = B φ0 + A B φ1 + A² B φ2``), the φ-functions of each ``s``
        remembered (``tests/estimation/test_filters.py`` checks it against the model's own). On
        the Earth (``traj.gradient`` set) plus the first-order terms in the gravity gradient
        ``Γ_g`` of :meth:`EarthErrorModel.transition
        <imunav.estimation.error_model.EarthErrorModel.transition>` — its φ₂…φ₄ of each ``s``
        remembered too — so that every Gauss–Legendre node is one array operation, not a
        transition of its own."""
        F = skew(traj.f_n)
        N = F.shape[0]
        FB = F @ B[:, 0:3]                                      # A B rows δv, A² B rows δp
        Bv = B[:, 3:6]
        I3 = np.eye(3)
        Gm = traj.gradient if self.model is not FLAT else None
        if Gm is not None:
            GF = Gm @ F
            GBv, GFB = Gm @ Bv, Gm @ FB

        def phis(s):
            key = float(s)
            phi = self._phi.get(key)
            if phi is None:
                if len(self._phi) > 256:
                    self._phi.clear()
                phi = phi_functions(self.D, key)
                if Gm is not None:
                    phi = phi + _phi_234(self.D, key)
                phi = self._phi[key] = phi
            return phi

        def rows(s):
            """At one ``s`` (N, 9, n); at an array of them (S, N, 9, n): the same numbers."""
            one = np.ndim(s) == 0
            sv = np.atleast_1d(np.asarray(s, dtype=float))
            key = sv.tobytes()
            ps = self._stacked.get(key)
            if ps is None:                              # the same nodes every step of a length
                if len(self._stacked) > 64:
                    self._stacked.clear()
                ps = self._stacked[key] = [np.stack(p)[:, None, None, :]
                                           for p in zip(*map(phis, sv), strict=True)]
            p0, p1, p2 = ps[:3]
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
            if Gm is not None:                          # the terms in Γ_g (eq. of _with_gravity)
                out[:, :, DV, PHI] += GF * (sv**3 / 6)
                out[:, :, DV, DV] += Gm * (sv * sv / 2)
                out[:, :, DV, DP] += Gm * sv
                out[:, :, DP, PHI] += GF * (sv**4 / 24)
                out[:, :, DP, DV] += Gm * (sv**3 / 6)
                out[:, :, DP, DP] += Gm * (sv * sv / 2)
                if self.D.size:
                    q2, q3, q4 = ps[3:]
                    G[:, :, DV] += GBv * q2 + GFB * q3
                    G[:, :, DP] += GBv * q3 + GFB * q4
            return out[0] if one else out

        return rows

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

    @staticmethod
    def reset_jacobian(x: FloatArray) -> FloatArray:
        """``G``: how the error left after a feedback depends on the error before it.

        The filter corrects its attitude by the estimated error, ``q ← exp(φ̂) ⊗ q``, and
        restarts the error state at zero. With the attitude error defined by
        ``C_est = (I − [φ×]) C`` (``q_est = exp(−φ) ⊗ q``), the error after the correction is
        ``φ⁺`` with ``exp(−φ⁺) = exp(φ̂) exp(−φ)``; to first order in the estimation error
        ``δ = φ − φ̂`` (Baker–Campbell–Hausdorff) ``φ⁺ = δ + ½ φ̂ × δ``. So the covariance the
        filter carries on is ``G P Gᵀ`` with ``G = I`` but for ``G_φφ = I + ½ [φ̂×]``: the
        velocity, position and sensor errors are corrected additively (their block is the
        identity). Leaving ``G`` out is right to first order in ``φ̂`` only; a correction of
        several degrees (a heading learnt once a car drives off) then leaves the attitude
        covariance too small (issue 38; ``benchmarks/aided_consistency.py --causes``).

        Parameters
        ----------
        x : ndarray, shape (..., n)
            The corrections fed back (``φ̂`` first).

        Returns
        -------
        ndarray, shape (..., n, n)
        """
        x = np.asarray(x, dtype=float)
        G = np.broadcast_to(np.eye(x.shape[-1]), x.shape[:-1] + (x.shape[-1],) * 2).copy()
        G[..., PHI, PHI] += 0.5 * skew(x[..., PHI])
        return G

    def reset(self, P: FloatArray, x: FloatArray) -> FloatArray:
        """The covariance after feeding back ``x``: ``G P Gᵀ`` (:meth:`reset_jacobian`),
        computed on the rows and columns of the attitude error only.

        Parameters
        ----------
        P : ndarray, shape (..., n, n)
            The covariance after the update.
        x : ndarray, shape (..., n)
            The corrections fed back.

        Returns
        -------
        ndarray, shape (..., n, n)
            Symmetric.
        """
        P = np.array(P, dtype=float)
        A = np.eye(3) + 0.5 * skew(np.asarray(x, dtype=float)[..., PHI])      # (..., 3, 3)
        P[..., PHI, :] = A @ P[..., PHI, :]
        P[..., :, PHI] = P[..., :, PHI] @ np.swapaxes(A, -1, -2)
        return 0.5 * (P + np.swapaxes(P, -1, -2))
