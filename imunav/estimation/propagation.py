"""Covariance propagation of the navigation errors, step by step along a trajectory.

Each :class:`~imunav.estimation.error_model.ErrorSource` is independent of the others, so its
covariance is propagated on its own (``P ← Φ P Φᵀ + Q_d`` per sub-step) and the total is the
sum. The trajectory is taken in pieces of :data:`CHUNK` steps (:func:`propagate_chunks`): the
discrete systems of one piece are built together (vectorised), the covariances carried from
piece to piece, and only the navigation block of each step is handed out — so the memory of the
propagation does not grow with the record (with a
:class:`~imunav.estimation.error_model.LazyTrajectory` not even the trajectory is held);
:func:`propagate` collects every step.

The propagation works on the blocks of each step's system
(:class:`~imunav.estimation.discretisation.StepBlocks`: the navigation transition, the input
``Γ`` of the sensor states, their diagonal decay, the blocks of ``Q_d``), which any error model
supplies — its ``discretise_blocks(piece, source)``, or its full ``discretise`` split by
:func:`~imunav.estimation.discretisation.blocks_from_full` — for any number of navigation and
sensor states. Two engines run them, with the same arithmetic per step up to rounding:

- :func:`step_blocks`: one step after the other (any navigation transition);
- :func:`scan_blocks`: for a model whose navigation transition is unipotent (``I + N``, ``N``
  strictly lower block triangular in the order φ, δv, δp: the flat frame, ``A³ = 0``), every
  block of ``P`` follows a recursion with a constant coefficient along the time axis — a
  cumulative sum, or a first-order recursion per decay (scaled cumulative sums) — so a whole
  piece is propagated in a few dozen vectorised operations instead of one Python step per
  sample (the 2-hour records of a covariance analysis).

Sources with the same number of states and sub-stepping are propagated together, batched.

May import: ``imunav.core``, ``imunav.estimation``.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from imunav.core.kernels import FloatArray
from imunav.estimation.discretisation import StepBlocks, blocks_from_full
from imunav.estimation.error_model import FLAT, NAV, ErrorSource, FlatErrorModel, Trajectory

__all__ = ["CHUNK", "BlockCovariance", "Recursion", "propagate", "propagate_chunks",
           "scan_blocks", "scan_nav", "scan_states", "step_blocks", "system_blocks"]

#: Steps of the trajectory whose discrete systems are built at once.
CHUNK = 256


@dataclass
class BlockCovariance:
    """The covariance of ``b`` independent systems ``[e, x]``, in blocks.

    Attributes
    ----------
    nn : ndarray, shape (b, n, n)
        Of the navigation errors.
    nx : ndarray, shape (b, n, k)
        Between the navigation errors and the sensor states.
    xx : ndarray, shape (b, k, k)
        Of the sensor states.
    carry : dict
        The :class:`Recursion` states :func:`scan_blocks` carries from piece to piece.
    """

    nn: FloatArray
    nx: FloatArray
    xx: FloatArray
    carry: dict = field(default_factory=dict, repr=False)

    @classmethod
    def of(cls, P0: FloatArray, n: int = NAV) -> BlockCovariance:
        """Split full covariances ``P0`` (b, n + k, n + k).

        Parameters
        ----------
        P0 : ndarray, shape (b, n + k, n + k)
        n : int
            The navigation errors: the first ``n`` states.

        Returns
        -------
        BlockCovariance
        """
        P0 = np.asarray(P0, float)
        return cls(P0[:, :n, :n].copy(), P0[:, :n, n:].copy(), P0[:, n:, n:].copy())


def system_blocks(model, piece: Trajectory, source: ErrorSource) -> StepBlocks:
    """The blocks of ``source``'s discrete system over each (sub-)step of ``piece``.

    Parameters
    ----------
    model : error model
        Its ``discretise_blocks(piece, source)`` if it has one, else its full
        ``discretise(piece, source)`` split by
        :func:`~imunav.estimation.discretisation.blocks_from_full`.
    piece : Trajectory
    source : ErrorSource

    Returns
    -------
    StepBlocks
    """
    if hasattr(model, "discretise_blocks"):
        return model.discretise_blocks(piece, source)
    Phi, Qd = model.discretise(piece, source)
    return blocks_from_full(Phi, Qd, NAV)


def _stack(blocks: list[StepBlocks]) -> tuple[FloatArray, ...]:
    """Stack the systems of ``b`` sources: nav (T, n, n) (shared), gamma (T, b, n, k),
    decay (b, k), Qnn (T, b, n, n), Qnx (T, b, n, k), Qxx (b, k, k)."""
    return (blocks[0].nav, np.stack([s.gamma for s in blocks], 1),
            np.stack([s.decay for s in blocks]), np.stack([s.Qnn for s in blocks], 1),
            np.stack([s.Qnx for s in blocks], 1), np.stack([s.Qxx for s in blocks]))


def step_blocks(P: BlockCovariance, blocks: list[StepBlocks], sub: int = 1) -> FloatArray:
    """Propagate ``P`` over every step of ``blocks`` (one system per source), one step at a
    time: ``P ← Φ P Φᵀ + Q_d`` written in blocks, any navigation transition.

    Parameters
    ----------
    P : BlockCovariance
        Updated in place to the covariance at the last step's end.
    blocks : list of StepBlocks
        One per system of ``P`` (the same ``nav`` for all).
    sub : int
        Identical sub-steps per step (each step's system applied ``sub`` times).

    Returns
    -------
    ndarray, shape (T, b, n, n)
        The navigation-error covariance at the end of each step.
    """
    nav, gamma, decay, Qnn, Qnx, Qxx = _stack(blocks)
    T = nav.shape[0]
    navT, gammaT = np.swapaxes(nav, -1, -2), np.swapaxes(gamma, -1, -2)
    out = np.empty((T,) + P.nn.shape)
    nn, nx, xx = P.nn, P.nx, P.xx
    E = decay[:, None, :]
    for i in range(T):
        for _ in range(sub):
            Y = nav[i] @ nn + gamma[i] @ np.swapaxes(nx, -1, -2)
            X = nav[i] @ nx + gamma[i] @ xx
            nn = Y @ navT[i] + X @ gammaT[i] + Qnn[i]
            nx = X * E + Qnx[i]
            xx = xx * (decay[:, :, None] * decay[:, None, :]) + Qxx
        out[i] = nn
    P.nn, P.nx, P.xx = nn, nx, xx
    return out


#: Largest ``|ln λ|·L`` of a segment of :class:`Recursion` (its scaled sums stay below e^30).
SPAN = 30.0


class Recursion:
    """``y_{i+1} = λ y_i + w_i`` along the time axis, ``λ ≥ 0`` constant per element, carried
    from piece to piece (:meth:`run`).

    In segments of ``L`` steps with ``|ln λ|·L ≤`` :data:`SPAN`, counted from the first step
    (so the result does not depend on how the steps are cut into pieces):
    ``y_{s+m} = λᵐ (y_s + Σ_{j<m} w_{s+j}/λ^{j+1})``, one cumulative sum per segment; a plain
    cumulative sum where every ``λ`` is 1; ``λ = 0`` (a state drawn afresh) is ``y_{i+1} =
    w_i``. Agrees with the loop to rounding.

    Parameters
    ----------
    lam : ndarray
        The coefficients, shape of ``y0`` (or broadcast to it).
    y0 : ndarray
        The value at the first step.
    """

    def __init__(self, lam: FloatArray, y0: FloatArray):
        y0 = np.array(y0, float)
        lam = np.ascontiguousarray(np.broadcast_to(np.asarray(lam, float), y0.shape))
        self.zero = lam == 0
        self.L, self.powers, self.inverse = _powers_table(lam.tobytes(), lam.shape)
        self.y, self.ys, self.z, self.m = y0, y0.copy(), np.zeros_like(y0), 0

    def run(self, w: FloatArray) -> FloatArray:
        """The next ``T`` steps.

        Parameters
        ----------
        w : ndarray, shape (T, …)
            The inputs ``w_i``.

        Returns
        -------
        ndarray, shape (T + 1, …)
            ``y`` at the start (the last value of the previous piece) and after each step.
        """
        T = w.shape[0]
        out = np.empty((T + 1,) + self.y.shape)
        out[0] = self.y
        if self.L is None:
            out[1:] = w
            np.cumsum(out, axis=0, out=out)
        else:
            i = 0
            buf = np.empty((min(self.L, T) + 1,) + self.y.shape)
            while i < T:
                if self.m == self.L:                         # a new segment
                    self.ys, self.z, self.m = out[i].copy(), np.zeros_like(self.z), 0
                n = min(self.L - self.m, T - i)
                b = buf[:n + 1]
                b[0] = self.z
                np.multiply(w[i:i + n], self.inverse[self.m:self.m + n], out=b[1:])
                np.cumsum(b, axis=0, out=b)
                self.z = b[n].copy()
                np.add(b[1:], self.ys, out=b[1:])
                np.multiply(b[1:], self.powers[self.m:self.m + n], out=out[i + 1:i + n + 1])
                self.m, i = self.m + n, i + n
        if np.any(self.zero):
            out[1:, self.zero] = w[:, self.zero]
        self.y = out[-1]
        return out


#: Longest segment of a :class:`Recursion` (its tables of powers hold this many steps).
LMAX = 1024


@lru_cache(maxsize=32)
def _powers_table(lam: bytes, shape: tuple):
    """``(L, λᵐ, λ^{−m})`` for m = 1 … L of :class:`Recursion` (``exp(m ln λ)``: not
    ``λ ** m``, which numpy computes as a square for a lone 2); ``L`` None where every ``λ`` is
    1 or 0."""
    lam = np.frombuffer(lam).reshape(shape)
    safe = np.where(lam == 0, 1.0, lam)
    moving = safe != 1
    if not np.any(moving):
        return None, None, None
    L = max(1, min(LMAX, int(SPAN / np.abs(np.log(safe[moving])).max())))
    m = np.arange(1, L + 1).reshape((L,) + (1,) * len(shape))
    powers = np.exp(m * np.log(safe))
    return L, powers, 1.0 / powers


def _cumulative(inc: FloatArray, y0: FloatArray) -> FloatArray:
    """``y_{i+1} = y_i + inc_i``: ``y_0 … y_T``, summed in the loop's order."""
    return np.cumsum(np.concatenate([y0[None], inc]), axis=0)


def _tr(x: FloatArray) -> FloatArray:
    """A contiguous transpose of the last two axes (numpy's matmul is slow on strided views)."""
    return np.ascontiguousarray(np.swapaxes(x, -1, -2))


def _blk(x: FloatArray, r: slice, q: slice) -> FloatArray:
    return np.ascontiguousarray(x[..., r, q])


F_, V_, P_ = slice(0, 3), slice(3, 6), slice(6, 9)


class _Scalar:
    """``h·I`` as a block of a transition: ``@`` multiplies by ``h`` (no matrix product)."""

    __array_ufunc__ = None                   # numpy arrays defer ``x @ self`` to __rmatmul__

    def __init__(self, h: float):
        self.h = h

    def __matmul__(self, x):
        return self.h * x

    def __rmatmul__(self, x):
        return x * self.h


def _nav_parts(nav: FloatArray):
    """``a, c, d`` of a unipotent ``nav = I + [[0, 0, 0], [a, 0, 0], [c, d, 0]]`` (T, 1, 3, 3),
    and their transposes; ``d`` as a scalar where it is ``h·I`` at every step (the flat frame:
    ``δp ← h δv``)."""
    a, c, d = (_blk(nav, r, q)[:, None] for r, q in ((V_, F_), (P_, F_), (P_, V_)))
    if d.size and np.all(d == d[:1, :, :1, :1] * np.eye(3)):
        d = dT = _Scalar(float(d[0, 0, 0, 0]))
    else:
        dT = _tr(d)
    return a, c, d, _tr(a), _tr(c), dT


def scan_states(P: BlockCovariance, blocks: list[StepBlocks], sub: int = 1) -> FloatArray:
    """The sensor-state part of :func:`scan_blocks`: carry ``P.nx`` and ``P.xx`` over the
    steps of ``blocks`` and return what drives the navigation block,
    ``Z = nav Pnx Γᵀ + Γ Pxn navᵀ + Γ Pxx Γᵀ + Qnn`` at each (sub-)step.

    Parameters
    ----------
    P : BlockCovariance
        Its ``nx``, ``xx`` (and the recursions in ``carry``) updated in place.
    blocks : list of StepBlocks
    sub : int

    Returns
    -------
    ndarray, shape (T·sub, b, n, n)
    """
    nav, gamma, decay, Qnn, Qnx, Qxx = _stack(blocks)
    if sub > 1:
        nav, gamma, Qnn, Qnx = (np.repeat(x, sub, axis=0) for x in (nav, gamma, Qnn, Qnx))
    T, b, k = nav.shape[0], P.nn.shape[0], decay.shape[-1]
    if not k:
        return Qnn
    f, v, p = F_, V_, P_
    a, c, d, *_ = _nav_parts(nav)
    rec = P.carry
    # the sensor states: x ← E x E + Qxx, diagonal if they start and are driven so
    diag = not (np.any(P.xx - np.einsum("bii->bi", P.xx)[:, :, None] * np.eye(k))
                or np.any(Qxx - np.einsum("bii->bi", Qxx)[:, :, None] * np.eye(k)))
    if diag:
        if "xx" not in rec:
            rec["xx"] = Recursion(decay * decay, np.einsum("bii->bi", P.xx))
        xs = rec["xx"].run(np.broadcast_to(np.einsum("bii->bi", Qxx), (T, b, k)))
        GP = gamma * xs[:-1, :, None, :]                                     # Γ Pxx
        P.xx = xs[-1][:, :, None] * np.eye(k)
    else:
        if "xx" not in rec:
            rec["xx"] = Recursion(decay[:, :, None] * decay[:, None, :], P.xx)
        xs = rec["xx"].run(np.broadcast_to(Qxx, (T, b, k, k)))
        GP = gamma @ xs[:-1]
        P.xx = xs[-1]
    E = decay[:, None, :]
    if "f" not in rec:
        for key, r in (("f", f), ("v", v), ("p", p)):
            rec[key] = Recursion(np.broadcast_to(E, (b, 3, k)), P.nx[:, r])
    # cross-covariances, row block by row block: C ← (C + known) E + Qnx
    Cf = rec["f"].run(GP[:, :, f] * E + Qnx[:, :, f])
    Cv = rec["v"].run((a @ Cf[:-1] + GP[:, :, v]) * E + Qnx[:, :, v])
    Cp = rec["p"].run((c @ Cf[:-1] + d @ Cv[:-1] + GP[:, :, p]) * E + Qnx[:, :, p])
    P.nx = np.concatenate([Cf[-1], Cv[-1], Cp[-1]], axis=1)
    gT = _tr(gamma)
    Uf, Uv, Up = Cf[:-1] @ gT, Cv[:-1] @ gT, Cp[:-1] @ gT                   # Pnx Γᵀ, by rows
    NU = np.concatenate([Uf, Uv + a @ Uf, Up + c @ Uf + d @ Uv], axis=2)     # nav · Pnx Γᵀ
    return NU + np.swapaxes(NU, -1, -2) + GP @ gT + Qnn


def scan_nav(nn: FloatArray, Z: FloatArray, nav: FloatArray, sub: int = 1) -> FloatArray:
    """The navigation part of :func:`scan_blocks`: ``Pnn ← nav Pnn navᵀ + Z`` for a unipotent
    ``nav``, block by block (φφ, δvφ, δvδv, δpφ, δpδv, δpδp), each a cumulative sum.

    Parameters
    ----------
    nn : ndarray, shape (b, n, n)
        At the first step's start.
    Z : ndarray, shape (T·sub, b, n, n)
        From :func:`scan_states` (or ``Qnn`` for sources without states).
    nav : ndarray, shape (T, n, n)
        The navigation transition of each step.
    sub : int

    Returns
    -------
    ndarray, shape (T·sub + 1, b, n, n)
        ``Pnn`` at the start and after every sub-step.
    """
    if sub > 1:
        nav = np.repeat(nav, sub, axis=0)
    f, v, p = F_, V_, P_
    a, c, d, aT, cT, dT = _nav_parts(nav)
    ff = _cumulative(Z[:, :, f, f], nn[:, f, f])
    F0 = ff[:-1]
    vf = _cumulative(a @ F0 + Z[:, :, v, f], nn[:, v, f])
    V0 = vf[:-1]
    V0T = _tr(V0)
    vv = _cumulative(a @ V0T + V0 @ aT + (a @ F0) @ aT + Z[:, :, v, v], nn[:, v, v])
    low = c @ F0 + d @ V0                                                    # N_p P_·φ
    pf = _cumulative(low + Z[:, :, p, f], nn[:, p, f])
    W0, P0 = vv[:-1], pf[:-1]
    mid = c @ V0T + d @ W0                                                   # N_p P_·δv
    pv = _cumulative(mid + P0 @ aT + low @ aT + Z[:, :, p, v], nn[:, p, v])
    Q0 = pv[:-1]
    pp = _cumulative(c @ _tr(P0) + d @ _tr(Q0) + P0 @ cT + Q0 @ dT + low @ cT + mid @ dT
                     + Z[:, :, p, p], nn[:, p, p])
    out = np.empty((ff.shape[0],) + nn.shape)
    out[:, :, f, f], out[:, :, v, v], out[:, :, p, p] = ff, vv, pp
    out[:, :, v, f], out[:, :, p, f], out[:, :, p, v] = vf, pf, pv
    out[:, :, f, v], out[:, :, f, p], out[:, :, v, p] = (np.swapaxes(x, -1, -2)
                                                         for x in (vf, pf, pv))
    return out


def scan_blocks(P: BlockCovariance, blocks: list[StepBlocks], sub: int = 1) -> FloatArray:
    """:func:`step_blocks` for a unipotent navigation transition, along the time axis.

    With ``nav = I + N``, ``N = [[0, 0, 0], [a, 0, 0], [c, d, 0]]`` in the blocks (φ, δv, δp)
    (flat frame: ``a = [f_n×] h``, ``c = [f_n×] h²/2``, ``d = h I``) and the sensor states
    decaying each on its own (``E = diag(decay)``), the blocks of ``P`` follow in order
    (:func:`scan_states`): the sensor states (``x ← E x E + Q``), their cross-covariances row
    block by row block (``C ← (C + known) E + Q``: a :class:`Recursion` with the decays), then
    (:func:`scan_nav`) the navigation blocks φφ, δvφ, δvδv, δpφ, δpδv, δpδp, each its previous
    value plus terms of blocks already known at every step (a cumulative sum).

    Parameters
    ----------
    P : BlockCovariance
        Updated in place to the covariance at the last step's end.
    blocks : list of StepBlocks
        One per system of ``P`` (the same ``nav`` for all, unipotent as above).
    sub : int
        Identical sub-steps per step.

    Returns
    -------
    ndarray, shape (T, b, n, n)
        The navigation-error covariance at the end of each step.
    """
    out = scan_nav(P.nn, scan_states(P, blocks, sub), blocks[0].nav, sub)
    P.nn = out[-1].copy()
    return out[sub::sub]


def propagate_chunks(sources: list[ErrorSource], traj, model: FlatErrorModel = FLAT,
                     chunk: int = CHUNK, local: bool = False
                     ) -> Iterator[tuple[int, int, list[FloatArray]]]:
    """Propagate every source along ``traj`` a piece at a time.

    Parameters
    ----------
    sources : list of ErrorSource
    traj : Trajectory or LazyTrajectory
        Anything with ``steps`` and ``piece(lo, hi)``.
    model : error model
        Its ``discretise_blocks`` (or ``discretise``); a model with ``unipotent = True`` is
        propagated along the time axis (:func:`scan_blocks`), any other step by step
        (:func:`step_blocks`).
    chunk : int
        Steps per piece.
    local : bool
        Hand out the covariances of the errors a user reads (``model.local``: the local NED
        errors on the Earth; the same on the flat frame) instead of the error state's.

    Yields
    ------
    lo, hi : int
        The piece: steps ``lo … hi − 1``.
    covariances : list of ndarray, shape (hi − lo, 9, 9)
        Per source (in the order given), the navigation-error covariance at the end of each
        step of the piece (times ``t_{lo+1} … t_hi``).
    """
    N = traj.steps
    scan = getattr(model, "unipotent", False)
    groups: dict[tuple[int, int], list[int]] = {}
    for j, s in enumerate(sources):
        groups.setdefault((s.block_size, s.sub), []).append(j)
    P = {key: BlockCovariance.of(np.stack([sources[j].initial_covariance() for j in members]))
         for key, members in groups.items()}
    subs = sorted({key[1] for key in groups})
    for lo in range(0, N, chunk):
        hi = min(N, lo + chunk)
        piece = traj.piece(lo, hi)
        out: list[FloatArray | None] = [None] * len(sources)
        for sub in subs:
            keys = [key for key in groups if key[1] == sub]
            blocks = {key: [system_blocks(model, piece, sources[j]) for j in groups[key]]
                      for key in keys}
            if scan:        # one pass of the navigation blocks for every source of this sub
                Z = np.concatenate([scan_states(P[key], blocks[key], sub) for key in keys], 1)
                nn = np.concatenate([P[key].nn for key in keys])
                hist = scan_nav(nn, Z, blocks[keys[0]][0].nav, sub)
                ends, hist = hist[-1], hist[sub::sub]
            else:
                hist = np.concatenate([step_blocks(P[key], blocks[key], sub) for key in keys], 1)
            at = 0
            for key in keys:
                n = len(groups[key])
                if scan:
                    P[key].nn = ends[at:at + n].copy()
                for c, j in enumerate(groups[key]):
                    out[j] = model.local(piece, hist[:, at + c], 1) if local else hist[:, at + c]
                at += n
        yield lo, hi, out


def propagate(sources: list[ErrorSource], traj: Trajectory, model: FlatErrorModel = FLAT,
              chunk: int = CHUNK) -> list[FloatArray]:
    """The navigation-error covariance of each source at every output time.

    Parameters
    ----------
    sources : list of ErrorSource
    traj : Trajectory
    model : FlatErrorModel
    chunk : int
        Steps per piece (:func:`propagate_chunks`); the result does not depend on it.

    Returns
    -------
    list of ndarray, shape (N + 1, 9, 9)
        Per source, at ``t_0 … t_N`` (the first is the initial covariance of the navigation
        errors: zero, or the levelled attitude's of
        :class:`~imunav.estimation.alignment.LevelledSource`).
    """
    N = traj.steps
    hist = [np.empty((N + 1, NAV, NAV)) for _ in sources]
    for h, s in zip(hist, sources, strict=True):
        h[0] = s.initial_covariance()[:NAV, :NAV]        # zero, unless levelled
    for lo, hi, covs in propagate_chunks(sources, traj, model, chunk):
        for h, c in zip(hist, covs, strict=True):
            h[lo + 1:hi + 1] = c
    return hist
