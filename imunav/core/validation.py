"""The one user-facing error type, :class:`ImunavError`, and the input checks that raise it.

Every check names the argument, what was expected and what came, so that a bad input never
surfaces as a traceback from deep inside numpy.

May import: nothing from imunav (layer 0).
"""

from __future__ import annotations

import numbers
import tomllib
from pathlib import Path

import numpy as np
import numpy.typing as npt


class ImunavError(ValueError):
    """Bad input to imunav: the message names the argument and what was expected.

    Parameters
    ----------
    message : str
        What is wrong, in the library's terms: it starts with the argument's name where one is
        at fault (``"imu 'x' is neither a preset …"``).
    argument : str or tuple of str, optional
        The name(s) of the argument(s) at fault, as they appear in the message: a face (the
        command line) replaces each by its own spelling (``imu`` → ``--imu``).
    """

    def __init__(self, message: str = "", *, argument: str | tuple[str, ...] | None = None):
        super().__init__(message)
        self.argument = argument


def as_float_array(x: npt.ArrayLike, name: str, *, last: int | None = None,
                   ndim: int | None = None, min_ndim: int = 0) -> np.ndarray:
    """Convert ``x`` to a finite float64 array and check its shape.

    Parameters
    ----------
    x : array_like
    name : str
        The argument's name, used in error messages.
    last : int, optional
        Required size of the last axis (e.g. 3 for vectors, 4 for quaternions).
    ndim : int, optional
        Required number of dimensions.
    min_ndim : int
        Minimum number of dimensions.

    Returns
    -------
    ndarray of float64
        ``x`` as an array (not a copy if it already was one of float64).

    Raises
    ------
    ImunavError
        Naming ``name``: if ``x`` is not numeric, has the wrong number of dimensions or the
        wrong last axis, or contains NaN or inf (the message gives the first such index).

    Examples
    --------
    >>> as_float_array([1, 2, 3], "v", last=3)
    array([1., 2., 3.])
    >>> as_float_array([1, 2], "v", last=3)
    Traceback (most recent call last):
    ...
    imunav.core.validation.ImunavError: v must have shape (..., 3), got (2,)
    """
    try:
        a = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ImunavError(f"{name} must be numeric, got {type(x).__name__}: {exc}") from None
    if ndim is not None and a.ndim != ndim:
        raise ImunavError(f"{name} must have {ndim} dimension(s), got shape {a.shape}")
    if a.ndim < min_ndim:
        raise ImunavError(f"{name} must have at least {min_ndim} dimension(s), got shape {a.shape}")
    if last is not None and (a.ndim == 0 or a.shape[-1] != last):
        want = f"(..., {last})" if ndim is None else "(" + "N, " * (ndim - 1) + f"{last})"
        raise ImunavError(f"{name} must have shape {want}, got {a.shape}")
    if not np.all(np.isfinite(a)):
        bad = np.argwhere(~np.isfinite(a))[0]
        raise ImunavError(f"{name} contains NaN or inf (first at index {tuple(int(i) for i in bad)})")
    return a


def check_positive(value, name: str) -> float:
    """A finite real number > 0, as float.

    Only real numbers are accepted (not ``True``, not the string ``"10"``): files and the API
    must say what they mean; the command line converts its strings before calling this.

    Parameters
    ----------
    value : object
        The value to check.
    name : str
        The argument's name, used in the error message.

    Returns
    -------
    float

    Raises
    ------
    ImunavError
        If ``value`` is not a real number (a bool, a string, None …), is NaN or infinite, or
        is ≤ 0.

    Examples
    --------
    >>> check_positive(100, "rate")
    100.0
    """
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Real):
        raise ImunavError(f"{name} must be a positive number, got {show(value)}")
    v = float(value)
    if not np.isfinite(v) or v <= 0:
        raise ImunavError(f"{name} must be a positive finite number, got {show(value)}")
    return v


def check_gravity(g) -> float:
    """Check a gravity magnitude ``g`` (m/s²; the navigation frame's ``g_n = [0, 0, +g]``).

    Parameters
    ----------
    g : float
        Gravity magnitude (m/s²).

    Returns
    -------
    float

    Raises
    ------
    ImunavError
        If ``g`` is not a finite real number > 0 (the message names ``g``).
    """
    return check_positive(g, "g")


def check_int(value, name: str, minimum: int = 0) -> int:
    """An integer ≥ ``minimum``, as int.

    ``1.7``, ``True`` and ``"3"`` are refused; ``3.0`` is not an integer either: counts and
    seeds are whole numbers. numpy integers are accepted.

    Parameters
    ----------
    value : object
        The value to check.
    name : str
        The argument's name, used in the error message.
    minimum : int, default 0
        The smallest value accepted.

    Returns
    -------
    int

    Raises
    ------
    ImunavError
        If ``value`` is not an integer (a float, a bool, a string …) or is below ``minimum``.

    Examples
    --------
    >>> check_int(3, "runs", minimum=1)
    3
    """
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Integral):
        raise ImunavError(f"{name} must be an integer ≥ {minimum}, got {show(value)}")
    v = int(value)
    if v < minimum:
        raise ImunavError(f"{name} must be an integer ≥ {minimum}, got {v}")
    return v


def show(value) -> str:
    """A value for an error message: plain numbers, not ``np.float64(…)``.

    Parameters
    ----------
    value : object
        Anything; numpy scalars are converted to Python ones first.

    Returns
    -------
    str
        A float with 6 significant digits (``%.6g``), anything else as its ``repr``.

    Examples
    --------
    >>> import numpy as np
    >>> show(np.float64(0.1) + np.float64(0.2)), show("x")
    ('0.3', "'x'")
    """
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, float):
        return f"{value:.6g}"
    return repr(value)


def check_time(t: npt.ArrayLike, name: str = "t") -> np.ndarray:
    """Check a time vector: 1-D, finite and strictly increasing.

    Parameters
    ----------
    t : array_like, shape (N,)
        Times (s).
    name : str, default "t"
        The argument's name, used in the error message.

    Returns
    -------
    ndarray of float64, shape (N,)

    Raises
    ------
    ImunavError
        If ``t`` is not numeric, not 1-D or not finite, or if a time does not exceed the one
        before it (the message gives both indices and values).
    """
    a = as_float_array(t, name, ndim=1)
    if a.size >= 2:
        d = np.diff(a)
        if np.any(d <= 0):
            i = int(np.argmax(d <= 0))
            raise ImunavError(
                f"{name} must be strictly increasing; {name}[{i + 1}] = {show(a[i + 1])} "
                f"does not exceed {name}[{i}] = {show(a[i])}"
            )
    return a


#: A quaternion read from a file is a unit ``q_nb`` to this tolerance on its norm (a file
#: written with 3 or more decimals) and is then normalised; beyond it, it is refused (a scaled
#: or garbled quaternion is not silently made unit).
QUATERNION_NORM_TOLERANCE = 1e-3


def unit_quaternions(q: npt.ArrayLike, row: str = "row", first_row: int = 0) -> np.ndarray:
    """Check that each quaternion is of unit norm to :data:`QUATERNION_NORM_TOLERANCE` and
    return them normalised.

    Parameters
    ----------
    q : array_like, shape (N, 4)
        Scalar-first quaternions.
    row : str
        How a row is named in the message (``"pose"``, ``"poses.csv, line"``).
    first_row : int
        The number of the first row in that naming.

    Returns
    -------
    ndarray, shape (N, 4)
        ``q / |q|``.

    Raises
    ------
    ImunavError
        Naming the first row whose norm is off by more than the tolerance.
    """
    q = as_float_array(q, "attitude", last=4)
    norm = np.linalg.norm(q, axis=-1)
    bad = np.nonzero(~(np.abs(norm - 1) <= QUATERNION_NORM_TOLERANCE))[0]
    if bad.size:
        i = int(bad[0])
        raise ImunavError(f"{row} {i + first_row}: quaternion norm {norm[i]:.9g} is not 1 (to "
                          f"{QUATERNION_NORM_TOLERANCE:g}; expected a unit q_nb, scalar first)")
    return q / norm[..., None]


def read_toml(path, what: str) -> dict:
    """Read the table of a TOML file.

    Parameters
    ----------
    path : str or path-like
        The file.
    what : str
        What the file is, for the error message: ``"motion file"``, ``"IMU file"`` ….

    Returns
    -------
    dict
        The top-level table, as :mod:`tomllib` parses it.

    Raises
    ------
    ImunavError
        One line, for a missing file or a directory, text that is not UTF-8 (with the byte
        offset; a byte-order mark at the start is allowed), or malformed TOML (with tomllib's
        line and column).
    """
    path = Path(path)
    if path.is_dir():
        raise ImunavError(f"{what} {path} is a folder; expected a TOML file")
    if not path.is_file():
        raise ImunavError(f"{what} not found: {path}")
    try:
        text = path.read_bytes().decode("utf-8-sig")        # a byte-order mark is allowed
    except UnicodeDecodeError as exc:
        raise ImunavError(f"{what} {path} is not UTF-8 text (byte {exc.start})") from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ImunavError(f"malformed TOML in {path}: {exc}") from None
