"""The unchecked rotation kernels: quaternion product, conjugate, rotation of vectors, exponential
and logarithm, relative angle, DCM, cross product and cross-product matrix.

These are the numeric cores that every layer calls in its hot paths (strapdown scans, the error
model, Monte Carlo, the motions). They take float64 arrays of the right shape and check nothing:
quaternions ``(..., 4)`` as ``[w, x, y, z]`` (Hamilton, scalar first), vectors ``(..., 3)``,
broadcasting over leading axes. :mod:`imunav.core.rotations` is the checked facade over them
(the same operations under the same names, with argument checks and errors), as scipy's
``spatial.transform`` keeps validation in the facade and the arithmetic in backend modules.
Call the facade with user input; call these on arrays your own code made.

May import: nothing from imunav (layer 0).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]

__all__ = ["axis_quat", "cross", "quat_angle", "quat_conj", "quat_exp", "quat_log", "quat_mul",
           "quat_rotate", "quat_to_dcm", "skew"]

_CONJ = np.array([1.0, -1.0, -1.0, -1.0])


def quat_mul(p: FloatArray, q: FloatArray) -> FloatArray:
    """Hamilton product ``p ⊗ q`` of ``(..., 4)`` arrays (``C(p ⊗ q) = C(p) C(q)``)."""
    pw, px, py, pz = p[..., 0], p[..., 1], p[..., 2], p[..., 3]
    qw, qx, qy, qz = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack(
        [
            pw * qw - px * qx - py * qy - pz * qz,
            pw * qx + px * qw + py * qz - pz * qy,
            pw * qy - px * qz + py * qw + pz * qx,
            pw * qz + px * qy - py * qx + pz * qw,
        ],
        axis=-1,
    )


def quat_conj(q: FloatArray) -> FloatArray:
    """Conjugate ``q* = [w, −x, −y, −z]`` of any ``(..., 4)`` array."""
    return q * _CONJ


def cross(a: FloatArray, b: FloatArray) -> FloatArray:
    """``a × b`` over the last axis (3), broadcasting; componentwise, without the axis moves
    and casts of ``np.cross``, which dominate its cost on long arrays."""
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    np.multiply(a1, b2, out=out[..., 0])
    out[..., 0] -= a2 * b1
    np.multiply(a2, b0, out=out[..., 1])
    out[..., 1] -= a0 * b2
    np.multiply(a0, b1, out=out[..., 2])
    out[..., 2] -= a1 * b0
    return out


def quat_rotate(q: FloatArray, v: FloatArray) -> FloatArray:
    """``q ⊗ [0, v] ⊗ q*`` for unit ``q``: ``v + 2w (u × v) + 2 u × (u × v)``, u = vec(q)."""
    w = q[..., :1]
    u = q[..., 1:]
    t = cross(u, v)
    t *= 2.0
    out = cross(u, t)
    out += v
    out += w * t
    return out


def quat_to_dcm(q: FloatArray) -> FloatArray:
    """Direction cosine matrix ``C`` (``C @ v == quat_rotate(q, v)``) of unit ``q``:
    shape ``(..., 3, 3)``."""
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        axis=-2,
    )


def axis_quat(angle: FloatArray, axis: int) -> FloatArray:
    """Quaternion of a turn by ``angle`` (rad, any shape) about body axis ``axis`` (1 = x,
    2 = y, 3 = z: the index of the quaternion component): shape ``angle.shape + (4,)``."""
    q = np.zeros(np.shape(angle) + (4,))
    q[..., 0] = np.cos(angle / 2)
    q[..., axis] = np.sin(angle / 2)
    return q


def quat_exp(v: FloatArray) -> FloatArray:
    """Unit quaternion of rotation vectors ``v`` (rad): ``[cos(|v|/2), sin(|v|/2) v/|v|]``, exact
    at ``v = 0`` (``sin(a/2)/a = sinc(a/2π)/2``)."""
    a = np.linalg.norm(v, axis=-1, keepdims=True)
    return np.concatenate([np.cos(a / 2), 0.5 * np.sinc(a / (2 * np.pi)) * v], axis=-1)


def quat_log(q: FloatArray) -> FloatArray:
    """Rotation vector (rad) of unit ``q``, the short way round (angle in [0, π]), as
    ``2 atan2(|vec|, w)`` (full precision at small angles; exactly 0 for the identity)."""
    q = np.where(q[..., :1] < 0, -q, q)  # short way round: q and −q are the same rotation
    w = q[..., :1]
    v = q[..., 1:]
    n = np.linalg.norm(v, axis=-1, keepdims=True)
    # Where |v| = 0 the result is 0 whatever the factor, so divide by 1 there.
    return 2 * np.arctan2(n, w) / np.where(n > 0, n, 1.0) * v


def quat_angle(p: FloatArray, q: FloatArray) -> FloatArray:
    """Angle (rad, in [0, π]) of the rotation between unit ``p`` and ``q``, sign-insensitive:
    ``2 atan2(|vec(p* ⊗ q)|, |w|)``."""
    d = quat_mul(quat_conj(p), q)
    return 2 * np.arctan2(np.linalg.norm(d[..., 1:], axis=-1), np.abs(d[..., 0]))


def skew(v: FloatArray) -> FloatArray:
    """Cross-product matrix ``[v×]`` of ``(..., 3)`` vectors: ``skew(a) @ b == cross(a, b)``;
    shape ``(..., 3, 3)``."""
    z = np.zeros(v.shape[:-1])
    x, y, w = v[..., 0], v[..., 1], v[..., 2]
    return np.stack(
        [np.stack([z, -w, y], -1), np.stack([w, z, -x], -1), np.stack([-y, x, z], -1)], axis=-2
    )
