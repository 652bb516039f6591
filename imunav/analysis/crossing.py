"""The whole outage: how likely the position error stays within the tolerance at *every* epoch of
a GNSS outage, from the covariance analysis of the filter along the true motion.

The true error ``z`` of the filter linearised along the truth
(:class:`~imunav.analysis.aided_covariance.AlongTruth`) is a linear Gauss–Markov process: with
the filter's gains ``K`` fixed by its own (deterministic) covariance,

    between epochs     z ← Φ_e z + w_e,               w_e ~ N(0, Q_e)
    at a reading       z ← z − K (H_t z + v),         v ~ N(0, R_t)

(the recursion whose covariance :meth:`AlongTruth.propagate
<imunav.analysis.aided_covariance.AlongTruth.propagate>` carries: ``P ← Φ P Φᵀ + Q``, Joseph's
form). Its values at the epochs of an outage are therefore jointly Gaussian, the cross-epoch
covariance ``Cov(z_j, z_k) = Ψ_{j,k} P_k`` (``Ψ`` the closed loop's transition from ``k`` to
``j``) — and the probability that the position error ``x_k`` (3 rows of ``z``; on the Earth
local NED) stays within the tolerance at every epoch,

    p_within = P(|x_k| ≤ r for every epoch k of the outage),

is a Gaussian integral over an intersection of cylinders in ``3K`` dimensions (``K`` a few
hundred epochs): no closed form, and far too many dimensions for a deterministic quadrature.
It is evaluated here by sampling the process itself (:func:`walk`): ``S`` paths drawn from its
exact law — the state at the outage's start (the last fix used, after its update) from
``N(0, P)``, then the recursion above with the same ``Φ``, ``Q``, ``K``, ``H``, ``R`` the
covariance pass uses (the filter's and the true covariance are walked beside the paths, the
same numbers as :meth:`~imunav.analysis.aided_covariance.AlongTruth.propagate`'s) — and
counting the paths inside at every epoch. This is not a Monte Carlo of the filter (no
strapdown, no linearisation along an estimate, no gate: that is
:func:`~imunav.analysis.aided_montecarlo.aided_monte_carlo`, the independent check): it is the
quadrature of one known Gaussian integral, whose only error is the sampling one.

That error is made small with a control variate (:meth:`Window.p_within`): the exact
probability inside at one epoch ``*`` of the outage, ``P(|x_*| ≤ r)`` from its marginal
covariance (:func:`~imunav.analysis.gaussnorm.norm_cdf`), less the sampled fraction of paths
inside at ``*`` but outside at another epoch. Unbiased, never above the exact ``P(|x_*| ≤ r)``
(an upper bound of the whole), and its error ``√(δ(1 − δ)/S)`` depends on that small fraction
``δ`` only — a few times below the plain count's ``√(p(1 − p)/S)``: with the default
:data:`SAMPLES` about 0.002–0.003 near 0.95 (reported as ``p_within_whole_outage_se``). The
draws come from ``seed`` (the same answer every time); the paths are kept in float32 (their
rounding, ~1e-7 of the error, is far below their sampling error).

The paths use common random numbers: the noise of an epoch (the IMU's, an aid's) is drawn once
and shared by every outage walked at that epoch, as one sensor's noise is the same whichever
GNSS fixes are used — so comparisons between outages (the search for the worst start) are not
blurred by independent sampling errors.

Why not a bound: a union (Bonferroni) bound over the epochs sums hundreds of strongly
correlated exceedance probabilities and is useless for outages of a few hundred epochs; a
first-passage bound (the probability outside at the start plus the expected number of
outward crossings between epochs) is sound and tight when paths rarely cross twice, but each
of its terms is itself a six-dimensional Gaussian integral over a ball and a ball's outside —
sampling the exact law answers the question itself at a smaller cost, with its error stated.

The tolerance applies to the **3-D norm** of the position error, as every ``position_p95_*``
of the aided answers; the horizontal (north–east) error's probability is kept beside it
(``horizontal=True``).

May import: ``imunav.core``, ``imunav.estimation``, ``imunav.analysis``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from imunav.analysis.aided_covariance import AlongTruth
from imunav.analysis.gaussnorm import eigenvalues, norm_cdf, norm_quantile, tabulated_quantile_bounds
from imunav.core.kernels import FloatArray
from imunav.core.layout import DP, NAV, PHI
from imunav.core.threads import limit_blas
from imunav.estimation.kalman import gain, joseph, predict_blocks

__all__ = ["LEVEL", "SAMPLES", "Window", "factor", "walk"]

#: The probability the verdict asks for: inside the tolerance at every epoch of an outage.
LEVEL = 0.95

#: Paths sampled per outage: with the control variate a standard error of 0.002–0.003 on a
#: probability near 0.95 (at most 0.011, for half the paths leaving and coming back).
SAMPLES = 2000


@dataclass
class Window:
    """One outage walked: the epochs from its last fix used, the true position covariance at
    each, and which sampled paths are inside the tolerance at each.

    Attributes
    ----------
    t : ndarray, shape (K,)
        The epochs' times (s), from the last fix used (after its update) to the last epoch
        walked.
    cov : ndarray, shape (K, 3, 3)
        The true position-error covariance after each epoch's readings (m²; local NED).
    inside : ndarray of bool, shape (K, S)
        Per epoch and path: the 3-D position error within the tolerance.
    inside_horizontal : ndarray of bool, shape (K, S)
        The same for the horizontal (north–east) error.
    tolerance : float
    stopped : str
        Why the walk stopped: ``"stop"`` (the epoch asked), ``"failed"`` (no window reaching
        further can pass: an epoch's exact probability inside, or clearly the paths' fraction
        inside at every epoch so far, fell below the level), ``"end"`` (the record's end).
    attitude_p95 : ndarray, shape (K,)
        The p95 of the true attitude error's norm at each epoch (rad): the covariance's own
        linearisation check (:data:`~imunav.analysis.aided_assessment.ATTITUDE_VALID`).
    """

    t: FloatArray
    cov: FloatArray
    inside: np.ndarray
    inside_horizontal: np.ndarray
    tolerance: float
    stopped: str
    attitude_p95: FloatArray | None = None

    @property
    def samples(self) -> int:
        """Paths sampled.

        Returns
        -------
        int
        """
        return int(self.inside.shape[1])

    def epochs(self, until: float) -> int:
        """How many epochs come before ``until`` (the next fix used: its epoch is where the
        error is corrected, so it is not one of the outage's).

        Parameters
        ----------
        until : float
            Seconds.

        Returns
        -------
        int
        """
        return int(np.count_nonzero(self.t < until - 1e-9))

    def p_within(self, until, horizontal: bool = False) -> tuple[FloatArray, FloatArray]:
        """The probability that the position error stays within the tolerance at every epoch
        from the last fix used until ``until`` (excluded), and its standard error.

        The estimate with an exact marginal as control variate: ``P(|x_*| ≤ r)`` at an epoch
        ``*`` of the window (:func:`~imunav.analysis.gaussnorm.norm_cdf`, exact) less the
        fraction of paths inside at ``*`` but outside at some other epoch of the window —
        unbiased whichever epoch ``*`` is (clipped at 0), and never above the exact probability
        at ``*`` (an upper bound of the whole); its error is ``√(δ(1 − δ)/S)`` with ``δ`` that
        fraction (``δ = (c + 1)/(S + 2)`` for ``c`` such paths: Laplace's rule, so that none
        seen is not read as no error), smallest where the marginal is: ``*`` is the epoch
        with the largest p95 by the tabulated bounds (within 3 %:
        :func:`~imunav.analysis.gaussnorm.tabulated_quantile_bounds`). Near 0.95 the error is
        a few times smaller than the plain fraction's ``√(p(1 − p)/S)``.

        Parameters
        ----------
        until : float or array_like
            The next fix used (s), or just past the last epoch walked.
        horizontal : bool
            The horizontal error's (default the 3-D error's: the tolerance's meaning).

        Returns
        -------
        p, se : ndarray, shape of ``until``
        """
        ins = self.inside_horizontal if horizontal else self.inside
        u = np.asarray(until, float)
        j = np.searchsorted(self.t, u.ravel() - 1e-9)            # epochs before each until
        S = ins.shape[1]
        p, se = np.ones(j.shape), np.zeros(j.shape)
        if not self.t.size or not j.any():
            return p.reshape(u.shape), se.reshape(u.shape)
        cov = self._cov(horizontal)
        lo, hi = tabulated_quantile_bounds(eigenvalues(cov), LEVEL)
        arg = _running_argmax(lo + hi)
        star = arg[np.maximum(j, 1) - 1]
        P_star = norm_cdf(cov[star], self.tolerance)
        alive = np.logical_and.accumulate(ins, axis=0)
        for i, jj in enumerate(j):
            if jj == 0:
                continue
            c = np.count_nonzero(ins[star[i]] & ~alive[jj - 1])
            p[i] = max(P_star[i] - c / S, 0.0)   # the control variate can dip below 0
            d = (c + 1) / (S + 2)             # Laplace's rule: no count is not no error
            se[i] = np.sqrt(d * (1.0 - d) / S)
        return p.reshape(u.shape), se.reshape(u.shape)

    def _cov(self, horizontal: bool) -> FloatArray:
        if not horizontal:
            return self.cov
        cov = self.cov.copy()
        cov[:, 2, :] = 0.0
        cov[:, :, 2] = 0.0
        return cov

    def marginal(self, horizontal: bool = False) -> FloatArray:
        """The exact probability inside the tolerance at each epoch, from its covariance
        (:func:`~imunav.analysis.gaussnorm.norm_cdf`).

        Parameters
        ----------
        horizontal : bool

        Returns
        -------
        ndarray, shape (K,)
        """
        return norm_cdf(self._cov(horizontal), self.tolerance) if self.t.size else np.zeros(0)


def _running_argmax(x: FloatArray) -> np.ndarray:
    """Per position, the index of the largest value so far (the last of equal ones)."""
    m = np.maximum.accumulate(x)
    return np.maximum.accumulate(np.where(x == m, np.arange(x.size), 0))


def factor(P: FloatArray) -> FloatArray:
    """A square root ``L`` of symmetric positive semi-definite matrices, ``L Lᵀ = P`` (from
    their eigenvectors; negative rounding clipped to 0).

    Parameters
    ----------
    P : ndarray, shape (..., n, n)

    Returns
    -------
    ndarray, shape (..., n, n)
    """
    lam, V = np.linalg.eigh(0.5 * (P + np.swapaxes(P, -1, -2)))
    return V * np.sqrt(np.maximum(lam, 0.0))[..., None, :]


def _over(cov: FloatArray, tolerance: float, level: float) -> np.ndarray:
    """Where ``P(|x| ≤ tolerance) < level`` for ``x ~ N(0, cov)`` (tabulated quantile bounds
    first, the exact probability where they do not decide)."""
    lo, hi = tabulated_quantile_bounds(eigenvalues(cov), level)
    over = lo > tolerance
    open_ = ~over & (hi > tolerance)
    if open_.any():
        over[open_] = norm_cdf(cov[open_], tolerance) < level
    return over


@limit_blas
def walk(at: AlongTruth, epochs, P_start: FloatArray, tolerance: float, *,
         stops=None, samples: int = SAMPLES, seed: int = 0, imu_scale: float = 1.0,
         decide: bool = False, level: float = LEVEL) -> list[Window]:
    """Walk outages without GNSS from their last fix: the filter's covariance, the true one and
    ``samples`` paths of the true error, epoch by epoch — every outage in one loop, the ones
    under way at an epoch as one batch.

    From the epoch ``epochs[b]`` on (the last fix used, after its readings), outage ``b``
    uses every reading but GNSS: until the fix after it, an outage is the scenario "GNSS lost
    for good at its start" (the covariance is causal), so one walk answers every length.

    Parameters
    ----------
    at : AlongTruth
    epochs : sequence of int, length B
        Each outage's first epoch.
    P_start : ndarray, shape (B, 2, n, n)
        The filter's covariance and the true one at that epoch, after its readings (the
        weights of :meth:`AlongTruth.weights` with ``imu_scale``: ``propagate(...).final``).
    tolerance : float
        Position (m).
    stops : sequence of int, optional
        The last epoch walked per outage (default the record's last).
    samples : int
        Paths per outage.
    seed : int
        Of the paths' draws.
    imu_scale : float
        As :meth:`AlongTruth.weights`.
    decide : bool
        Stop an outage after the first epoch that no longer window can pass: its exact
        probability inside, or the fraction of its paths inside at every epoch so far, below
        ``level``.
    level : float

    Returns
    -------
    list of Window
        In the order of ``epochs``.
    """
    epochs = [int(e) for e in epochs]
    B = len(epochs)
    E = at.t.size - 1
    stops = [E] * B if stops is None else [min(E, int(s)) for s in stops]
    n, k = at.n, NAV
    ms = n - k
    S = int(samples)
    rng = np.random.Generator(np.random.SFC64(seed))
    wf, wt, _ = at.weights(imu_scale)
    W = np.concatenate([wf[None], wt[:1]])                       # (2, J): filter, truth
    jq = [(j, i.q) for j, i in enumerate(at.ingredients) if i.q is not None]
    ja = [(j, at.layout[i.name]) for j, i in enumerate(at.ingredients) if i.kind == "aid"]
    r_scale = {i.sensor: W[1, j] for j, i in enumerate(at.ingredients) if i.kind == "white"}
    r2 = tolerance * tolerance
    P_start = np.asarray(P_start, float)

    rec_t: list[list[float]] = [[] for _ in range(B)]
    rec_c: list[list[FloatArray]] = [[] for _ in range(B)]
    rec_in: list[list[np.ndarray]] = [[] for _ in range(B)]
    rec_h: list[list[np.ndarray]] = [[] for _ in range(B)]
    rec_a: list[list[float]] = [[] for _ in range(B)]
    stopped = ["stop"] * B
    # the outages under way: their covariances (filter, truth) and paths (state × path)
    act: list[int] = []
    P = np.zeros((0, 2, n, n))
    z = np.zeros((0, n, S), np.float32)

    def record(e, sel):
        """Record the outages ``act[sel]`` at epoch ``e``; the positions in ``act`` of those
        that stop here."""
        loc = at.local(P[sel, 1, :k, :k], e)
        cov = loc[:, DP, DP]
        att = norm_quantile(loc[:, PHI, PHI], 0.95)           # its p95 (rad)
        x = z[sel, DP] if at.output is None else at.output[e][DP, :k].astype(np.float32) @ \
            z[sel, :k]
        d2 = np.einsum("bis,bis->bs", x, x)
        h2 = np.einsum("bis,bis->bs", x[:, :2], x[:, :2])
        ins, ins_h = d2 <= r2, h2 <= r2
        te = float(at.t[e])
        failed = _over(cov, tolerance, level) if decide else np.zeros(len(sel), bool)
        done = []
        for ii, i in enumerate(sel):
            b = act[i]
            rec_t[b].append(te)
            rec_c[b].append(cov[ii])
            rec_in[b].append(ins[ii])
            rec_h[b].append(ins_h[ii])
            rec_a[b].append(float(att[ii]))
            if e >= stops[b]:
                stopped[b] = "end" if e >= E else "stop"
                done.append(i)
            elif failed[ii]:
                stopped[b] = "failed"
                done.append(i)
        return done

    def drop(done):
        nonlocal act, P, z
        if done:
            keep = np.ones(len(act), bool)
            keep[done] = False
            act = [b for b, kp in zip(act, keep, strict=True) if kp]
            P, z = P[keep], z[keep]

    order = sorted(range(B), key=lambda b: epochs[b])
    nxt = 0
    e = epochs[order[0]] if B else E
    # every step's blocks at once: the process noise of the filter and of the truth, the
    # transition and the truth's noise factor for the paths (float32: the paths' rounding is
    # far below their sampling error)
    e_lo = e
    steps = slice(e_lo, max([e_lo] + [s_ for s_ in stops]))
    Ee = steps.stop - steps.start
    Qnn, Qns, Qss = np.zeros((Ee, 2, k, k)), np.zeros((Ee, 2, k, ms)), np.zeros((Ee, 2, ms))
    for j, q in jq:
        w_ = W[None, :, j]
        Qnn += w_[..., None, None] * at.Q[q][0][steps][:, None]
        Qns += w_[..., None, None] * at.Q[q][1][steps][:, None]
        Qss += w_[..., None] * at.Q[q][2][steps][:, None]
    for j, sl in ja:
        Qss[:, :, sl.start - k:sl.stop - k] += W[None, :, j, None] * \
            at.Qaid[steps, None, sl.start - k:sl.stop - k]
    eye = np.eye(ms)
    Phi = np.zeros((Ee, n, n), np.float32)
    Phi[:, :k, :k], Phi[:, :k, k:] = at.F[steps], at.G[steps]
    Phi[:, np.arange(k, n), np.arange(k, n)] = at.D[steps]
    Bn = _noise_factor(Qnn[:, 1], Qns[:, 1], Qss[:, 1])
    while True:
        # outages starting at this epoch: their covariances, and paths drawn from N(0, P)
        new = []
        while nxt < B and epochs[order[nxt]] == e:
            new.append(order[nxt])
            nxt += 1
        if new:
            Pn = P_start[new]
            xi = rng.standard_normal((len(new), n, S), dtype=np.float32)
            m0 = len(act)
            act = act + new
            P = np.concatenate([P, Pn])
            z = np.concatenate([z, factor(Pn[:, 1]).astype(np.float32) @ xi])
            drop(record(e, list(range(m0, len(act)))))
        if not act:
            if nxt >= B:
                break
            e = epochs[order[nxt]]
            continue
        if e >= E:
            break
        # ---- predict to e + 1: the covariances, and the paths with one draw of the noise
        i = e - e_lo
        P = predict_blocks(P, at.F[e], at.G[e], at.D[e], Qnn[i], Qns[i],
                           Qss[i][..., :, None] * eye)
        z = Phi[i] @ z + Bn[i] @ rng.standard_normal((Bn.shape[-1], S), dtype=np.float32)
        e += 1
        # ---- the readings of the epoch, GNSS left out
        for r in at.readings[e]:
            if r.sensor == "gnss":
                continue
            Kg, _, HP = gain(P[:, 0], r.Hf, r.Rf)                     # (B, n, m)
            Rt = r.Rt * r_scale.get(r.sensor, 1.0)
            P = np.stack([joseph(P[:, 0], Kg, r.Hf, r.Rf, HP),
                          joseph(P[:, 1], Kg, r.Ht, Rt)], axis=1)
            v = factor(Rt).astype(np.float32) @ rng.standard_normal((Rt.shape[0], S),
                                                                   dtype=np.float32)
            y = r.Ht.astype(np.float32) @ z + v                          # (B, m, S)
            z -= Kg.astype(np.float32) @ y
        drop(record(e, list(range(len(act)))))
    return [Window(np.array(rec_t[b]), np.array(rec_c[b]).reshape(-1, 3, 3),
                   np.array(rec_in[b]).reshape(-1, S), np.array(rec_h[b]).reshape(-1, S),
                   float(tolerance), stopped[b], np.array(rec_a[b])) for b in range(B)]


def _noise_factor(Qnn: FloatArray, Qns: FloatArray, Qss: FloatArray) -> np.ndarray:
    """A factor ``L`` (float32) of the process noise ``[[Qnn, Qns], [Qnsᵀ, diag Qss]]`` of
    every step, ``L Lᵀ`` the noise: the states' own noise on the diagonal (the states driven
    in any step of the range), the navigation's given it (``Qns Qss⁻¹ w_s`` plus
    ``N(0, Qnn − Qns Qss⁻¹ Qnsᵀ)``); a state without noise has none in ``Qns`` either (a
    zero diagonal entry of a covariance empties its row).

    Parameters
    ----------
    Qnn, Qns, Qss : ndarray, shapes (T, k, k), (T, k, m), (T, m)

    Returns
    -------
    ndarray, shape (T, k + m, d + k)
        ``d`` the states driven somewhere.
    """
    T, k, ms = Qns.shape
    on = np.nonzero((Qss > 0).any(axis=0))[0]
    q = Qss[:, on]
    pos = q > 0
    C = np.where(pos[:, None, :], Qns[:, :, on] / np.where(pos, q, 1.0)[:, None, :], 0.0)
    Ln = factor(Qnn - (C * q[:, None, :]) @ np.swapaxes(C, -1, -2))
    L = np.zeros((T, k + ms, on.size + k), np.float32)
    sq = np.sqrt(q)
    L[:, k + on, np.arange(on.size)] = sq
    L[:, :k, :on.size] = C * sq[:, None, :]
    L[:, :k, on.size:] = Ln
    return L
