"""Aided navigation: the error-state (feedback) Kalman filter that fuses the strapdown with any
aids — GNSS, a barometer, a heading reference, vehicle constraints, zero-velocity updates, an
odometer, or a measurement a user writes — and its Rauch–Tung–Striebel smoother.

The filter takes its aids as a list of :class:`~imunav.sensors.aids.Aid` (a measurement model
and its readings): ``run_filter(signals, q0, v0, p0, measurements=[Aid(…), …], imu=…)``; an
``AIDING.toml`` (:class:`~imunav.sensors.aids.AidingConfig`) with its readings
(:class:`~imunav.sensors.aids.AidingData`) is the convenience that builds that list
(:func:`~imunav.sensors.aids.aids_from`). The error state and its discrete dynamics are
:class:`~imunav.estimation.system.AidedSystem`'s; the prediction and the update are the Kalman
core's (:mod:`~imunav.estimation.kalman`); the readings' nodes the schedule's
(:mod:`~imunav.estimation.schedule`).

The loop (one loop, for one run or ``R`` runs of one record filtered at once, each with its own
linearisation — what a Monte Carlo of the filter needs):

1. the strapdown (any algorithm of the family, :mod:`imunav.strapdown.registry`) integrates
   the IMU samples, compensated by the current estimates of the sensor errors, from one
   epoch with readings to the next, at the IMU rate;
2. the covariance is propagated on its own step (``covariance_step``, default 0.1 s, ending at
   every epoch with readings), linearised along the estimated trajectory of that step (its
   midpoint attitude, its mean specific force ``Δv_n/h − g_n``, its mean body rate and force);
3. at an epoch each reading is predicted from the navigation state (a reading between two IMU
   samples from the nearest one, moved by ``v·dt``), gated (χ² of its innovation, probability
   ``gate``) and used in a Joseph-form update, one aid after another;
4. the estimate is fed back: the navigation state corrected (``q ← exp(φ̂) ⊗ q``,
   ``v ← v − δv̂``, ``p ← p − δp̂``), the sensor and aid estimates moved by their part
   (``ŝ ← ŝ + x̂``; between epochs a Gauss–Markov estimate decays as its state does), and the
   error state starts again from zero.

Standard deviations are exact at the covariance epochs; at the IMU samples in between they are
interpolated linearly in variance. The smoother keeps each covariance step's ``Φ`` and
predicted covariance and runs :func:`~imunav.estimation.smoother.smooth_history` (the RTS
steps in the coordinates of the uncorrected state at each epoch).

**On the rotating Earth** (``earth="wgs84"``) the navigation and the error state are in the
inertial frame (:mod:`~imunav.estimation.inertial`): readings are predicted in local NED at the
estimate and their Jacobians carried onto the inertial errors; the reported covariances (and
the smoother's corrections) are mapped by the same exact map.

May import: ``imunav.core``, ``imunav.earth``, ``imunav.sensors``, ``imunav.strapdown``,
``imunav.estimation``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import numpy.typing as npt

from imunav.core.kernels import FloatArray, quat_exp, quat_mul, quat_to_dcm
from imunav.core.layout import DP, DV, NAV, PHI
from imunav.core.rotations import quat_normalize
from imunav.core.states import States
from imunav.core.threads import limit_blas
from imunav.core.validation import ImunavError, as_float_array, check_positive
from imunav.earth import gravitation_gradient
from imunav.estimation.error_model import EARTH, FLAT, FlatErrorModel, Trajectory, local_error_map
from imunav.estimation.health import assess_health
from imunav.estimation.inertial import EarthSide, inject_local
from imunav.estimation.kalman import predict_blocks, update_batch
from imunav.estimation.results import SD_COLUMNS, BatchResult, FilterResult, Innovations, nav_sd
from imunav.estimation.schedule import Schedule, step_length
from imunav.estimation.smoother import smooth_history
from imunav.estimation.system import AidedSystem
from imunav.sensors.aids import (
    AIDS,
    Aid,
    AidingConfig,
    AidingData,
    InitialConfig,
    NavPoint,
    aids_from,
)
from imunav.sensors.models import ImuModel
from imunav.sensors.signals import ImuSignals
from imunav.strapdown.registry import resolve

__all__ = ["SD_COLUMNS", "BatchResult", "FilterResult", "Innovations", "nav_sd", "run_filter",
           "run_filter_batch", "run_smoother"]

# ----------------------------------------------------------------------------- the loop

def _inject(q, v, p, e):
    """The state corrected by the navigation error ``e`` (…, 9): ``exp(φ) ⊗ q``, ``v − δv``,
    ``p − δp``."""
    q = quat_mul(quat_exp(e[..., PHI]), q)
    return q / np.linalg.norm(q, axis=-1, keepdims=True), v - e[..., DV], p - e[..., DP]


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
    """The estimated motion over each covariance step of R runs (nodes (N + 1, R, ·), samples
    (W, R, 3)): midpoint attitude, mean ``f_n``, mean compensated ``ω_b`` and ``f_b``; the
    steps of every run side by side, step-major (step i of run r at ``i·R + r``)."""
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
    zero = np.zeros((1,) + gw.shape[1:])
    if kind == "increments":
        cg = np.concatenate([zero, np.cumsum(gw[off:], axis=0)])
        ca = np.concatenate([zero, np.cumsum(aw[off:], axis=0)])
    else:                                       # trapezoid over the rate samples
        cg = np.concatenate([zero, np.cumsum((gw[off:-1] + gw[off + 1:]) / 2, axis=0)])
        ca = np.concatenate([zero, np.cumsum((aw[off:-1] + aw[off + 1:]) / 2, axis=0)])
    om = (cg[hi - a0] - cg[lo - a0]) / Lr
    fb = (ca[hi - a0] - ca[lo - a0]) / Lr
    K, R = qa.shape[:2]
    traj = Trajectory(h, np.zeros(K * R + 1), quat_to_dcm(qa.reshape(K * R, 4)),
                      f_n.reshape(K * R, 3), om.reshape(K * R, 3), fb.reshape(K * R, 3))
    return traj, L.tolist()


#: The largest inflation of the covariance at one re-admission, and the most re-admissions of
#: one aid in one run (beyond them the aid stays locked out: its readings disagree with the run
#: for good, and the warnings say so).
MAX_INFLATION = 1e4
MAX_READMISSIONS = 3


def _inflation(P: FloatArray, H: FloatArray, R: FloatArray, nu: FloatArray) -> float:
    """The factor on the whole error covariance that makes the innovation ``nu`` plausible —
    its NIS down to its degrees of freedom — for a reading re-admitted after a lock-out:
    bisection on ``log f`` in [0, ln 1e4] (the NIS falls as the covariance grows; a reading that
    even ten thousand times the covariance cannot explain is admitted at that). The whole
    covariance, not only the navigation errors': a filter that diverged has usually also
    learnt a wrong sensor bias, which must be free to move again."""
    m = nu.size
    HPH = H @ P @ H.T

    def nis(f):
        return float(nu @ np.linalg.solve(f * HPH + R, nu))

    if nis(1.0) <= m:
        return 1.0
    lo, hi = 0.0, np.log(MAX_INFLATION)
    if nis(np.exp(hi)) > m:
        return float(np.exp(hi))
    for _ in range(40):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if nis(np.exp(mid)) > m else (lo, mid)
    return float(np.exp(hi))


def _evaluate(m, nav: NavPoint, R: int) -> tuple[FloatArray, FloatArray]:
    """A measurement's prediction (R, m) and Jacobian (R, m, n) for R runs: in one call when
    the model takes batches, else run by run."""
    if m.batched:
        return np.asarray(m.predict(nav), float), np.asarray(m.jacobian(nav), float)
    pred = np.stack([np.asarray(m.predict(nav.run(r)), float).reshape(m.size)
                     for r in range(R)])
    H = np.stack([np.asarray(m.jacobian(nav.run(r)), float) for r in range(R)])
    return pred, H


@dataclass
class _Run:
    """The state of the loop (every array with a run axis R)."""

    R: int
    n: int
    q: FloatArray
    v: FloatArray
    p: FloatArray
    s_hat: FloatArray
    P: FloatArray
    ep_idx: list = field(default_factory=list)
    ep_post: list = field(default_factory=list)
    ep_prior: list = field(default_factory=list)
    ep_est: list = field(default_factory=list)


class _Logs:
    """Every reading's innovation, per aid, preallocated."""

    def __init__(self, aids: list[Aid], R: int):
        self.t = [a.t.copy() for a in aids]
        self.nu = [np.full((len(a), R, a.measurement.size), np.nan) for a in aids]
        self.S = [np.full((len(a), R, a.measurement.size, a.measurement.size), np.nan)
                  for a in aids]
        self.nis = [np.full((len(a), R), np.nan) for a in aids]
        self.acc = [np.zeros((len(a), R), dtype=bool) for a in aids]
        self.used = [np.zeros(len(a), dtype=bool) for a in aids]

    def innovations(self, aids: list[Aid], units: list[tuple], r: int) -> dict:
        out = {}
        for i, a in enumerate(aids):
            u = self.used[i]
            out[a.name] = Innovations(a.name, self.t[i][u], self.nu[i][u, r], self.S[i][u, r],
                                      self.nis[i][u, r], self.acc[i][u, r], units[i])
        return out


class _Filter:
    """One loop over a record for R runs (see the module docstring)."""

    def __init__(self, sigs: list[ImuSignals], q0, v0, p0, aids: list[list[Aid]], *, imu,
                 initial, algorithm, covariance_step, gate, model, earth, units, recover=5):
        s0 = sigs[0]
        R = self.R = len(sigs)
        self.algo = algo = resolve(s0.kind, algorithm)
        self.kind, self.h, self.g = s0.kind, 1.0 / s0.rate, s0.g
        M = self.M = len(s0)
        N = self.N = M if self.kind == "increments" else M - 1
        if N < 1:
            raise ImunavError(f"{self.kind} signals need at least {algo.min_samples} samples")
        self.t_nodes = s0.state_times()
        t0 = float(self.t_nodes[0])
        div = self.h if self.kind == "increments" else 1.0
        self.gyro_raw = np.stack([s.gyro for s in sigs], axis=1) / div          # (M, R, 3)
        self.accel_raw = np.stack([s.accel for s in sigs], axis=1) / div
        imu = imu or ImuModel(name="ideal")
        self.aids = aids[0]
        names = [a.name for a in self.aids]
        if len(set(names)) != len(names):
            raise ImunavError(f"two aids share one name ({', '.join(names)}): give each "
                              "measurement a name of its own", argument="measurements")
        self.units = units
        peaks = (float(np.linalg.norm(self.gyro_raw, axis=-1).max()),
                 float(np.linalg.norm(self.accel_raw, axis=-1).max()))
        self.system = AidedSystem(imu, [a.measurement for a in self.aids], h=self.h,
                                  kind=self.kind, decimate=imu.decimation(s0.rate), peaks=peaks,
                                  initial=initial, model=model)
        self.earth = EarthSide(self.h, t0, q0, v0, p0) if earth == "wgs84" else None
        self.frame = earth
        # the readings: one schedule, the same in every run
        sched = self.sched = Schedule(t0, self.h, N, algo.align)
        for i, a in enumerate(self.aids):
            if a.t.size > 2:                    # an aid faster than the IMU: refused
                span = float(a.t[-1] - a.t[0])
                if span > 0 and (a.t.size - 1) / span > s0.rate * (1 + 1e-6):
                    raise ImunavError(f"aid {a.name}: {a.t.size} readings in {span:.6g} s "
                                      f"({(a.t.size - 1) / span:.6g} Hz) are faster than the "
                                      f"IMU ({s0.rate:g} Hz): the filter updates at IMU "
                                      "samples; thin them", argument="measurements")
            sched.add(i, a.t, a.name)
        for run in aids[1:]:
            other = Schedule(t0, self.h, N, algo.align)
            if len(run) != len(self.aids):
                raise ImunavError("run_filter_batch needs the same aids in every run",
                                  argument="data")
            for i, a in enumerate(run):
                other.add(i, a.t, a.name)
            if not sched.same_as(other):
                raise ImunavError("run_filter_batch needs the same reading times in every run",
                                  argument="data")
        self.values = [np.stack([run[i].values for run in aids], axis=1)
                       for i in range(len(self.aids))]                    # (N_i, R, m)
        self.noise = []
        for i, a in enumerate(self.aids):
            if a.sigma is None:
                self.noise.append(None)
            else:
                s = np.stack([run[i].sigma for run in aids], axis=1)
                self.noise.append(s * s)                                 # (N_i, R, m)
        self.gate = None if gate is None or gate >= 1 else gate
        self.recover = int(recover) if recover else 0
        self.streak = [np.zeros(R, dtype=int) for _ in self.aids]
        self.grace = [np.zeros(R, dtype=int) for _ in self.aids]
        self.broken = [np.zeros(R, dtype=int) for _ in self.aids]
        self.readmitted = [[[] for _ in range(R)] for _ in self.aids]
        self.n_readmit = [np.zeros(R, dtype=int) for _ in self.aids]
        self.m_cov = step_length(covariance_step, self.h, algo.align)
        n = self.system.n
        q = np.empty((N + 1, R, 4))
        v = np.empty((N + 1, R, 3))
        p = np.empty((N + 1, R, 3))
        q[0], v[0], p[0] = q0, v0, p0
        P = np.repeat(self.system.P0[None], R, axis=0)
        self.st = _Run(R, n, q, v, p, np.zeros((R, n - NAV)), P)
        self.logs = _Logs(self.aids, R)
        self.comp = [(self.system.layout[s.name], s.states) for s in self.system.sources]

    # ------------------------------------------------------------------ one epoch's readings
    def readings(self, k: int, P: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Every reading at node ``k``, one after another: the correction and ``P``."""
        st, sysm, R, n = self.st, self.system, self.R, self.st.n
        est = np.concatenate([np.zeros((R, NAV)), st.s_hat], axis=1)
        i = min(k, self.M - 1)
        u, f = self.gyro_raw[i], self.accel_raw[i]                       # (R, 3)
        Mg = sysm.triad_input("gyro", u, f)                               # (R, 3, n)
        omega = u - np.einsum("rik,rk->ri", Mg[:, :, NAV:], st.s_hat)
        x = np.zeros((R, n))
        t = float(self.t_nodes[k])
        inertial = self.earth.state() if self.earth is not None else None
        for ai, j, dt, _ in self.sched.at[k]:
            a = self.aids[ai]
            m = a.measurement
            est_x = est.copy()
            est_x[:, NAV:] += x[:, NAV:]
            values = self.values[ai][j]                                   # (R, m)
            if self.earth is None:
                qk, vk, pk = _inject(st.q[k], st.v[k], st.p[k], x[:, :NAV])
                nav = NavPoint(qk, vk, pk, omega, dt, est_x, Mg)
            else:
                nav, lla, Mmap = self.earth.reading(t, inertial, x[:, :NAV], omega, dt, est_x, Mg)
                values = m.localise(values, lla)
            pred, H = _evaluate(m, nav, R)
            if self.earth is not None:
                H = H.copy()
                H[..., :NAV] = H[..., :NAV] @ Mmap
            z = m.residual(pred, values)
            Rn = (m.noise() if self.noise[ai] is None else
                  self.noise[ai][j][:, :, None] * np.eye(m.size))
            admit = None
            gate = self.gate if m.gated else None
            if self.recover and gate is not None:
                lock = (self.streak[ai] >= self.recover) & (self.n_readmit[ai] < MAX_READMISSIONS)
                admit = self.grace[ai] > 0
                if lock.any():
                    P = P.copy()
                    for r in np.nonzero(lock)[0]:
                        Rr = Rn if Rn.ndim == 2 else Rn[r]
                        f = _inflation(P[r], H[r], Rr, z[r])
                        P[r] = f * P[r]
                        self.readmitted[ai][r].append((float(self.t_nodes[k] + dt), f))
                        self.n_readmit[ai][r] += 1
                    admit = admit | lock
                    self.grace[ai][lock] = self.recover + 1
                self.grace[ai] = np.maximum(self.grace[ai] - 1, 0)
                if not admit.any():
                    admit = None
            up = update_batch(x, P, z + np.einsum("rmn,rn->rm", H, x), H, Rn, gate=gate,
                              admit=admit, robust=True)
            self.broken[ai] += np.isnan(up.nis)
            self.streak[ai] = np.where(up.accepted, 0, self.streak[ai] + 1)
            lg = self.logs
            lg.nu[ai][j], lg.S[ai][j], lg.nis[ai][j], lg.acc[ai][j] = (up.innovation, up.S,
                                                                      up.nis, up.accepted)
            lg.used[ai][j] = True
            x, P = up.x, up.P
        return x, P

    def feedback(self, k: int, x: FloatArray) -> None:
        """Correct the state at node ``k`` by ``x`` and move the estimates."""
        st = self.st
        if self.earth is None:
            st.q[k], st.v[k], st.p[k] = _inject(st.q[k], st.v[k], st.p[k], x[:, :NAV])
        else:
            st.q[k], st.v[k], st.p[k] = self.earth.correct(self.t_nodes[k], x[:, :NAV])
        st.s_hat = st.s_hat + x[:, NAV:]

    # ------------------------------------------------------------------ the whole record
    def run(self, smooth: bool):
        st, sysm, R, n = self.st, self.system, self.R, self.st.n
        algo, kind, h, g, M = self.algo, self.kind, self.h, self.g, self.M
        t_nodes = self.t_nodes
        st.ep_idx.append(0)
        st.ep_prior.append(st.P[:, :NAV, :NAV].copy())
        x_hat = np.zeros((R, n))
        P_fed = st.P                                 # the covariance before the reset
        if 0 in self.sched.at:                       # readings at the very start
            x_hat, P_fed = self.readings(0, st.P)
            self.feedback(0, x_hat)
            st.P = sysm.reset(P_fed, x_hat)
        st.ep_post.append(st.P[:, :NAV, :NAV].copy())
        st.ep_est.append(st.s_hat.copy())
        segs = []
        before, after = algo.context
        own = 1 if kind == "rates" else 0
        scale = h if kind == "increments" else 1.0
        a = 0
        for b in self.sched.epochs():
            # the smoother works in the error before the feedback's reset: (x̂, P) there, and
            # the first step's transition Φ G (AidedSystem.reset_jacobian)
            x_first, P_first = x_hat, P_fed
            # strapdown a → b with the compensated samples
            w0, w1 = max(0, a - before), min(M, b + own + after)
            W = w1 - w0
            tw = t_nodes[w0:w1] + (h / 2 if kind == "increments" else 0.0)
            decay = sysm.decay(tw - t_nodes[a])                              # (W, n − 9)
            gw, aw = self.gyro_raw[w0:w1].copy(), self.accel_raw[w0:w1].copy()
            for sl, ss in self.comp:
                cols = slice(sl.start - NAV, sl.stop - NAV)
                s_loc = decay[:, None, cols] * st.s_hat[None, :, cols]       # (W, R, k)
                uu = self.gyro_raw[w0:w1] if ss.triad == "gyro" else self.accel_raw[w0:w1]
                Mx = ss.input_matrix(uu.reshape(-1, 3), self.accel_raw[w0:w1].reshape(-1, 3))
                corr = np.einsum("nik,nk->ni", Mx, s_loc.reshape(W * R, -1)).reshape(W, R, 3)
                if ss.triad == "gyro":
                    gw -= corr
                else:
                    aw -= corr
            bounds = list(range(a, b, self.m_cov)) + [b]
            with np.errstate(all="ignore"):
                if self.earth is None:
                    q, v, p = algo.func(gw * scale, aw * scale, h, st.q[a], st.v[a], st.p[a], g,
                                        a - w0, b - a)
                    ok = (np.isfinite(q[-1]).all() and np.isfinite(v[-1]).all()
                          and np.isfinite(p[-1]).all())
                else:
                    qI, vT, loc = self.earth.advance(algo, gw * scale, aw * scale, h, a - w0,
                                                     b - a)
                    ok = loc is not None
            if not ok:
                raise ImunavError(f"navigation became non-finite between t = {t_nodes[a]:.9g} "
                                  f"and {t_nodes[b]:.9g} s: the signals are too large to "
                                  "integrate")
            if self.earth is None:
                st.q[a + 1:b + 1], st.v[a + 1:b + 1], st.p[a + 1:b + 1] = q[1:], v[1:], p[1:]
                traj, lens = _linearisation(bounds, st.q, st.v, gw, aw, a - w0, kind, h, g)
            else:
                st.q[a + 1:b + 1], st.v[a + 1:b + 1], st.p[a + 1:b + 1] = loc
                # in the inertial frame: C_ib, the thrust's mean f_i (g = 0), Γ at the midpoints
                rel = [k - a for k in bounds]
                traj, lens = _linearisation(rel, qI, vT, gw, aw, a - w0, kind, h, 0.0)
                mid = np.asarray(bounds[:-1]) + np.asarray(lens) // 2
                r_mid = self.earth.r_inertial(t_nodes[mid], st.p[mid])          # (K, R, 3)
                traj = Trajectory(h, traj.t, traj.C, traj.f_n, traj.omega, traj.f_b,
                                  traj.max_rate, traj.max_force, "wgs84",
                                  gravitation_gradient(r_mid.reshape(-1, 3)))
            steps = []
            P = st.P
            for lo, hi, L in _groups(lens):
                blocks = sysm.steps(traj.piece(lo * R, hi * R), L * h)
                Phi_full = blocks.full()[0] if smooth else None
                for i in range(hi - lo):
                    sl = slice(i * R, (i + 1) * R)
                    P = predict_blocks(P, blocks.nav[sl], blocks.gamma[sl], blocks.decay,
                                       blocks.Qnn[sl], blocks.Qnx[sl], blocks.Qxx)
                    steps.append((None if Phi_full is None else Phi_full[i * R:(i + 1) * R], P))
            s_decayed = st.s_hat[None] * sysm.decay(t_nodes[bounds[1:]] - t_nodes[a])[:, None]
            for j, (_, Pj) in enumerate(steps[:-1]):
                st.ep_idx.append(bounds[j + 1])
                st.ep_post.append(Pj[:, :NAV, :NAV].copy())
                st.ep_prior.append(Pj[:, :NAV, :NAV].copy())
                st.ep_est.append(s_decayed[j])
            st.s_hat = s_decayed[-1]
            P_prior = P
            x_hat = np.zeros((R, n))
            P_fed = P
            if b in self.sched.at:
                x_hat, P_fed = self.readings(b, P)
                self.feedback(b, x_hat)
                P = sysm.reset(P_fed, x_hat)
            st.P = P
            st.ep_idx.append(b)
            st.ep_prior.append(P_prior[:, :NAV, :NAV].copy())
            st.ep_post.append(P[:, :NAV, :NAV].copy())
            st.ep_est.append(st.s_hat.copy())
            if smooth:
                if steps and x_first.any():
                    steps[0] = (steps[0][0] @ sysm.reset_jacobian(x_first), steps[0][1])
                segs.append((x_first, P_first, steps))
            a = b
        return segs, x_hat

    # ------------------------------------------------------------------ the outputs
    def epochs(self):
        """Epoch indices and their navigation covariances (local NED on the Earth): (E,),
        (E, R, 9, 9) after and before the readings, and the map used (or None)."""
        st = self.st
        ep = np.asarray(st.ep_idx)
        post, prior = np.asarray(st.ep_post), np.asarray(st.ep_prior)
        M_ep = None
        if self.earth is not None:
            M_ep = local_map(self.earth, self.t_nodes[ep], st.p[ep], st.v[ep])
            MT = np.swapaxes(M_ep, -1, -2)
            post, prior = M_ep @ post @ MT, M_ep @ prior @ MT
        return ep, post, prior, M_ep

    def smoothed(self, segs, x_last, M_ep):
        """The smoother's states and covariances: q, v, p (N + 1, R, ·), the node σ's
        variances (N + 1, R, 9) and the epochs' covariances (E, R, 9, 9)."""
        st = self.st
        ep = np.asarray(st.ep_idx)
        err, err_prior, P_s = smooth_history(segs, x_last, st.P, ep.size, NAV)
        if M_ep is not None:
            err = np.einsum("erij,erj->eri", M_ep, err)
            err_prior = np.einsum("erij,erj->eri", M_ep, err_prior)
            P_s = M_ep @ P_s @ np.swapaxes(M_ep, -1, -2)
        t = self.t_nodes
        q, v, p = st.q.copy(), st.v.copy(), st.p.copy()
        e_nodes = np.zeros((t.size, self.R, NAV))
        var_ep = nav_sd(P_s, q[ep]) ** 2
        var_nodes = np.empty((t.size, self.R, 9))
        e_nodes[ep] = err
        var_nodes[ep] = var_ep
        for k in range(ep.size - 1):
            a, b = ep[k], ep[k + 1]
            if b - a > 1:
                w = ((t[a + 1:b] - t[a]) / (t[b] - t[a]))[:, None, None]
                e_nodes[a + 1:b] = (1 - w) * err[k] + w * err_prior[k + 1]
                var_nodes[a + 1:b] = (1 - w) * var_ep[k] + w * var_ep[k + 1]
        q, v, p = (_inject(q, v, p, e_nodes) if M_ep is None else
                   inject_local(q, v, p, e_nodes))
        return q, v, p, var_nodes, P_s


def local_map(earth: EarthSide, t, lla, v):
    """The map of the inertial errors onto the local NED ones at the epochs ((E,) times,
    (E, R, ·) states): :func:`~imunav.estimation.error_model.local_error_map`."""
    return local_error_map(np.broadcast_to(np.asarray(t, float)[:, None], lla.shape[:-1]), lla,
                           v, earth.t0)


def _node_sd(ep_idx, ep_post, ep_prior, q_nodes, t_nodes) -> FloatArray:
    """σ at every node (N + 1, R, 9): exact at the epochs, variance interpolated linearly in
    between."""
    var_post = nav_sd(ep_post, q_nodes[ep_idx]) ** 2
    var_prior = nav_sd(ep_prior, q_nodes[ep_idx]) ** 2
    out = np.empty((t_nodes.size,) + var_post.shape[1:])
    out[ep_idx] = var_post
    for j in range(ep_idx.size - 1):
        a, b = ep_idx[j], ep_idx[j + 1]
        if b - a > 1:
            w = ((t_nodes[a + 1:b] - t_nodes[a]) / (t_nodes[b] - t_nodes[a]))[:, None, None]
            out[a + 1:b] = (1 - w) * var_post[j] + w * var_prior[j + 1]
    return np.sqrt(out)


# ----------------------------------------------------------------------------- the entry points

def _aids(signals: ImuSignals, aiding, data, measurements) -> tuple[list[Aid], list[tuple]]:
    """The aids of one run (the configuration's, then the user's) and their innovation units."""
    out, units = [], []
    if aiding is not None:
        if data is None:
            raise ImunavError("aiding needs its readings: give data (AidingData)",
                              argument="data")
        for a in aids_from(aiding, data, signals):
            out.append(a)
            units.append(_spec_units(aiding, a.name))
    for a in measurements or []:
        if not isinstance(a, Aid):
            raise ImunavError(f"measurements must be a list of Aid (a Measurement with its "
                              f"readings), got {type(a).__name__}", argument="measurements")
        out.append(a)
        units.append(())
    return out, units


def _spec_units(aiding, name):
    return AIDS[name].units(aiding.get(name))


def _start(q0, v0, p0, R=None):
    q0 = quat_normalize(as_float_array(q0, "q0", last=4), "q0")
    v0 = as_float_array(v0, "v0", last=3)
    p0 = as_float_array(p0, "p0", last=3)
    if R is None:
        for x, name in ((q0, "q0"), (v0, "v0"), (p0, "p0")):
            if x.ndim != 1:
                raise ImunavError(f"{name} must be one state (shape ({x.shape[-1]},)), got "
                                  f"{x.shape}", argument=name)
        return q0[None], v0[None], p0[None]
    return tuple(np.broadcast_to(x, (R, x.shape[-1])).copy() for x in (q0, v0, p0))


#: The longest covariance step (s): the discretisation holds the motion at each step's midpoint.
MAX_COVARIANCE_STEP = 10.0


def _common(signals, covariance_step, earth, model):
    if not isinstance(signals, ImuSignals):
        raise ImunavError(f"signals must be ImuSignals, got {type(signals).__name__}")
    check_positive(covariance_step, "covariance_step")
    if covariance_step > MAX_COVARIANCE_STEP:
        raise ImunavError(f"covariance_step must be in (0, {MAX_COVARIANCE_STEP:g}] s (the "
                          f"motion is held over a step), got {covariance_step:g}",
                          argument="covariance_step")
    if earth not in ("flat", "wgs84"):
        raise ImunavError(f"earth must be 'flat' or 'wgs84', got {earth!r}", argument="earth")
    return model or (EARTH if earth == "wgs84" else FLAT)


@limit_blas
def run_filter(signals: ImuSignals, q0: npt.ArrayLike, v0: npt.ArrayLike, p0: npt.ArrayLike,
               aiding: AidingConfig | None = None, data: AidingData | None = None, *,
               measurements: list[Aid] | None = None, imu: ImuModel | None = None,
               initial: InitialConfig | None = None, algorithm: str | None = None,
               covariance_step: float = 0.1, gate: float | None = 0.9999, smooth: bool = False,
               model: FlatErrorModel | None = None, earth: str = "flat",
               recover: int | None = 5) -> FilterResult:
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
    aiding : AidingConfig, optional
        Aids described by an ``AIDING.toml`` (what the filter assumes of them; GNSS readings
        inside its ``outages`` are not used) and the initial uncertainty (``[initial]``).
    data : AidingData, optional
        Their readings. NHC without readings: the constraint (zero) at ``[nhc] rate``; ZUPT with
        the ``shoe`` detector: stance from the IMU data, else from ``data.zupt``.
    measurements : list of Aid, optional
        Aids given directly: any :class:`~imunav.estimation.measurements.Measurement` with its
        readings (after those of ``aiding``). ``[]`` and no ``aiding``: the unaided filter.
    imu : ImuModel, optional
        The IMU model the filter assumes (default ideal: no sensor states).
    initial : InitialConfig, optional
        The initial uncertainty (default ``aiding.initial``, else none).
    algorithm : str, optional
        Strapdown algorithm (default the most accurate for the kind).
    covariance_step : float
        Longest covariance step (s), rounded to whole IMU intervals.
    gate : float or None
        Probability of the χ² innovation gate (None: no gate): a reading whose normalised
        innovation squared exceeds the χ² quantile of this probability is not used (the aids whose
        ``Measurement.gated`` is False — zero-velocity updates — are never gated).
    smooth : bool
        Also run the RTS smoother (``result.smoothed``).
    model : FlatErrorModel, optional
        The error model (default the frame's: ``FLAT`` or ``EARTH``).
    earth : {"flat", "wgs84"}
        The navigation frame. On ``"wgs84"`` the GNSS readings are ``[lat, lon, h]`` (rad, rad,
        m) [and NED velocity relative to the Earth], the barometer's the height above the
        ellipsoid, the states and standard deviations those of local NED (positions
        ``[lat, lon, h]``, σ in metres).
    recover : int or None
        The recovery from a lock-out, as fielded navigators have: after this many consecutive
        readings of one aid rejected by the gate, the next one is used whatever its innovation,
        the navigation covariance first inflated until that reading is plausible (its NIS down
        to its degrees of freedom); reported in ``result.health`` and its warnings. None or 0:
        no recovery (a filter that diverged keeps rejecting).

    Returns
    -------
    FilterResult
        With ``health`` (:class:`~imunav.estimation.health.Health`: per aid the readings
        used and gated, the longest run of rejections, the re-admissions, the NIS and the
        innovations' autocorrelation against their bands) and its warnings in ``warnings``.

    Raises
    ------
    ImunavError
        For a reading outside the IMU record, missing readings of a configured aid, GNSS
        velocity readings missing while ``velocity_sigma`` is set, two aids of one name, a
        non-positive ``covariance_step``, or a navigation that turns non-finite.
    """
    model = _common(signals, covariance_step, earth, model)
    q0, v0, p0 = _start(q0, v0, p0)
    aids, units = _aids(signals, aiding, data, measurements)
    if initial is None:
        initial = aiding.initial if aiding is not None else None
    f = _Filter([signals], q0, v0, p0, [aids], imu=imu, initial=initial, algorithm=algorithm,
                covariance_step=covariance_step, gate=gate, model=model, earth=earth,
                units=units, recover=recover)
    segs, x_last = f.run(smooth)
    res = _results(f, [0], segs, x_last, smooth)[0]
    res.health = assess_health(res.innovations, {a.name: f.readmitted[i][0]
                                                 for i, a in enumerate(f.aids)},
                               ideal_imu=imu is None or not f.system.sources)
    res.warnings += res.health.warnings
    for i, a in enumerate(f.aids):
        if f.broken[i][0]:
            res.warnings.append(f"{a.name}: {f.broken[i][0]} readings could not be used: the "
                                "filter's covariance lost its meaning (a divergence); its "
                                "estimate is not to be trusted")
    return res


def _results(f: _Filter, runs: list[int], segs, x_last, smooth: bool) -> list[FilterResult]:
    """The :class:`FilterResult` of some runs of a finished loop."""
    ep, post, prior, M_ep = f.epochs()
    st = f.st
    sd = _node_sd(ep, post, prior, st.q, f.t_nodes)
    est = np.asarray(st.ep_est)
    sm = f.smoothed(segs, x_last, M_ep) if smooth else None
    out = []
    for r in runs:
        states = States(f.t_nodes, st.p[:, r], st.v[:, r], st.q[:, r], f.algo.name,
                        frame=f.frame)
        res = FilterResult(states, sd[:, r], ep, post[:, r], f.logs.innovations(f.aids, f.units, r),
                           est[:, r], f.system.layout, warnings=list(f.system.warnings))
        if sm is not None:
            q, v, p, var, P_s = sm
            res.smoothed = FilterResult(
                States(f.t_nodes, p[:, r], v[:, r], q[:, r], f.algo.name, frame=f.frame),
                np.sqrt(var[:, r]), ep, P_s[:, r], res.innovations, res.estimates, res.layout,
                warnings=res.warnings)
        out.append(res)
    return out


def run_smoother(signals: ImuSignals, q0: npt.ArrayLike, v0: npt.ArrayLike, p0: npt.ArrayLike,
                 aiding: AidingConfig | None = None, data: AidingData | None = None,
                 **kw) -> FilterResult:
    """The RTS smoother of the aided filter: :func:`run_filter` with ``smooth=True``, its
    ``smoothed`` result (whose ``innovations`` and ``estimates`` are the filter's).

    Parameters
    ----------
    signals, q0, v0, p0, aiding, data
        As :func:`run_filter`.
    **kw
        As :func:`run_filter` (``measurements``, ``imu``, …).

    Returns
    -------
    FilterResult
    """
    return run_filter(signals, q0, v0, p0, aiding, data, smooth=True, **kw).smoothed


@limit_blas
def run_filter_batch(signals: list[ImuSignals], q0: npt.ArrayLike, v0: npt.ArrayLike,
                     p0: npt.ArrayLike, aiding: AidingConfig | None = None,
                     data: list[AidingData] | None = None, *,
                     measurements: list[list[Aid]] | None = None, imu: ImuModel | None = None,
                     initial: InitialConfig | None = None, algorithm: str | None = None,
                     covariance_step: float = 0.1, gate: float | None = 0.9999,
                     smooth: bool = False, model: FlatErrorModel | None = None,
                     earth: str = "flat", innovations: bool = False, keep: int = 0,
                     recover: int | None = 5) -> BatchResult:
    """:func:`run_filter` on R runs of one record at once — the same loop, every array with a
    run axis, each run with its own linearisation and its own χ² gate (what a Monte Carlo of
    the filter needs).

    The runs must share the record (kind, rate, times) and the reading times (their values
    differ); the states agree with :func:`run_filter` of each run to rounding.

    Parameters
    ----------
    signals : list of ImuSignals
        One record per run.
    q0 : array_like, shape (R, 4) or (4,)
    v0, p0 : array_like, shape (R, 3) or (3,)
        The initial states.
    aiding : AidingConfig, optional
    data : list of AidingData, optional
        One per run.
    measurements : list of list of Aid, optional
        Per run, aids given directly (the same models and times in every run).
    imu, initial, algorithm, covariance_step, gate, smooth, model, earth, recover
        As :func:`run_filter`.
    innovations : bool
        Keep every run's innovations (:attr:`BatchResult.innovations`).
    keep : int
        Keep the whole :class:`FilterResult` of the first ``keep`` runs.

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
    if R < 1 or (data is not None and len(data) != R) or (
            measurements is not None and len(measurements) != R):
        raise ImunavError(f"run_filter_batch needs one AidingData (and one list of aids) per "
                          f"run: {R} signals", argument="data")
    s0 = signals[0]
    model = _common(s0, covariance_step, earth, model)
    for s in signals:
        if not isinstance(s, ImuSignals):
            raise ImunavError(f"signals must be ImuSignals, got {type(s).__name__}")
        if (s.kind, s.rate, s.g, len(s)) != (s0.kind, s0.rate, s0.g, len(s0)) or \
                not np.array_equal(s.t, s0.t):
            raise ImunavError("run_filter_batch needs runs of one record (kind, rate, g, times)",
                              argument="signals")
    q0, v0, p0 = _start(q0, v0, p0, R)
    per, units = [], []
    for r in range(R):
        aids, units = _aids(signals[r], aiding, None if data is None else data[r],
                            None if measurements is None else measurements[r])
        per.append(aids)
    if initial is None:
        initial = aiding.initial if aiding is not None else None
    f = _Filter(signals, q0, v0, p0, per, imu=imu, initial=initial, algorithm=algorithm,
                covariance_step=covariance_step, gate=gate, model=model, earth=earth,
                units=units, recover=recover)
    segs, x_last = f.run(smooth)
    ep, post, _, M_ep = f.epochs()
    st = f.st
    lg = f.logs
    counts = {a.name: int(lg.used[i].sum()) for i, a in enumerate(f.aids)}
    rejected = {a.name: (~lg.acc[i][lg.used[i]]).sum(axis=0).astype(int)
                for i, a in enumerate(f.aids)}
    readmitted = {a.name: np.array([len(f.readmitted[i][r]) for r in range(R)])
                  for i, a in enumerate(f.aids)}
    out = BatchResult(f.t_nodes, st.q, st.v, st.p, ep, post, counts, rejected, f.algo.name,
                      list(f.system.warnings), frame=earth)
    out.readmitted = readmitted
    if innovations:
        out.innovations = [lg.innovations(f.aids, f.units, r) for r in range(R)]
    if smooth:
        q, v, p, _, P_s = f.smoothed(segs, x_last, M_ep)
        out.smoothed = {"quaternion": q, "velocity": v, "position": p, "P_nav": P_s}
    if keep:
        out.results = _results(f, list(range(min(keep, R))), segs, x_last, smooth)
    return out
