"""Rotations core: Hamilton quaternions (scalar first), DCMs, Z-Y-X Euler angles, rotation vectors.

All functions are vectorised over leading axes: quaternions have shape ``(..., 4)`` as
``[w, x, y, z]``, vectors ``(..., 3)``, matrices ``(..., 3, 3)``. ``q_nb`` rotates body vectors
into the navigation frame, ``v_n = q ⊗ v_b ⊗ q*`` and ``C_nb = quat_to_dcm(q_nb)``.

This is the checked facade: every function converts and checks its arguments (shapes, finite
values, unit norm where a rotation is meant) and raises :class:`~imunav.core.validation.ImunavError`
naming the argument. The arithmetic is in :mod:`imunav.core.kernels` (the same operations under
the same names, unchecked), which the numeric layers above call in their hot paths.

May import: ``imunav.core.validation``, ``imunav.core.kernels``.
"""

from __future__ import annotations

import warnings

import numpy as np
import numpy.typing as npt

from imunav.core import kernels as K
from imunav.core.kernels import FloatArray
from imunav.core.validation import ImunavError, as_float_array

#: ``|cos θ|`` below which Z-Y-X Euler angles are treated as gimbal-locked.
GIMBAL_LOCK_TOL = 1e-9


class GimbalLockWarning(UserWarning):
    """Pitch is at ±90°: yaw and roll are not separable; roll is set to 0.

    Issued by :func:`quat_to_euler` (and so by every ``euler()`` of a motion or of
    :class:`~imunav.core.states.States`) where ``|cos θ| < GIMBAL_LOCK_TOL``; only ``ψ ∓ φ``
    is defined there, and it is returned as the yaw. Filter it with :mod:`warnings` where a
    vertical attitude is expected.
    """


def quat_mul(p: npt.ArrayLike, q: npt.ArrayLike) -> FloatArray:
    """Hamilton product ``p ⊗ q`` (scalar first), broadcasting over leading axes.

    ``i ⊗ j = k``, ``j ⊗ i = −k``, ``i ⊗ j ⊗ k = −1``. The rotation ``p ⊗ q`` applies ``q``
    first, then ``p`` (as matrices: ``C(p ⊗ q) = C(p) C(q)``).

    Parameters
    ----------
    p, q : array_like, shape (..., 4)
        Quaternions ``[w, x, y, z]`` (any norm; the product of unit quaternions is unit).

    Returns
    -------
    ndarray, shape (..., 4)

    Raises
    ------
    ImunavError
        If either is not numeric, finite, with a last axis of 4.

    Examples
    --------
    >>> quat_mul([0, 1, 0, 0], [0, 0, 1, 0])          # i ⊗ j = k
    array([0., 0., 0., 1.])
    """
    p = as_float_array(p, "p", last=4)
    q = as_float_array(q, "q", last=4)
    return K.quat_mul(p, q)


def quat_conj(q: npt.ArrayLike) -> FloatArray:
    """Conjugate ``q* = [w, −x, −y, −z]`` (the inverse of a unit quaternion).

    Parameters
    ----------
    q : array_like, shape (..., 4)

    Returns
    -------
    ndarray, shape (..., 4)

    Raises
    ------
    ImunavError
        If ``q`` is not numeric, finite, with a last axis of 4.
    """
    q = as_float_array(q, "q", last=4)
    return K.quat_conj(q)


def quat_normalize(q: npt.ArrayLike, name: str = "q") -> FloatArray:
    """Scale ``q`` to unit norm.

    Parameters
    ----------
    q : array_like, shape (..., 4)
    name : str
        The argument the error message names.

    Returns
    -------
    ndarray, shape (..., 4)

    Raises
    ------
    ImunavError
        If ``q`` is not a finite (..., 4) array, or one of them is zero.
    """
    q = as_float_array(q, name, last=4)
    n = np.linalg.norm(q, axis=-1, keepdims=True)
    if np.any(n == 0):
        raise ImunavError(f"{name} must have non-zero norm to be normalised, got a zero quaternion")
    return q / n


def quat_rotate(q: npt.ArrayLike, v: npt.ArrayLike) -> FloatArray:
    """Rotate vectors: ``q ⊗ [0, v] ⊗ q*`` for unit ``q`` (``q`` is normalised first).

    With ``q = q_nb`` this takes body-frame vectors to the navigation frame.

    Parameters
    ----------
    q : array_like, shape (..., 4)
    v : array_like, shape (..., 3)
        Broadcast against ``q``'s leading axes.

    Returns
    -------
    ndarray, shape (..., 3)

    Raises
    ------
    ImunavError
        For arrays of the wrong shape, non-finite values or a zero quaternion.

    Examples
    --------
    >>> import numpy as np
    >>> np.round(quat_rotate([np.cos(np.pi / 4), 0, 0, np.sin(np.pi / 4)], [1.0, 0, 0]), 12)
    array([0., 1., 0.])
    """
    q = quat_normalize(q)
    v = as_float_array(v, "v", last=3)
    return K.quat_rotate(q, v)


def quat_to_dcm(q: npt.ArrayLike) -> FloatArray:
    """Direction cosine matrix ``C`` with ``C @ v == quat_rotate(q, v)``.

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Normalised first.

    Returns
    -------
    ndarray, shape (..., 3, 3)
        ``C_nb`` for ``q = q_nb``.

    Raises
    ------
    ImunavError
        For a wrong shape, non-finite values or a zero quaternion.
    """
    q = quat_normalize(q)
    return K.quat_to_dcm(q)


def quat_from_dcm(c: npt.ArrayLike, *, atol: float = 1e-6) -> FloatArray:
    """Unit quaternion (``w ≥ 0``) of a rotation matrix, by Shepperd's method.

    Parameters
    ----------
    c : array_like, shape (..., 3, 3)
    atol : float
        Tolerance of the orthonormality and determinant checks.

    Returns
    -------
    ndarray, shape (..., 4)

    Raises
    ------
    ImunavError
        If ``c`` is not a proper rotation (``cᵀc = I`` and ``det c = +1`` within ``atol``).
    """
    c = as_float_array(c, "c", min_ndim=2)
    if c.shape[-2:] != (3, 3):
        raise ImunavError(f"c must have shape (..., 3, 3), got {c.shape}")
    err = np.abs(np.swapaxes(c, -1, -2) @ c - np.eye(3)).max(axis=(-1, -2))
    if np.any(err > atol) or np.any(np.linalg.det(c) <= 0):
        raise ImunavError(
            f"c must be a proper rotation matrix (orthonormal, det +1); worst |cᵀc − I| = "
            f"{float(np.max(err)):.3g}"
        )
    tr = np.trace(c, axis1=-2, axis2=-1)
    d = np.stack([tr, c[..., 0, 0], c[..., 1, 1], c[..., 2, 2]], axis=-1)
    k = np.argmax(d, axis=-1)
    out = np.empty(c.shape[:-2] + (4,))
    # Each branch divides by the largest of the four candidates, so never by ~0.
    s0 = np.sqrt(np.maximum(1 + tr, 0)) * 2
    s1 = np.sqrt(np.maximum(1 + 2 * c[..., 0, 0] - tr, 0)) * 2
    s2 = np.sqrt(np.maximum(1 + 2 * c[..., 1, 1] - tr, 0)) * 2
    s3 = np.sqrt(np.maximum(1 + 2 * c[..., 2, 2] - tr, 0)) * 2
    with np.errstate(divide="ignore", invalid="ignore"):
        cand = [
            np.stack([s0 / 4, (c[..., 2, 1] - c[..., 1, 2]) / s0,
                      (c[..., 0, 2] - c[..., 2, 0]) / s0, (c[..., 1, 0] - c[..., 0, 1]) / s0], -1),
            np.stack([(c[..., 2, 1] - c[..., 1, 2]) / s1, s1 / 4,
                      (c[..., 0, 1] + c[..., 1, 0]) / s1, (c[..., 0, 2] + c[..., 2, 0]) / s1], -1),
            np.stack([(c[..., 0, 2] - c[..., 2, 0]) / s2, (c[..., 0, 1] + c[..., 1, 0]) / s2,
                      s2 / 4, (c[..., 1, 2] + c[..., 2, 1]) / s2], -1),
            np.stack([(c[..., 1, 0] - c[..., 0, 1]) / s3, (c[..., 0, 2] + c[..., 2, 0]) / s3,
                      (c[..., 1, 2] + c[..., 2, 1]) / s3, s3 / 4], -1),
        ]
    for i in range(4):
        m = k == i
        out[m] = cand[i][m]
    out = out / np.linalg.norm(out, axis=-1, keepdims=True)
    return np.where(out[..., :1] < 0, -out, out)


def euler_to_quat(ypr: npt.ArrayLike) -> FloatArray:
    """Quaternion ``q_nb = q_z(ψ) ⊗ q_y(θ) ⊗ q_x(φ)`` of Z-Y-X Euler angles.

    Intrinsic Z-Y-X: the same rotation as ``Rotation.from_euler("ZYX", [ψ, θ, φ])``.

    Parameters
    ----------
    ypr : array_like, shape (..., 3)
        ``[yaw ψ, pitch θ, roll φ]`` (rad).

    Returns
    -------
    ndarray, shape (..., 4)

    Raises
    ------
    ImunavError
        If ``ypr`` is not a finite (..., 3) array.
    """
    ypr = as_float_array(ypr, "ypr", last=3)
    return K.quat_mul(K.quat_mul(K.axis_quat(ypr[..., 0], 3), K.axis_quat(ypr[..., 1], 2)),
                      K.axis_quat(ypr[..., 2], 1))


def quat_to_euler(q: npt.ArrayLike) -> FloatArray:
    """``[yaw ψ, pitch θ, roll φ]`` (rad, intrinsic Z-Y-X) of ``q_nb``.

    ψ, φ ∈ (−π, π], θ ∈ [−π/2, π/2]. At gimbal lock (``|cos θ| < GIMBAL_LOCK_TOL``) only
    ψ ∓ φ is defined: φ is set to 0 and a :class:`GimbalLockWarning` is issued.

    Parameters
    ----------
    q : array_like, shape (..., 4)

    Returns
    -------
    ndarray, shape (..., 3)

    Raises
    ------
    ImunavError
        For a wrong shape, non-finite values or a zero quaternion.
    """
    q = quat_normalize(q)
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    s = 2 * (w * y - x * z)  # sin θ = −C20
    # cos θ from the first column's other two entries; atan2 keeps θ exact near ±90°
    # (arcsin(s) loses half the digits there).
    cos_pitch = np.hypot(1 - 2 * (y * y + z * z), 2 * (x * y + w * z))
    pitch = np.arctan2(s, cos_pitch)
    yaw = np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))
    roll = np.arctan2(2 * (w * x + y * z), 1 - 2 * (x * x + y * y))
    locked = cos_pitch < GIMBAL_LOCK_TOL
    if np.any(locked):
        warnings.warn(
            "gimbal lock: pitch is ±90°, yaw and roll are not separable; roll set to 0",
            GimbalLockWarning,
            stacklevel=2,
        )
        # At θ = ±90° the DCM reduces to C01 = −sin(ψ ∓ φ), C11 = cos(ψ ∓ φ).
        yaw_l = np.arctan2(-2 * (x * y - w * z), 1 - 2 * (x * x + z * z))
        yaw = np.where(locked, yaw_l, yaw)
        roll = np.where(locked, 0.0, roll)
    return np.stack([yaw, pitch, roll], axis=-1)


def quat_exp(rotvec: npt.ArrayLike) -> FloatArray:
    """Unit quaternion of a rotation vector ``φ`` (rad): ``[cos(|φ|/2), sin(|φ|/2) φ/|φ|]``.

    Exact at ``φ = 0`` (uses ``sin(a/2)/a = sinc(a/2π)/2``, no division by zero).

    Parameters
    ----------
    rotvec : array_like, shape (..., 3)

    Returns
    -------
    ndarray, shape (..., 4)

    Raises
    ------
    ImunavError
        If ``rotvec`` is not a finite (..., 3) array.
    """
    v = as_float_array(rotvec, "rotvec", last=3)
    return K.quat_exp(v)


def quat_log(q: npt.ArrayLike) -> FloatArray:
    """Rotation vector (rad) of ``q``, the short way round (angle in [0, π]).

    Uses ``angle = 2 atan2(|v|, |w|)``, accurate to full precision for small angles and
    for ``|w|`` slightly above 1; the zero rotation gives exactly 0.

    Parameters
    ----------
    q : array_like, shape (..., 4)
        Normalised first.

    Returns
    -------
    ndarray, shape (..., 3)

    Raises
    ------
    ImunavError
        For a wrong shape, non-finite values or a zero quaternion.
    """
    q = quat_normalize(q)
    return K.quat_log(q)


def quat_angle(p: npt.ArrayLike, q: npt.ArrayLike) -> FloatArray:
    """Angle (rad, in [0, π]) of the rotation between ``p`` and ``q``: ``|log(p* ⊗ q)|``.

    Sign-insensitive (``quat_angle(q, −q) == 0``), symmetric, and computed as
    ``2 atan2(|vec|, |w|)`` so that angles far below 1e-8 rad are resolved (an
    ``arccos``-based angle floors near 1e-8 rad).

    Parameters
    ----------
    p, q : array_like, shape (..., 4)
        Normalised first; broadcast against each other.

    Returns
    -------
    ndarray, shape (...)

    Raises
    ------
    ImunavError
        For a wrong shape, non-finite values or a zero quaternion.
    """
    return K.quat_angle(quat_normalize(p, "p"), quat_normalize(q, "q"))


def skew(v: npt.ArrayLike) -> FloatArray:
    """Cross-product matrix ``[v×]``, with ``skew(a) @ b == cross(a, b)``.

    Parameters
    ----------
    v : array_like, shape (..., 3)
        Vectors (any frame and unit; the matrix has the same).

    Returns
    -------
    ndarray, shape (..., 3, 3)
        ``[[0, −v_z, v_y], [v_z, 0, −v_x], [−v_y, v_x, 0]]`` for each vector (antisymmetric).

    Raises
    ------
    ImunavError
        If ``v`` is not numeric, finite, with a last axis of 3.

    Examples
    --------
    >>> skew([1.0, 2.0, 3.0]) @ [4.0, 5.0, 6.0]          # = cross([1, 2, 3], [4, 5, 6])
    array([-3.,  6., -3.])
    """
    return K.skew(as_float_array(v, "v", last=3))


def to_scipy(q: npt.ArrayLike):
    """``scipy.spatial.transform.Rotation`` of scalar-first ``q`` (flag passed explicitly).

    Parameters
    ----------
    q : array_like, shape (..., 4)

    Returns
    -------
    scipy.spatial.transform.Rotation

    Raises
    ------
    ImunavError
        For a wrong shape, non-finite values or a zero quaternion.
    """
    from scipy.spatial.transform import Rotation

    return Rotation.from_quat(quat_normalize(q), scalar_first=True)


def from_scipy(rotation) -> FloatArray:
    """Scalar-first quaternion(s) ``[w, x, y, z]`` of a scipy ``Rotation``.

    Parameters
    ----------
    rotation : scipy.spatial.transform.Rotation

    Returns
    -------
    ndarray, shape (4,) or (N, 4)
    """
    return np.asarray(rotation.as_quat(scalar_first=True), dtype=np.float64)
