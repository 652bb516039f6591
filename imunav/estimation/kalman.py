"""The Kalman core, written once: the discrete system of a step in blocks, its prediction, and the
measurement update in Joseph form with its χ² gate — for one filter or a batch of them.

These know nothing of navigation: the error model supplies the discrete system
(:mod:`~imunav.estimation.error_model`, :class:`~imunav.estimation.system.AidedSystem`), a
measurement its ``(z, H, R)``. Every filter, smoother and covariance analysis of imunav goes
through these functions:

- :class:`StepBlocks` and :func:`predict_blocks` (:func:`predict_split` on a covariance kept in
  its blocks): ``P ← Φ P Φᵀ + Q_d`` for a state ``[e, x]`` of ``n`` "navigation" errors and
  ``k`` states that decay on their own, ``Φ = [[nav, Γ], [0, diag(decay)]]`` — ``n/(n+k)`` of
  the operations of the full product; :func:`predict` is the textbook step (``k = 0``);
- :func:`gain`, :func:`joseph`, :func:`update_batch` (and :func:`update`, a batch of one): the
  gain ``K = P Hᵀ S⁻¹``, ``S = H P Hᵀ + R``, and Joseph's form
  ``P⁺ = (I − K H) P (I − K H)ᵀ + K R Kᵀ``, exact for any gain (a suboptimal one too: the
  covariance analysis applies the filter's gain to the true error covariance). It is evaluated
  as ``P − K H P − (K H P)ᵀ + K S Kᵀ`` — the same sum, ``m n²`` operations instead of ``n³`` —
  and symmetrised; for the optimal gain it equals ``P − K S Kᵀ``;
- :func:`gate_quantile`: the χ² gate (a reading whose normalised innovation squared
  ``νᵀ S⁻¹ ν`` exceeds the quantile of probability ``gate`` for its ``m`` components is
  rejected), the one quantile every caller uses.

Every function broadcasts over leading axes: a batch of ``R`` filters is ``P`` (R, n, n).

May import: ``imunav.core``.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import numpy.typing as npt
from scipy.stats import chi2

from imunav.core.kernels import FloatArray
from imunav.core.validation import ImunavError, as_float_array

__all__ = ["BatchUpdate", "StepBlocks", "Update", "gain", "gate_quantile", "joseph", "predict",
           "predict_blocks", "predict_split", "update", "update_batch"]


# ----------------------------------------------------------------------------- prediction

@dataclass
class StepBlocks:
    """The discrete system of ``T`` steps, in blocks.

    The state is ``[e, x]``: ``n`` errors ``e`` whose transition may be anything and ``k``
    states ``x`` that evolve on their own (each decays by its factor, driven by its own white
    noise), so that over one step::

        Φ = [[nav, gamma], [0, diag(decay)]],     Q_d = [[Qnn, Qnx], [Qnxᵀ, Qxx]].

    Attributes
    ----------
    nav : ndarray, shape (T, n, n)
        The errors' own transition.
    gamma : ndarray, shape (T, n, k)
        How the states at the step's start drive the errors at its end.
    decay : ndarray, shape (k,) or (T, k)
        The states' transition (diagonal; 0 for a state drawn afresh every step).
    Qnn, Qnx : ndarray, shapes (T, n, n), (T, n, k)
        Process-noise blocks.
    Qxx : ndarray, shape (k, k) or (T, k, k)
        The states' process noise.
    """

    nav: FloatArray
    gamma: FloatArray
    decay: FloatArray
    Qnn: FloatArray
    Qnx: FloatArray
    Qxx: FloatArray

    @property
    def steps(self) -> int:
        """Number of steps ``T``."""
        return int(self.nav.shape[0])

    def step(self, i) -> tuple[FloatArray, ...]:
        """The blocks of step(s) ``i`` (an index or a slice), as :func:`predict_blocks` takes
        them.

        Parameters
        ----------
        i : int or slice

        Returns
        -------
        tuple of ndarray
            ``nav, gamma, decay, Qnn, Qnx, Qxx``.
        """
        d = self.decay if self.decay.ndim == 1 else self.decay[i]
        q = self.Qxx if self.Qxx.ndim == 2 else self.Qxx[i]
        if isinstance(i, slice) and self.decay.ndim == 1:
            d = np.broadcast_to(d, (len(range(*i.indices(self.steps))),) + d.shape)
        return self.nav[i], self.gamma[i], d, self.Qnn[i], self.Qnx[i], q

    def full(self) -> tuple[FloatArray, FloatArray]:
        """The whole ``(Φ, Q_d)``, shapes (T, n + k, n + k) (what :func:`blocks_from_full
        <imunav.estimation.discretisation.blocks_from_full>` splits).

        Returns
        -------
        Phi, Qd : ndarray
        """
        T, n, k = self.steps, self.nav.shape[-1], self.gamma.shape[-1]
        Phi = np.zeros((T, n + k, n + k))
        Phi[:, :n, :n] = self.nav
        Phi[:, :n, n:] = self.gamma
        Phi[:, range(n, n + k), range(n, n + k)] = self.decay
        Qd = np.empty_like(Phi)
        Qd[:, :n, :n] = self.Qnn
        Qd[:, :n, n:] = self.Qnx
        Qd[:, n:, :n] = np.swapaxes(self.Qnx, -1, -2)
        Qd[:, n:, n:] = self.Qxx
        return Phi, Qd


def predict_split(nn: FloatArray, nx: FloatArray, xx: FloatArray, nav: FloatArray,
                  gamma: FloatArray, decay: FloatArray, Qnn: FloatArray, Qnx: FloatArray,
                  Qxx: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """``Φ P Φᵀ + Q_d`` on a covariance kept in its blocks, ``Φ`` as in :class:`StepBlocks`.

    Parameters
    ----------
    nn, nx, xx : ndarray, shapes (..., n, n), (..., n, k), (..., k, k)
        The blocks of ``P``.
    nav, gamma, decay, Qnn, Qnx, Qxx : ndarray
        One step's blocks (broadcast against ``P``'s leading axes).

    Returns
    -------
    nn, nx, xx : ndarray
        The predicted blocks (``nn`` symmetrised).
    """
    Y = nav @ nn + gamma @ np.swapaxes(nx, -1, -2)
    X = nav @ nx + gamma @ xx
    out_nn = Y @ np.swapaxes(nav, -1, -2) + X @ np.swapaxes(gamma, -1, -2)
    out_nn = 0.5 * (out_nn + np.swapaxes(out_nn, -1, -2)) + Qnn
    out_nx = X * decay[..., None, :] + Qnx
    out_xx = xx * (decay[..., :, None] * decay[..., None, :]) + Qxx
    return out_nn, out_nx, out_xx


def predict_blocks(P: FloatArray, nav: FloatArray, gamma: FloatArray, decay: FloatArray,
                   Qnn: FloatArray, Qnx: FloatArray, Qxx: FloatArray) -> FloatArray:
    """``Φ P Φᵀ + Q_d`` for a whole covariance ``P`` (…, n + k, n + k), ``Φ`` as in
    :class:`StepBlocks` — one filter's step or a batch's (the blocks broadcast per row).

    The same numbers as :func:`predict_split` of ``P``'s blocks, each block written straight
    into the result (no second pass over the large ``k × k`` block of a batch).

    Parameters
    ----------
    P : ndarray, shape (..., n + k, n + k)
    nav, gamma, decay, Qnn, Qnx, Qxx : ndarray
        One step's blocks (:meth:`StepBlocks.step`).

    Returns
    -------
    ndarray, shape of ``P``
        Symmetric when ``P`` is (the navigation block symmetrised).
    """
    n = nav.shape[-1]
    nn, nx, xx = P[..., :n, :n], P[..., :n, n:], P[..., n:, n:]
    lead = np.broadcast_shapes(P.shape[:-2], nav.shape[:-2], gamma.shape[:-2], Qnn.shape[:-2],
                               Qnx.shape[:-2], np.shape(decay)[:-1], np.shape(Qxx)[:-2])
    out = np.empty(lead + P.shape[-2:])
    Y = nav @ nn + gamma @ np.swapaxes(nx, -1, -2)
    X = nav @ nx + gamma @ xx
    o = Y @ np.swapaxes(nav, -1, -2) + X @ np.swapaxes(gamma, -1, -2)
    out[..., :n, :n] = 0.5 * (o + np.swapaxes(o, -1, -2)) + Qnn
    o_nx = out[..., :n, n:]
    np.multiply(X, decay[..., None, :], out=o_nx)
    o_nx += Qnx
    out[..., n:, :n] = np.swapaxes(o_nx, -1, -2)
    o_xx = out[..., n:, n:]
    np.multiply(xx, decay[..., :, None] * decay[..., None, :], out=o_xx)
    o_xx += Qxx
    return out


def predict(x: npt.ArrayLike, P: npt.ArrayLike, Phi: npt.ArrayLike, Qd: npt.ArrayLike
            ) -> tuple[FloatArray, FloatArray]:
    """One prediction step: ``x ← Φ x``, ``P ← Φ P Φᵀ + Q_d`` (:func:`predict_blocks` with no
    states of their own).

    Parameters
    ----------
    x : array_like, shape (n,)
    P : array_like, shape (n, n)
    Phi : array_like, shape (n, n)
    Qd : array_like, shape (n, n)

    Returns
    -------
    x, P : ndarray
        The predicted state and covariance (``P`` symmetrised).

    Examples
    --------
    >>> import numpy as np
    >>> x, P = predict([1.0, 0.5], np.eye(2), [[1.0, 0.1], [0.0, 1.0]], 0.01 * np.eye(2))
    >>> x
    array([1.05, 0.5 ])
    """
    x = np.asarray(x, dtype=float)
    Phi = np.asarray(Phi, dtype=float)
    n = Phi.shape[-1]
    P = predict_blocks(np.asarray(P, dtype=float), Phi, np.zeros((n, 0)), np.zeros(0),
                       np.asarray(Qd, dtype=float), np.zeros((n, 0)), np.zeros((0, 0)))
    return Phi @ x, P


# ----------------------------------------------------------------------------- the update

@lru_cache(maxsize=256)
def gate_quantile(p: float, dof: int) -> float:
    """The χ² quantile of a gate of probability ``p`` for ``dof`` components (remembered: a
    filter gates thousands of readings alike).

    Parameters
    ----------
    p : float
        In (0, 1).
    dof : int

    Returns
    -------
    float
    """
    return float(chi2.ppf(p, dof))


def gain(P: FloatArray, H: FloatArray, R: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The gain ``K = P Hᵀ S⁻¹`` and ``S = H P Hᵀ + R``.

    Parameters
    ----------
    P : ndarray, shape (..., n, n)
    H : ndarray, shape (..., m, n)
    R : ndarray, shape (..., m, m)

    Returns
    -------
    K : ndarray, shape (..., n, m)
    S : ndarray, shape (..., m, m)
        Symmetrised.
    HP : ndarray, shape (..., m, n)
        ``H P`` (for :func:`joseph`).

    Raises
    ------
    ImunavError
        If ``S`` is not positive definite (check R).
    """
    HP = H @ P
    S = HP @ np.swapaxes(H, -1, -2) + R
    S = 0.5 * (S + np.swapaxes(S, -1, -2))
    try:
        L = np.linalg.cholesky(S)
    except np.linalg.LinAlgError:
        raise ImunavError("the innovation covariance H P Hᵀ + R is not positive definite "
                          "(check the measurement noise R and the covariance P: an initial or "
                          "inflated σ too large, or too small, for double precision)") from None
    Y = np.linalg.solve(L, HP)                                 # L⁻¹ H P
    K = np.swapaxes(np.linalg.solve(np.swapaxes(L, -1, -2), Y), -1, -2)   # (S⁻¹ H P)ᵀ
    return K, S, HP


def joseph(P: FloatArray, K: FloatArray, H: FloatArray, R: FloatArray,
           HP: FloatArray | None = None) -> FloatArray:
    """Joseph's form ``(I − K H) P (I − K H)ᵀ + K R Kᵀ`` for any gain ``K``.

    Parameters
    ----------
    P : ndarray, shape (..., n, n)
    K : ndarray, shape (..., n, m)
    H : ndarray, shape (..., m, n)
    R : ndarray, shape (..., m, m)
    HP : ndarray, shape (..., m, n), optional
        ``H P``, if known.

    Returns
    -------
    ndarray, shape (..., n, n)
        Symmetric.
    """
    HP = H @ P if HP is None else HP
    S = HP @ np.swapaxes(H, -1, -2) + R
    KHP = K @ HP
    out = P - KHP - np.swapaxes(KHP, -1, -2) + K @ S @ np.swapaxes(K, -1, -2)
    return 0.5 * (out + np.swapaxes(out, -1, -2))


@dataclass
class BatchUpdate:
    """The result of one measurement update of ``R`` filters (leading axes ``(R,)``).

    Attributes
    ----------
    x, P : ndarray, shapes (R, n), (R, n, n)
        The updated states and covariances (unchanged where the reading was rejected).
    innovation : ndarray, shape (R, m)
        ``z − H x`` (before the update).
    S : ndarray, shape (R, m, m)
        Its covariance ``H P Hᵀ + R``.
    nis : ndarray, shape (R,)
        The normalised innovation squared ``νᵀ S⁻¹ ν`` (χ² with m degrees of freedom when the
        filter is consistent).
    accepted : ndarray of bool, shape (R,)
        False where the gate rejected the reading.
    """

    x: FloatArray
    P: FloatArray
    innovation: FloatArray
    S: FloatArray
    nis: FloatArray
    accepted: np.ndarray


def _cholesky(S: FloatArray) -> tuple[FloatArray, np.ndarray]:
    """The lower Cholesky factor of each ``S`` (…, m, m) and where it exists (…,): closed
    forms for ``m ≤ 3`` (the aids' readings: one batched LAPACK call each costs more than the
    arithmetic), LAPACK above — where a factor does not exist its rows are NaN."""
    m = S.shape[-1]
    if m > 3:
        good = np.isfinite(S).all(axis=(-2, -1))
        good[good] = np.all(np.linalg.eigvalsh(S[good]) > 0, axis=-1)
        L = np.full(S.shape, np.nan)
        if good.any():
            L[good] = np.linalg.cholesky(S[good])
        return L, good
    L = np.zeros(S.shape)
    with np.errstate(invalid="ignore", divide="ignore"):
        for j in range(m):
            d = S[..., j, j] - np.einsum("...k,...k->...", L[..., j, :j], L[..., j, :j])
            L[..., j, j] = np.sqrt(d)
            for i in range(j + 1, m):
                L[..., i, j] = (S[..., i, j] - np.einsum("...k,...k->...", L[..., i, :j],
                                                         L[..., j, :j])) / L[..., j, j]
    diag = np.diagonal(L, axis1=-2, axis2=-1)
    return L, np.all(diag > 0, axis=-1) & np.isfinite(L).all(axis=(-2, -1))


def _forward(L: FloatArray, B: FloatArray) -> FloatArray:
    """``L⁻¹ B`` for lower-triangular ``L`` (…, m, m) and ``B`` (…, m, k)."""
    m = L.shape[-1]
    if m > 3:
        return np.linalg.solve(L, B)
    Y = np.empty(np.broadcast_shapes(L.shape[:-2], B.shape[:-2]) + B.shape[-2:])
    for i in range(m):
        r = B[..., i, :]
        for k in range(i):
            r = r - L[..., i, k, None] * Y[..., k, :]
        Y[..., i, :] = r / L[..., i, i, None]
    return Y


def _backward(L: FloatArray, Y: FloatArray) -> FloatArray:
    """``L⁻ᵀ Y`` for lower-triangular ``L`` (…, m, m) and ``Y`` (…, m, k)."""
    m = L.shape[-1]
    if m > 3:
        return np.linalg.solve(np.swapaxes(L, -1, -2), Y)
    Z = np.empty(Y.shape)
    for i in reversed(range(m)):
        r = Y[..., i, :]
        for k in range(i + 1, m):
            r = r - L[..., k, i, None] * Z[..., k, :]
        Z[..., i, :] = r / L[..., i, i, None]
    return Z


def update_batch(x: FloatArray, P: FloatArray, z: FloatArray, H: FloatArray, R: FloatArray,
                 *, gate: float | None = None, admit: np.ndarray | None = None,
                 robust: bool = False) -> BatchUpdate:
    """One measurement update of ``R`` filters at once, each with its own gate.

    The gain and the NIS through the Cholesky factor of ``S`` (closed forms for up to three
    components), and Joseph's form as ``P + (U + Uᵀ)`` with ``U = K (½ S Kᵀ − H P)`` — the same
    sum as :func:`joseph` (``−K H P − (K H P)ᵀ + K S Kᵀ``) in half the passes over ``P``,
    exactly symmetric for the symmetric ``P`` a filter keeps.

    Parameters
    ----------
    x : ndarray, shape (R, n)
    P : ndarray, shape (R, n, n)
        Symmetric.
    z : ndarray, shape (R, m)
        The measurement (an error-state filter: predicted minus measured, about ``x``).
    H : ndarray, shape (R, m, n) or (m, n)
    R : ndarray, shape (R, m, m) or (m, m)
    gate : float, optional
        Probability of the χ² gate: a reading whose NIS exceeds :func:`gate_quantile` is
        rejected (its filter unchanged).
    admit : ndarray of bool, shape (R,), optional
        Filters whose reading is used whatever its NIS (a recovery after a lock-out).
    robust : bool
        A filter whose ``S`` is not positive definite (a covariance ruined by a divergence)
        keeps its state and covariance, its reading counted as rejected (``nis`` NaN), instead
        of an error for all.

    Returns
    -------
    BatchUpdate

    Raises
    ------
    ImunavError
        If ``S`` is not positive definite (without ``robust``).
    """
    HP = H @ P
    S = HP @ np.swapaxes(H, -1, -2) + R
    S = 0.5 * (S + np.swapaxes(S, -1, -2))
    L, good = _cholesky(S)
    if not good.all():
        if not robust:
            raise ImunavError("the innovation covariance H P Hᵀ + R is not positive definite "
                              "(check R)")
        out = BatchUpdate(x.copy(), P.copy(), np.full(z.shape, np.nan), S,
                          np.full(good.shape, np.nan), np.zeros(good.shape, dtype=bool))
        if good.any():
            Hg = H[good] if H.ndim == 3 else H
            Rg = R[good] if R.ndim == 3 else R
            u = update_batch(x[good], P[good], z[good], Hg, Rg, gate=gate,
                             admit=None if admit is None else admit[good])
            out.x[good], out.P[good], out.innovation[good] = u.x, u.P, u.innovation
            out.S[good], out.nis[good], out.accepted[good] = u.S, u.nis, u.accepted
        return out
    K = np.swapaxes(_backward(L, _forward(L, HP)), -1, -2)           # (S⁻¹ H P)ᵀ
    nu = z - np.einsum("...mn,...n->...m", H, x)
    w = _forward(L, nu[..., None])[..., 0]
    nis = np.einsum("...m,...m->...", w, w)
    ok = np.ones(nis.shape, dtype=bool) if gate is None else nis <= gate_quantile(gate, z.shape[-1])
    if admit is not None:
        ok = ok | admit
    xn = x + np.einsum("...nm,...m->...n", K, nu)
    U = K @ (0.5 * (S @ np.swapaxes(K, -1, -2)) - HP)
    Pn = U + np.swapaxes(U, -1, -2)
    Pn += P
    if not ok.all():
        xn = np.where(ok[..., None], xn, x)
        Pn = np.where(ok[..., None, None], Pn, P)
    return BatchUpdate(xn, Pn, nu, S, nis, ok)


@dataclass
class Update:
    """The result of one measurement update.

    Attributes
    ----------
    x, P : ndarray
        The updated state and covariance (unchanged when the measurement was rejected).
    innovation : ndarray, shape (m,)
        ``z − H x`` (before the update).
    S : ndarray, shape (m, m)
        Its covariance ``H P Hᵀ + R``.
    nis : float
        The normalised innovation squared ``νᵀ S⁻¹ ν`` (χ² with m degrees of freedom when the
        filter is consistent).
    accepted : bool
        False when the gate rejected the measurement.
    """

    x: FloatArray
    P: FloatArray
    innovation: FloatArray
    S: FloatArray
    nis: float
    accepted: bool = True


def update(x: npt.ArrayLike, P: npt.ArrayLike, z: npt.ArrayLike, H: npt.ArrayLike,
           R: npt.ArrayLike, *, gate: float | None = None) -> Update:
    """One measurement update in Joseph form (:func:`update_batch` of one filter, its inputs
    checked).

    Parameters
    ----------
    x : array_like, shape (n,)
        The state (for an error-state filter, the error estimate).
    P : array_like, shape (n, n)
    z : array_like, shape (m,)
        The measurement (an error-state filter: the measured minus the predicted value).
    H : array_like, shape (m, n)
    R : array_like, shape (m, m)
        Measurement noise covariance (symmetric positive definite).
    gate : float, optional
        Probability of the χ² gate (e.g. 0.999): a measurement whose NIS exceeds the gate's
        quantile for m degrees of freedom is rejected (``accepted`` False, state unchanged).

    Returns
    -------
    Update

    Raises
    ------
    ImunavError
        For shapes that do not fit, a ``gate`` outside (0, 1), or an innovation covariance that
        is not positive definite.

    Examples
    --------
    >>> import numpy as np
    >>> u = update([0.0], [[4.0]], [1.0], [[1.0]], [[1.0]])
    >>> round(float(u.x[0]), 3), round(float(u.P[0, 0]), 3)
    (0.8, 0.8)
    """
    x = as_float_array(x, "x", ndim=1)
    n = x.size
    P = as_float_array(P, "P", ndim=2)
    z = np.atleast_1d(as_float_array(z, "z"))
    m = z.size
    H = as_float_array(H, "H", ndim=2)
    R = as_float_array(R, "R", ndim=2)
    if P.shape != (n, n) or H.shape != (m, n) or R.shape != (m, m):
        raise ImunavError(f"update needs P ({n}, {n}), H ({m}, {n}) and R ({m}, {m}) for x of "
                          f"size {n} and z of size {m}; got P {P.shape}, H {H.shape}, "
                          f"R {R.shape}")
    if gate is not None and not 0 < gate < 1:
        raise ImunavError(f"gate must be a probability in (0, 1), got {gate!r}")
    u = update_batch(x[None], P[None], z[None], H, R, gate=gate)
    return Update(u.x[0], u.P[0], u.innovation[0], u.S[0], float(u.nis[0]), bool(u.accepted[0]))
