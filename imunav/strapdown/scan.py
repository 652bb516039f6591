"""The attitude scan: ``q_k = q_{k−1} ⊗ d_k`` for long sequences, at compiled-code speed.

The recursion is associative, so it is evaluated by a blocked prefix product over cache-sized
chunks, quaternions held as complex pairs (Cayley–Dickson: 8 vectorised complex operations per
product instead of 28 real ones), with the exponential of rotation vectors fused into the scan
(:func:`exp_product`). :func:`prefix_product` is the same idea for any associative product
(matrices, as in the Marusenkova paper's DCM schemes). :mod:`imunav.strapdown.reference` holds
the one-sample-at-a-time loops these are tested against.

May import: ``imunav.core``.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from imunav.core.rotations import FloatArray, quat_normalize
from imunav.core.validation import ImunavError, as_float_array

__all__ = ["cumulative_product", "exp_product", "prefix_product"]


def prefix_product(x0: np.ndarray, d: np.ndarray, mul, block: int | None = None) -> np.ndarray:
    """``x_k = mul(x_{k−1}, d_k)`` for k = 1..N with ``x_0`` first, for any associative ``mul``
    on arrays whose first axis is the sample (quaternions ``(N, 4)``, matrices ``(N, 3, 3)``).

    Blocked prefix product: the N factors are split into ~√N blocks; prefix products are
    formed inside all blocks at once (vectorised across blocks), the block totals are
    chained, then applied — about 2√N vectorised operations instead of N scalar ones.
    Same arithmetic as the sequential loop up to associativity (tested to 1e-12).

    Parameters
    ----------
    x0 : ndarray
        The first element (e.g. a quaternion (4,) or a matrix (3, 3)); a last axis of 4 is
        taken for quaternions, otherwise square matrices (the padding identity).
    d : ndarray, shape (N,) + x0.shape
        The factors ``d_1 .. d_N``.
    mul : callable
        ``mul(a, b)``, associative and broadcasting over leading axes (e.g. ``np.matmul``).
    block : int, optional
        Block length; default ``ceil(√N)``.

    Returns
    -------
    ndarray, shape (N + 1,) + x0.shape
        ``x_0 .. x_N``.

    Examples
    --------
    >>> import numpy as np
    >>> shear = np.tile([[1.0, 1.0], [0.0, 1.0]], (3, 1, 1))
    >>> prefix_product(np.eye(2), shear, np.matmul)[-1]
    array([[1., 3.],
           [0., 1.]])
    """
    n = d.shape[0]
    if n == 0:
        return x0[None].copy()
    L = block or max(1, int(np.ceil(np.sqrt(n))))
    B = -(-n // L)
    pad = B * L - n
    if pad:
        ident = np.broadcast_to(_identity_like(x0), (pad,) + x0.shape)
        d = np.concatenate([d, ident])
    d = d.reshape((B, L) + x0.shape)
    P = np.empty_like(d)
    P[:, 0] = d[:, 0]
    for j in range(1, L):
        P[:, j] = mul(P[:, j - 1], d[:, j])
    S = np.empty((B,) + x0.shape)
    S[0] = x0
    for b in range(1, B):
        S[b] = mul(S[b - 1], P[b - 1, L - 1])
    x = mul(S[:, None], P).reshape((B * L,) + x0.shape)[:n]
    return np.concatenate([x0[None], x])


def _identity_like(x0: np.ndarray) -> np.ndarray:
    if x0.shape[-1] == 4:                      # quaternions, possibly batched (R, 4)
        return np.broadcast_to([1.0, 0.0, 0.0, 0.0], x0.shape)
    return np.broadcast_to(np.eye(x0.shape[-1]), x0.shape)


#: Samples per chunk of the quaternion scan (the working set stays in cache) and block length.
_SCAN_CHUNK = 1 << 16
_SCAN_LEAF = 16


# Quaternions inside the scan are pairs of complex numbers (Cayley–Dickson):
# q = (w + x i) + (y + z i) j, and the Hamilton product is
#     (a₁ + a₂ j) ⊗ (b₁ + b₂ j) = (a₁ b₁ − a₂ b̄₂) + (a₁ b₂ + a₂ b̄₁) j.
# An (..., 4) float array viewed as complex is exactly (..., 2) [w + x i, y + z i], so the
# change of representation is free, and a product costs 8 vectorised complex operations
# instead of 28 real ones.


def _cmul(a, b, out, t):
    """``out = a ⊗ b`` for component-first complex pairs (2, ...); ``t`` is scratch.
    ``out`` must not alias ``a`` or ``b``."""
    np.multiply(a[0], b[0], out=out[0])
    np.multiply(a[1], np.conjugate(b[1], out=t), out=t)
    np.subtract(out[0], t, out=out[0])
    np.multiply(a[0], b[1], out=out[1])
    np.multiply(a[1], np.conjugate(b[0], out=t), out=t)
    np.add(out[1], t, out=out[1])
    return out


def _blocked(x: np.ndarray, L: int, pad: np.ndarray) -> np.ndarray:
    """AoS chunk ``x`` (m, R, c) → component-first blocks ``(c, L, R, nb)`` (contiguous), where
    sample ``b·L + j`` lands at ``[:, j, :, b]``; the last block is padded with ``pad`` (c,)."""
    m, R, c = x.shape
    nb = -(-m // L)
    if nb * L > m:
        x = np.concatenate([x, np.broadcast_to(pad, (nb * L - m, R, c))])
    return np.ascontiguousarray(x.reshape(nb, L, R, c).transpose(3, 1, 2, 0))


def _quat_blocked(dq: np.ndarray, L: int) -> np.ndarray:
    """Quaternion factors (m, R, 4) → complex pairs blocked (2, L, R, nb), identity padding."""
    return _blocked(np.ascontiguousarray(dq).view(np.complex128), L, np.array([1.0 + 0j, 0j]))


def _exp_blocked(phi: np.ndarray, L: int) -> np.ndarray:
    """``exp(φ)`` of rotation vectors (m, R, 3) as complex pairs blocked (2, L, R, nb):
    ``[cos(a/2) + i s φx, s φy + i s φz]`` with ``a = |φ|``, ``s = sin(a/2)/a`` (→ ½ at 0)."""
    v = _blocked(phi, L, np.zeros(3))
    a = v[0] * v[0]
    a += v[1] * v[1]
    a += v[2] * v[2]
    np.sqrt(a, out=a)
    half = 0.5 * a
    out = np.empty((2,) + a.shape, np.complex128)
    s = np.sin(half)
    if a.size and a.max() < 1.0:        # cos(a/2) = √(1 − sin²(a/2)), exact to rounding here
        c = np.square(s, out=half)
        np.subtract(1.0, c, out=c)
        np.sqrt(c, out=out[0].real)
    else:
        np.cos(half, out=out[0].real)
    np.divide(s, a, out=s, where=a > 0)
    s[a == 0] = 0.5
    np.multiply(v[0], s, out=out[0].imag)
    np.multiply(v[1], s, out=out[1].real)
    np.multiply(v[2], s, out=out[1].imag)
    return out


def _quat_scan(q0: np.ndarray, n: int, factors, normalize: bool) -> FloatArray:
    """``q_k = q_{k−1} ⊗ d_k`` for k = 1..n, for ``R`` independent runs at once.

    ``q0`` (R, 4); ``factors(lo, hi, L)`` returns ``d_{lo+1..hi}`` as complex pairs blocked
    (2, L, R, nb) (see :func:`_blocked`). Returns (n+1, R, 4).

    Blocked prefix product, one cache-sized chunk after another: (1) prefix products inside
    every block of L factors, vectorised across the chunk's blocks and the runs; (2) the block
    totals are chained from the running attitude (recursively, by this same function) to give
    every block's starting attitude; (3) that is applied to the block's prefix products and
    the results are normalised and written out. The arithmetic is that of the sequential loop
    up to associativity (tested against :mod:`imunav.reference` to ≤ 1e-12).
    """
    R = q0.shape[0]
    out = np.empty((n + 1, R, 4))
    out[0] = q0
    L = _SCAN_LEAF
    if n <= 4 * L:                                      # short: the plain sequential loop
        if n:
            d = factors(0, n, 1)[:, 0]                          # (2, R, n) complex
            z = out.view(np.complex128)                          # (n+1, R, 2)
            for k in range(n):
                a1, a2, b1, b2 = z[k, :, 0], z[k, :, 1], d[0, :, k], d[1, :, k]
                z[k + 1, :, 0] = a1 * b1 - a2 * np.conjugate(b2)
                z[k + 1, :, 1] = a1 * b2 + a2 * np.conjugate(b1)
        if normalize:
            out /= np.linalg.norm(out, axis=-1, keepdims=True)
        return out
    step = max(1, _SCAN_CHUNK // (L * R))               # blocks per chunk
    P = np.empty((2, L, R, step), np.complex128)        # in-block prefix products
    X = np.empty_like(P)
    t = np.empty((L, R, step), np.complex128)
    r = np.empty((L, R, step))
    flat = out[1:].view(np.complex128)                  # (n, R, 2)
    carry = q0
    for lo in range(0, n, step * L):
        hi = min(n, lo + step * L)
        F = factors(lo, hi, L)
        nbc = F.shape[-1]
        Pc, Xc, tc = P[..., :nbc], X[..., :nbc], t[..., :nbc]
        Pc[:, 0] = F[:, 0]
        for j in range(1, L):                           # (1) inside the blocks
            _cmul(Pc[:, j - 1], F[:, j], Pc[:, j], tc[0])
        tot = np.ascontiguousarray(Pc[:, L - 1].transpose(2, 1, 0)).view(np.float64)
        S = _quat_scan(carry, nbc, lambda a, b, L2, tot=tot: _quat_blocked(tot[a:b], L2), False)
        carry = S[-1]
        S = np.ascontiguousarray(S[:-1].view(np.complex128).transpose(2, 1, 0))  # (2, R, nbc)
        _cmul(S[:, None], Pc, Xc, tc)                   # (3)
        if normalize:                                   # scale by 1/|q| on the float view
            rc = r[..., :nbc]
            xf = Xc.view(np.float64)                    # (2, L, R, 2·nbc): re, im, re, im…
            sq = np.square(xf)
            np.add(sq[0, ..., 0::2], sq[0, ..., 1::2], out=rc)
            rc += sq[1, ..., 0::2]
            rc += sq[1, ..., 1::2]
            np.sqrt(rc, out=rc)
            np.divide(1.0, rc, out=rc)
            xf[..., 0::2] *= rc
            xf[..., 1::2] *= rc
        if hi - lo == nbc * L:                          # (2, L, R, nbc) → (nbc, L, R, 2)
            flat[lo:hi].reshape(nbc, L, R, 2)[...] = Xc.transpose(3, 1, 2, 0)
        else:                                           # the last, padded chunk
            flat[lo:hi] = Xc.transpose(3, 1, 2, 0).reshape(-1, R, 2)[: hi - lo]
    return out


def _check_chain(q0, x, name: str, last: int) -> tuple[np.ndarray, np.ndarray, bool]:
    """Validate ``q0`` (4,) or (R, 4) and factors (N, 4|3) or (N, R, 4|3); return batched views."""
    q0 = as_float_array(q0, "q0", last=4)
    x = as_float_array(x, name, last=last)
    single = q0.ndim == 1
    if q0.ndim not in (1, 2) or x.ndim != q0.ndim + 1 or x.shape[1:-1] != q0.shape[:-1]:
        raise ImunavError(
            f"{name} must have shape (N, {last}) for q0 of shape (4,), or (N, R, {last}) for q0 "
            f"of shape (R, 4); got {name} {x.shape} and q0 {q0.shape}"
        )
    if single:
        q0, x = q0[None], x[:, None]
    return q0, x, single


def cumulative_product(q0: npt.ArrayLike, dq: npt.ArrayLike, normalize: bool = True) -> FloatArray:
    """``q_k = q_{k−1} ⊗ dq_k`` for k = 1..N (Hamilton product), returned with ``q_0`` first.

    Vectorised blocked prefix product (:func:`_quat_scan`). With ``q_nb`` and body-frame
    increments ``dq_k = q_{b_{k−1} b_k}`` this is the attitude update.

    Parameters
    ----------
    q0 : array_like, shape (4,) or (R, 4)
        The initial quaternion(s), scalar first; R independent chains when 2-D.
    dq : array_like, shape (N, 4) or (N, R, 4)
        The factors.
    normalize : bool, default True
        Rescale ``q0`` and the results to unit norm (False keeps the norm drift of
        unnormalised updates, as some papers do).

    Returns
    -------
    ndarray, shape (N + 1, 4) or (N + 1, R, 4)
        ``q_0 .. q_N``.

    Raises
    ------
    ImunavError
        If ``q0`` or ``dq`` is not finite or their shapes do not match ((N, 4) for ``q0`` (4,),
        (N, R, 4) for ``q0`` (R, 4)), or (``normalize``) ``q0`` is zero.

    Examples
    --------
    Four 45° rotations about z make a half turn:

    >>> import numpy as np
    >>> d = np.tile([np.cos(np.pi / 8), 0.0, 0.0, np.sin(np.pi / 8)], (4, 1))
    >>> q = cumulative_product([1.0, 0.0, 0.0, 0.0], d)
    >>> q.shape, bool(np.allclose(q[-1], [0.0, 0.0, 0.0, 1.0]))
    ((5, 4), True)
    """
    q0, dq, single = _check_chain(q0, dq, "dq", 4)
    if normalize:
        q0 = quat_normalize(q0, "q0")
    out = _quat_scan(q0, dq.shape[0], lambda lo, hi, L: _quat_blocked(dq[lo:hi], L), normalize)
    return out[:, 0] if single else out


def exp_product(q0: npt.ArrayLike, phi: npt.ArrayLike) -> FloatArray:
    """``q_k = q_{k−1} ⊗ exp(φ_k)`` for k = 1..N, normalised, with ``q_0`` first.

    The same as ``cumulative_product(q0, quat_exp(phi))`` with the exponential computed chunk
    by chunk inside the scan (one pass less over memory).

    Parameters
    ----------
    q0 : array_like, shape (4,) or (R, 4)
        The initial attitude(s) ``q_nb``, scalar first.
    phi : array_like, shape (N, 3) or (N, R, 3)
        Rotation vectors (rad) in the body frame, e.g. ``Δθ`` per interval.

    Returns
    -------
    ndarray, shape (N + 1, 4) or (N + 1, R, 4)
        ``q_0 .. q_N``, unit norm.

    Raises
    ------
    ImunavError
        If ``q0`` or ``phi`` is not finite, their shapes do not match, or ``q0`` is zero.

    Examples
    --------
    >>> import numpy as np
    >>> q = exp_product([1.0, 0.0, 0.0, 0.0], np.tile([0.0, 0.0, np.pi / 4], (4, 1)))
    >>> bool(np.allclose(q[2], [np.sqrt(0.5), 0, 0, np.sqrt(0.5)])), bool(np.allclose(q[4], [0, 0, 0, 1]))
    (True, True)
    """
    q0, phi, single = _check_chain(q0, phi, "phi", 3)
    q0 = quat_normalize(q0, "q0")
    out = _quat_scan(q0, phi.shape[0], lambda lo, hi, L: _exp_blocked(phi[lo:hi], L), True)
    return out[:, 0] if single else out
