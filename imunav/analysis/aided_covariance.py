"""Covariance analysis of the aided filter along the true motion: what the filter believes and
what its errors really are.

The error-state filter of :mod:`~imunav.estimation.filters`, linearised along the exact motion
instead of its own estimate, is a linear time-varying system whose covariance and gains are
deterministic: one pass gives them, without simulating anything. Its **true** error covariance
follows from the same gains applied to the *truth model* — the filter's own states plus the
states of every error the simulation has and the filter does not carry (a Gauss–Markov GNSS
error that the filter treats as white, ``[gnss] correlated_model = "white"``) — the standard
"true versus filter covariance" performance analysis of a suboptimal filter (Gelb 1974, §7.2;
Maybeck 1979, ch. 6). For a feedback filter, whose estimate is fed back and reset to zero at
every epoch, the true error ``z`` of the corrected state is the whole augmented state: the
filter's own estimate is zero between epochs, its knowledge lives in its (deterministic)
covariance. Hence

    between epochs     z ← Φ_t z + w_t                      (the truth model's dynamics)
    at a reading       z ← (I − K H_t) z − K v,  v ~ R_t    (the filter's gain K)

so ``P_t ← (I − K H_t) P_t (I − K H_t)ᵀ + K R_t Kᵀ`` — Joseph's form, exact for any gain —
while the filter's own ``P_f`` follows with its ``H_f`` and ``R_f`` and gives
``K = P_f H_fᵀ (H_f P_f H_fᵀ + R_f)⁻¹``. Where the two models agree, ``P_t = P_f`` (the
filter is consistent; ``tests/analysis/test_aided_assessment.py``). Readings at one epoch are used one
after another, as the filter does (its innovation of the next reading is taken about the
state the previous one corrected, which is this recursion).

For fixed gains everything is linear in the noise sources, so the true covariance is exactly
the sum of the contributions of each source — an IMU error term, an aid's white noise or its
own states, the initial uncertainty — propagated side by side (:meth:`AlongTruth.propagate`
with one row of weights per contribution): the aided error budget. Scaling every IMU term by
``k`` scales its part of ``Q_d`` and ``P₀`` by ``k²`` while the transitions stay the same (a
term's input matrix does not depend on its size), so an IMU ``k`` times better or worse is
one more pass, not a new discretisation.

What it shares with the filter, exactly: the error state and its blocks
(:class:`~imunav.estimation.filters.AidedSystem`: the same layout, ``Φ`` in closed form and
``Q_d`` by Gauss–Legendre, the same white treatment of quantisation), each aid's Jacobian and
noise (the measurement classes of :mod:`~imunav.estimation.measurements`, evaluated at the
truth), the epochs (every reading's IMU node, covariance steps of at most
``covariance_step`` between them, as :func:`~imunav.estimation.filters.run_filter` cuts
them), the sequential Joseph updates. What it does not model: the χ² gate (a consistent
filter rejects one reading in ``1/(1 − gate)``), the linearisation along the estimate instead
of the truth (second order in the errors), a SHOE detector's misses (the true stance is used,
with a warning), and — as the filter — the anti-alias filter and the range. The transition of
a step is linearised at its midpoint: ``C_nb`` and ``ω_b``, ``f_b`` there, the mean ``f_n``
from the velocity change (the filter: the same from its estimate).

Both covariances are kept in the truth model's coordinates (the filter's states are a subset
of them; :class:`AlongTruth` checks it): the filter's own is zero on the states it does not
carry.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.strapdown``,
``imunav.estimation``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from imunav.core.constants import G0
from imunav.core.kernels import FloatArray, quat_conj, quat_rotate, quat_to_dcm
from imunav.core.resources import check_memory
from imunav.core.validation import ImunavError, check_positive
from imunav.earth import dcm_ecef_to_inertial, earth_rate_ned, gravitation_gradient
from imunav.estimation.error_model import EARTH, FLAT, NAV, TRIAD_ROWS, Trajectory, linearise, local_error_map
from imunav.estimation.kalman import gain, joseph, predict_blocks
from imunav.estimation.schedule import Schedule, step_length
from imunav.estimation.system import AidedSystem
from imunav.motion.base import BaseMotion
from imunav.sensors.aids import AIDS, AidingConfig, Measurement, NavPoint, build_measurements
from imunav.sensors.models import ImuModel
from imunav.sensors.simulate import interval_count
from imunav.strapdown.registry import resolve

__all__ = ["AlongTruth", "Ingredient", "PassResult", "Reading", "reading_times",
           "truth_measurements"]

#: Steps discretised at once (memory of a piece: a few arrays of ``CHUNK × n²``).
CHUNK = 256


def truth_measurements(aiding: AidingConfig) -> dict[str, Measurement]:
    """The aids as the simulation makes them (a correlated GNSS error always carried as states,
    whatever the filter assumes).

    Parameters
    ----------
    aiding : AidingConfig

    Returns
    -------
    dict
        ``{aid: Measurement}``.
    """
    return build_measurements(aiding, truth=True)


def reading_times(aiding: AidingConfig, motion: BaseMotion, rate: float, duration: float
                  ) -> tuple[dict[str, FloatArray], np.ndarray, list[str]]:
    """When each aid reads along ``motion`` (each aid's ``times``, as the simulation and the
    filter schedule it) — every GNSS fix, the outages included (they are told apart by the
    mask).

    Parameters
    ----------
    aiding : AidingConfig
    motion : BaseMotion
        For the stance intervals of ZUPT.
    rate : float
        IMU rate (Hz).
    duration : float
        Seconds.

    Returns
    -------
    times : dict
        ``{aid: (k,) times}``, in the registry's order.
    outage : ndarray of bool
        Per GNSS fix: inside the file's ``outages``.
    warnings : list of str
    """
    out: dict[str, FloatArray] = {}
    warnings: list[str] = []
    outage = np.zeros(0, dtype=bool)
    for name in aiding.sensors:
        spec, cfg = AIDS[name], aiding.get(name)
        out[name] = spec.times(cfg, motion, rate, duration)
        warnings += spec.analysis_warnings(cfg)
    if aiding.gnss is not None:
        outage = aiding.gnss.in_outage(out["gnss"])
    return out, outage, warnings


@dataclass
class Reading:
    """One reading of the schedule, linearised at the truth.

    Attributes
    ----------
    sensor : str
    t : float
        Its time (s).
    index : int
        Its index among the sensor's readings.
    Hf, Rf : ndarray
        The filter's Jacobian (in the truth model's coordinates) and noise.
    Ht, Rt : ndarray
        The truth model's.
    outage : bool
        A GNSS fix inside the file's outages.
    """

    sensor: str
    t: float
    index: int
    Hf: FloatArray
    Rf: FloatArray
    Ht: FloatArray
    Rt: FloatArray
    outage: bool = False


@dataclass
class Ingredient:
    """One independent source of the true error: its initial covariance, its process noise
    (an index into :attr:`AlongTruth.Q`, or None) and the aid whose white noise it is.

    Attributes
    ----------
    name : str
        An IMU term (``"gyro.noise_density"``), ``"imu"`` (all of them), an aid's own states
        (``"gnss.correlated"``, ``"baro.bias"``), an aid's white noise (``"nhc.white"``), or
        ``"initial"``.
    kind : {"imu", "aid", "white", "initial"}
    P0 : ndarray, shape (n, n)
    q : int or None
    sensor : str or None
    """

    name: str
    kind: str
    P0: FloatArray
    q: int | None = None
    sensor: str | None = None


@dataclass
class PassResult:
    """Navigation-error covariances of one pass at every epoch, before (``prior``) and after
    (``post``) the readings of the epoch.

    Attributes
    ----------
    t : ndarray, shape (E + 1,)
        Epoch times (s); the first is the start.
    filter_prior, filter_post : ndarray, shape (B, E + 1, 9, 9)
        The filter's own covariance, per scenario.
    truth_prior, truth_post : ndarray, shape (B, M, E + 1, 9, 9)
        The true error covariance, per scenario and contribution (rows of the weights).
    final : ndarray, shape (B, 1 + M, n, n)
        The full covariances at the last epoch propagated (filter first).
    """

    t: FloatArray
    filter_prior: FloatArray
    filter_post: FloatArray
    truth_prior: FloatArray
    truth_post: FloatArray
    final: FloatArray | None = None


class AlongTruth:
    """The aided filter linearised along the true motion: every step's discrete system, every
    reading's Jacobians, and the sources of the true error — built once, propagated by
    :meth:`propagate` for any weights of the sources (an IMU scaled, one source alone) and any
    GNSS schedule (outages).

    Parameters
    ----------
    motion : BaseMotion
        The truth (flat frame).
    imu : ImuModel
        The IMU simulated and assumed by the filter.
    aiding : AidingConfig
        The aids: simulated as :func:`truth_measurements`, assumed as
        :func:`~imunav.estimation.filters.build_measurements`.
    rate : float
        IMU rate (Hz).
    duration : float
        Seconds.
    kind : {"increments", "rates"}
        The signal kind (quantisation).
    covariance_step : float
        The filter's longest covariance step (s).
    algorithm : str, optional
        The filter's strapdown algorithm (its sample alignment sets the epochs).
    g : float
        Gravity (m/s²).
    terms : bool
        Split the IMU into its error terms (one ingredient each, one more discretisation per
        term with white inputs): what the error budget needs. Default: one ingredient ``"imu"``.

    Attributes
    ----------
    truth : AidedSystem
        The truth model (its layout is the coordinates of every covariance here).
    filter_states : ndarray of bool, shape (n,)
        The states the filter carries.
    t : ndarray, shape (E + 1,)
        Epoch times (s).
    nodes : ndarray of int, shape (E + 1,)
        Their IMU nodes.
    readings : list of list of Reading
        Per epoch, its readings in the filter's order.
    ingredients : list of Ingredient
    warnings : list of str

    Raises
    ------
    ImunavError
        For a non-positive rate or covariance step, no aid at all, or an aid that reads faster
        than the IMU.
    """

    def __init__(self, motion: BaseMotion, imu: ImuModel, aiding: AidingConfig | None,
                 rate: float, duration: float, *, kind: str = "increments",
                 covariance_step: float = 0.1, algorithm: str | None = None, g: float = G0,
                 terms: bool = False, measurements: list | None = None):
        rate = check_positive(rate, "rate")
        if not 0 < check_positive(covariance_step, "covariance_step") <= 10.0:
            raise ImunavError(f"covariance_step must be in (0, 10] s (the motion is held over a "
                              f"step), got {covariance_step:g}", argument="covariance_step")
        aiding = aiding if aiding is not None else AidingConfig()
        extra = list(measurements or [])
        if not aiding.sensors and not extra:
            raise ImunavError("aiding has no aiding sensor ("
                              + ", ".join(f"[{n}]" for n in AIDS) + ")", argument="aiding")
        self.motion, self.imu, self.aiding, self.rate, self.g = motion, imu, aiding, rate, g
        self.frame = motion.frame
        earth = self.frame == "wgs84"
        h = self.h = 1.0 / rate
        N = self.N = interval_count(rate, duration)
        self.duration = N * h
        algo = resolve(kind, algorithm)
        for name in aiding.sensors:              # readings faster than the IMU's samples
            r_aid = AIDS[name].rate(aiding.get(name))
            if r_aid is not None and r_aid > rate * (1 + 1e-12):
                raise ImunavError(f"[{name}] rate = {r_aid:g} Hz is above the IMU rate of "
                                  f"{rate:g} Hz: expected at most {rate:g} Hz (the filter "
                                  "updates at IMU samples)", argument="aiding")
        times, gnss_outage, self.warnings = reading_times(aiding, motion, rate, N * h)
        t_meas = list(truth_measurements(aiding).values()) + [a.measurement for a in extra]
        f_meas = list(build_measurements(aiding).values()) + [a.measurement for a in extra]
        names = list(times) + [a.name for a in extra]
        all_times = list(times.values()) + [a.t for a in extra]
        # ---------------------------------------------------------------- epochs
        sched = Schedule(0.0, h, N, algo.align)
        for i, t in enumerate(all_times):
            sched.add(i, t, names[i])
        nodes = self.nodes = np.asarray(sched.bounds(step_length(covariance_step, h,
                                                                  algo.align)))
        self.t = nodes * h
        E = nodes.size - 1
        lo, hi = nodes[:-1], nodes[1:]
        L = hi - lo
        tm = (lo + hi) * (h / 2)
        if earth:
            traj = _earth_trajectory(motion, h, self.t, tm)
            self.output = local_error_map(self.t, *_local_states(motion, self.t))
        else:
            v = motion.velocity(self.t)
            C = motion.dcm(tm)
            f_n = (v[1:] - v[:-1]) / (L * h)[:, None] - np.array([0.0, 0.0, g])
            omega = motion.angular_rate(tm)
            f_b = motion.specific_force(tm, g)
            traj = Trajectory(h, self.t, C, f_n, omega, f_b,
                              float(np.linalg.norm(omega, axis=1).max()),
                              float(np.linalg.norm(f_b, axis=1).max()))
            self.output = None
        peaks = (traj.max_rate, traj.max_force)
        # ---------------------------------------------------------------- the two models
        decimate = imu.decimation(rate)
        model = EARTH if earth else FLAT
        truth = self.truth = AidedSystem(imu, t_meas, h=h, kind=kind, decimate=decimate,
                                         peaks=peaks, initial=aiding.initial, model=model)
        filt = AidedSystem(imu, f_meas, h=h, kind=kind, decimate=decimate, peaks=peaks,
                           initial=aiding.initial, model=model)
        self.warnings += list(truth.warnings)
        n = self.n = truth.n
        emb = np.zeros(n, dtype=bool)
        for name, sl in filt.layout.items():
            tsl = truth.layout.get(name)
            if tsl is None or tsl.stop - tsl.start != sl.stop - sl.start:
                raise ImunavError(f"the filter's state {name!r} is not in the truth model")
            emb[tsl] = True
        self.filter_states = emb
        for m in f_meas:                           # the filter's aids in the truth's coordinates
            m.bind(truth.layout)
        self.layout = truth.layout
        # ---------------------------------------------------------------- the ingredients
        aid_states = np.zeros(n, dtype=bool)
        for m in t_meas:
            for s in m.states:
                aid_states[truth.layout[s.name]] = True
        Qc_imu = np.where(aid_states, 0.0, truth.Qc)
        qcs: list[FloatArray] = []
        ingredients: list[Ingredient] = []

        def block(P, sl):
            out = np.zeros((n, n))
            out[sl, sl] = P[sl, sl]
            return out

        if terms:
            sources, _ = linearise(imu, Trajectory(h, np.zeros(1), np.zeros((0, 3, 3)),
                                                   np.zeros((0, 3)), np.zeros((0, 3)),
                                                   np.zeros((0, 3)), *peaks), kind, decimate)
            per: dict[str, tuple[FloatArray, FloatArray]] = {}
            for s in sources:
                qc, P0 = per.setdefault(s.name, (np.zeros(n), np.zeros((n, n))))
                if s.differenced:
                    qc[TRIAD_ROWS[s.states.triad]] += s.states.differenced_white / h
                    continue
                qc[:NAV] += s.noise_psd()[:NAV]
                if s.size:
                    sl = truth.layout[s.name]
                    qc[sl] = s.states.Qs
                    P0[sl, sl] = s.states.P0
            total_qc = sum((q for q, _ in per.values()), np.zeros(n))
            if not np.allclose(total_qc, Qc_imu, rtol=1e-12, atol=0):
                raise AssertionError("the IMU terms' white inputs do not add up to the model's")
            for name, (qc, P0) in per.items():
                j = None
                if np.any(qc):
                    qcs.append(qc)
                    j = len(qcs) - 1
                ingredients.append(Ingredient(name, "imu", P0, j))
        else:
            sl = slice(NAV, truth.sensor_end)
            qcs.append(Qc_imu)
            ingredients.append(Ingredient("imu", "imu", block(truth.P0, sl), 0))
        # the aids' own states (Q only on their own diagonal: they do not drive the navigation)
        aid_q: list[tuple[int, slice]] = []
        for m in t_meas:
            for s in m.states:
                sl = truth.layout[s.name]
                aid_q.append((len(ingredients), sl))
                ingredients.append(Ingredient(s.name, "aid", block(truth.P0, sl), None))
            ingredients.append(Ingredient(f"{m.name}.white", "white", np.zeros((n, n)),
                                          None, m.name))
        P_init = np.zeros((n, n))
        P_init[:NAV, :NAV] = truth.P0[:NAV, :NAV]
        ingredients.append(Ingredient("initial", "initial", P_init))
        self.ingredients = ingredients
        self._aid_q = aid_q
        # ---------------------------------------------------------------- the steps
        m_s = n - NAV
        J = len(qcs)
        need = 8.0 * E * (NAV * NAV + NAV * m_s + m_s) * (1 + J) + 8.0 * E * m_s * len(aid_q)
        check_memory(need + 8.0 * CHUNK * n * n * 4,
                     f"the aided covariance analysis of {E:,} epochs ({n} states)",
                     "a shorter duration or a longer covariance step")
        self.F = np.empty((E, NAV, NAV))
        self.G = np.empty((E, NAV, m_s))
        self.D = np.empty((E, m_s))
        self.Q = [(np.empty((E, NAV, NAV)), np.empty((E, NAV, m_s)), np.empty((E, m_s)))
                  for _ in range(J)]
        self.Qaid = np.zeros((E, m_s))
        aid_cols = np.nonzero(aid_states[NAV:])[0]
        i = 0
        while i < E:
            j = i + 1
            while j < E and j - i < CHUNK and L[j] == L[i]:
                j += 1
            piece = traj.piece(i, j)
            Phi, Qd = truth.discretise(piece, float(L[i] * h))
            if aid_cols.size and np.any(Phi[:, :NAV, NAV + aid_cols]):
                raise AssertionError("an aid's own state drives the navigation errors")
            self.F[i:j] = Phi[:, :NAV, :NAV]
            self.G[i:j] = Phi[:, :NAV, NAV:]
            self.D[i:j] = np.diagonal(Phi, axis1=1, axis2=2)[:, NAV:]
            dq = np.diagonal(Qd, axis1=1, axis2=2)[:, NAV:]
            self.Qaid[i:j, aid_cols] = dq[:, aid_cols]
            for q, (Qnn, Qns, Qss) in zip(qcs, self.Q, strict=True):
                if q is Qc_imu:                   # Q_d less the aids' own diagonal
                    Qs = Qd
                else:
                    _, Qs = truth.discretise(piece, float(L[i] * h), Qc=q)
                Qnn[i:j] = Qs[:, :NAV, :NAV]
                Qns[i:j] = Qs[:, :NAV, NAV:]
                Qss[i:j] = np.diagonal(Qs, axis1=1, axis2=2)[:, NAV:]
                if q is Qc_imu:
                    Qns[i:j][:, :, aid_cols] = 0.0
                    Qss[i:j][:, aid_cols] = 0.0
            i = j
        # ---------------------------------------------------------------- the readings
        epoch_of = {int(k): e for e, k in enumerate(nodes)}
        self.readings: list[list[Reading]] = [[] for _ in range(E + 1)]
        rk = sorted(sched.at)
        tr = np.array([k * h for k in rk])
        zeros = np.zeros(n)
        if earth:
            q_n, v_n, lla = _local_states(motion, tr, attitude=True)
            p_n = np.zeros(lla.shape)
            p_n[:, 2] = -lla[:, 2]
            w_n = motion.angular_rate(tr)
            w_n = w_n - quat_rotate(quat_conj(q_n), earth_rate_ned(lla[:, 0]))
            f_bn = motion.specific_force(tr)
            M_r = local_error_map(tr, lla, v_n)
        else:
            q_n, v_n, p_n = motion.attitude(tr), motion.velocity(tr), motion.position(tr)
            w_n, f_bn = motion.angular_rate(tr), motion.specific_force(tr, g)
        Mg = truth.triad_input("gyro", motion.angular_rate(tr), f_bn)
        for i, k in enumerate(rk):
            for ai, j, dt, t in sched.at[k]:
                nav = NavPoint(q_n[i], v_n[i], p_n[i], w_n[i], dt, zeros, Mg[i])
                ft, ff = t_meas[ai], f_meas[ai]
                Hf, Ht = _jacobian(ff, nav), _jacobian(ft, nav)
                if earth:
                    Hf[:, :NAV] = Hf[:, :NAV] @ M_r[i]
                    Ht[:, :NAV] = Ht[:, :NAV] @ M_r[i]
                name = names[ai]
                self.readings[epoch_of[k]].append(Reading(
                    name, t, j, Hf, ff.noise(), Ht, ft.noise(),
                    bool(name == "gnss" and ai < len(times) and gnss_outage[j])))

    def local(self, P: FloatArray, e) -> FloatArray:
        """Navigation covariances of the error state in the terms a user reads: the identity in
        the flat frame; on the Earth those of the local NED errors at the true position.

        Parameters
        ----------
        P : ndarray, shape (..., 9, 9)
        e : int or ndarray
            Their epochs.

        Returns
        -------
        ndarray, shape (..., 9, 9)
        """
        if self.output is None:
            return P
        M = self.output[e]
        return M @ P @ np.swapaxes(M, -1, -2)

    # -------------------------------------------------------------------- weights
    def weights(self, imu_scale: float = 1.0, split: bool = False,
                initial_error: bool = False) -> tuple[FloatArray, FloatArray, list[str]]:
        """The weights of the ingredients for the filter and the truth.

        Parameters
        ----------
        imu_scale : float
            Every IMU error term times this (its variances times its square), for the filter
            and the truth alike.
        split : bool
            One truth row per ingredient (the budget; their sum is the total) instead of one
            row, the total.
        initial_error : bool
            The true navigation error starts with the filter's initial covariance
            (``[initial]``); by default it starts at zero, as the simulated runs do (the filter
            is started at the true state, believing the ``[initial]`` uncertainty).

        Returns
        -------
        filter_weights : ndarray, shape (J,)
        truth_weights : ndarray, shape (M, J)
        names : list of str
            The truth rows.
        """
        k2 = float(imu_scale) ** 2
        w = np.array([k2 if i.kind == "imu" else 1.0 for i in self.ingredients])
        carried = np.array([i.kind != "aid" or bool(self.filter_states[self.layout[i.name]].all())
                            for i in self.ingredients])
        wf = np.where(carried, w, 0.0)
        if not initial_error:
            w = np.where([i.kind == "initial" for i in self.ingredients], 0.0, w)
        if not split:
            return wf, w[None], ["total"]
        return wf, np.diag(w), [i.name for i in self.ingredients]

    # -------------------------------------------------------------------- the pass
    def propagate(self, filter_weights: FloatArray, truth_weights: FloatArray,
                  active: np.ndarray | None = None, *, start: int = 0, stop: int | None = None,
                  P_start: FloatArray | None = None, keep: bool = True) -> PassResult:
        """The filter's covariance and the true error covariance, epoch by epoch.

        Parameters
        ----------
        filter_weights : ndarray, shape (J,)
            Ingredient weights of the filter's model (:meth:`weights`).
        truth_weights : ndarray, shape (M, J)
            One row per contribution of the truth propagated.
        active : ndarray of bool, shape (B, G), optional
            Per scenario, which GNSS fixes are used (default: one scenario, the file's outages
            left out).
        start, stop : int
            The epochs (default all).
        P_start : ndarray, shape (B, 1 + M, n, n), optional
            The covariances at epoch ``start`` after its readings (default the initial ones,
            with ``start`` 0).
        keep : bool
            Keep the navigation blocks of every epoch (else only :attr:`PassResult.final`).

        Returns
        -------
        PassResult
        """
        E = self.t.size - 1
        stop = E if stop is None else int(stop)
        n, k = self.n, NAV
        Wf = np.asarray(filter_weights, float)
        Wt = np.atleast_2d(np.asarray(truth_weights, float))
        W = np.concatenate([Wf[None], Wt])                        # (1 + M, J)
        M1 = W.shape[0]
        if active is None:
            gn = [r for rs in self.readings for r in rs if r.sensor == "gnss"]
            active = np.array([[not r.outage for r in gn]]) if gn else np.ones((1, 0), bool)
        active = np.asarray(active, dtype=bool)
        B = active.shape[0]
        if P_start is None:
            if start != 0:
                raise ValueError("P_start is needed to start after epoch 0")
            P0 = np.einsum("mj,jab->mab", W, np.stack([i.P0 for i in self.ingredients]))
            P = np.repeat(P0[None], B, axis=0)
        else:
            P = np.array(P_start, dtype=float)
        # the process noise of each row: the weighted ingredients
        jq = [(j, i.q) for j, i in enumerate(self.ingredients) if i.q is not None]
        ja = [(j, sl) for j, sl in self._aid_q]
        r_scale = {i.sensor: W[:, j] for j, i in enumerate(self.ingredients) if i.kind == "white"}
        nkeep = stop - start + 1 if keep else 1
        fp, fq = np.empty((B, nkeep, k, k)), np.empty((B, nkeep, k, k))
        tp, tq = np.empty((B, M1 - 1, nkeep, k, k)), np.empty((B, M1 - 1, nkeep, k, k))

        def record(slot, prior, e):
            if not keep:
                return
            nav = self.local(P[:, :, :k, :k], e)
            (fp if prior else fq)[:, slot] = nav[:, 0]
            (tp if prior else tq)[:, :, slot] = nav[:, 1:]

        def readings(e, P, gi):
            for r in self.readings[e]:
                if r.sensor == "gnss":
                    act = active[:, gi]
                    gi += 1
                    if not act.any():
                        continue
                else:
                    act = None
                P = _update(P, r, act, r_scale.get(r.sensor))
            return P, gi

        record(0, True, start)
        gi = sum(1 for rs in self.readings[:start + 1] for r in rs if r.sensor == "gnss")
        if P_start is None and self.readings[0]:         # readings on the initial state
            P, gi = readings(0, P, 0)
        record(0, False, start)
        for e in range(start, stop):
            F, G, D = self.F[e], self.G[e], self.D[e]
            Qnn = sum(W[:, j, None, None] * self.Q[q][0][e] for j, q in jq)
            Qns = sum(W[:, j, None, None] * self.Q[q][1][e] for j, q in jq)
            Qss = sum(W[:, j, None] * self.Q[q][2][e] for j, q in jq)
            for j, sl in ja:
                add = np.zeros((M1, n - k))
                add[:, sl.start - k:sl.stop - k] = W[:, j, None] * self.Qaid[e, sl.start - k:
                                                                              sl.stop - k]
                Qss = Qss + add
            P = predict_blocks(P, F, G, D, Qnn, Qns, Qss[..., :, None] * np.eye(Qss.shape[-1]))
            slot = e + 1 - start if keep else 0
            record(slot, True, e + 1)
            P, gi = readings(e + 1, P, gi)
            record(slot, False, e + 1)
        return PassResult(self.t[start:stop + 1] if keep else self.t[stop:stop + 1],
                          fp, fq, tp, tq, P)


def _update(P, r: Reading, active, r_scale):
    """One reading: the filter's gain from its own covariance (row 0), Joseph's form for it
    (``H_f``, ``R_f``) and for every truth row (``H_t``, ``R_t`` times the row's weight of
    this aid's white noise); scenarios where the reading is not used keep ``P``."""
    Pf = P[:, 0]
    K, _, HP = gain(Pf, r.Hf, r.Rf)                            # (B, n, m)
    if active is not None:
        K = K * active[:, None, None]
    out = np.empty_like(P)
    out[:, 0] = joseph(Pf, K, r.Hf, r.Rf, HP)
    scale = np.ones(P.shape[1] - 1) if r_scale is None else r_scale[1:]
    out[:, 1:] = joseph(P[:, 1:], K[:, None], r.Ht, scale[:, None, None] * r.Rt)
    return out


def _jacobian(m: Measurement, nav: NavPoint) -> FloatArray:
    """A measurement's Jacobian at one point (a model that takes batches given a batch of
    one)."""
    if m.batched:
        one = NavPoint(nav.q[None], nav.v[None], nav.p[None], nav.omega[None], nav.dt,
                       nav.estimates[None], nav.gyro_input[None])
        return np.array(m.jacobian(one)[0], dtype=float)
    return np.array(m.jacobian(nav), dtype=float)


def _local_states(motion, t: FloatArray, attitude: bool = False):
    """An EarthMotion's local states at ``t``: ``[lat, lon, h]`` and NED velocity (with
    ``attitude``: ``q_nb`` first)."""
    st = motion.states(t)
    if attitude:
        return st.quaternion, st.velocity, st.position
    return st.position, st.velocity


def _earth_trajectory(motion, h: float, t: FloatArray, tm: FloatArray) -> Trajectory:
    """The inertial-frame linearisation of an EarthMotion over steps ending at ``t[1:]`` with
    midpoints ``tm`` (steps of any length; the inertial frame is ECEF at t = 0)."""
    C = dcm_ecef_to_inertial(tm) @ quat_to_dcm(motion.ecef_attitude(tm))     # C_ib
    w = motion.angular_rate(tm)
    fb = motion.specific_force(tm)
    f_i = np.einsum("nij,nj->ni", C, fb)
    r_i = np.einsum("nij,nj->ni", dcm_ecef_to_inertial(tm), motion.ecef(tm)[0])
    return Trajectory(h, t, C, f_i, w, fb, float(np.linalg.norm(w, axis=1).max()),
                      float(np.linalg.norm(fb, axis=1).max()), "wgs84",
                      gravitation_gradient(r_i))
