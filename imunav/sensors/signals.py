"""IMU output as imunav handles it: :class:`ImuSignals` (rates or increments, times, rate, g).

May import: ``imunav.core``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from imunav.core.constants import G0
from imunav.core.rotations import FloatArray
from imunav.core.validation import ImunavError, as_float_array, check_gravity, check_positive

KINDS = ("rates", "increments")

#: Largest relative departure of a sample interval from ``1/rate`` (real recordings jitter).
RATE_TOLERANCE = 0.1


@dataclass
class ImuSignals:
    """The output of a 6-axis IMU: a gyro channel and an accelerometer channel.

    Attributes
    ----------
    t : ndarray, shape (M,)
        Sample times (s), strictly increasing; for increments, the interval ends.
    gyro : ndarray, shape (M, 3)
        The gyro channel: ``ω_b`` (rad/s) for rates, ``Δθ = ∫ω_b dt`` (rad) for increments
        (also available as :attr:`omega` or :attr:`dtheta`, which check the kind).
    accel : ndarray, shape (M, 3)
        The accelerometer channel: ``f_b`` (m/s²) for rates, ``Δv = ∫f_b dt`` (m/s) for
        increments (also :attr:`specific_force` or :attr:`dv`).
    kind : {"rates", "increments"}
    rate : float
        Sample rate (Hz); every interval of ``t`` is within 10 % of ``1/rate``.
    g : float
        Gravity magnitude used (m/s²), ``g_n = [0, 0, +g]``.
    meta : dict
        Free-form information carried along (the IMU model's name, a recording's source …);
        not read by the navigation.

    Raises
    ------
    ImunavError
        If ``kind`` is not ``"rates"`` or ``"increments"``, ``rate`` or ``g`` is not a finite
        number > 0, an array is not finite or has the wrong shape (``t`` 1-D with at least one
        sample, ``gyro`` and ``accel`` ``(M, 3)``), ``t`` does not strictly increase, or an
        interval of ``t`` departs from ``1/rate`` by more than 10 % (:data:`RATE_TOLERANCE`).

    Examples
    --------
    >>> import numpy as np
    >>> sig = ImuSignals(t=np.arange(1, 4) / 100, gyro=np.zeros((3, 3)),
    ...                  accel=np.tile([0.0, 0.0, -9.80665 / 100], (3, 1)),
    ...                  kind="increments", rate=100)
    >>> sig.t0, sig.state_times()
    (0.0, array([0.  , 0.01, 0.02, 0.03]))
    """

    t: FloatArray
    gyro: FloatArray
    accel: FloatArray
    kind: str
    rate: float
    g: float = G0
    meta: dict = field(default_factory=dict)

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ImunavError(f"kind must be one of {KINDS}, got {self.kind!r}")
        self.rate = check_positive(self.rate, "rate")
        self.g = check_gravity(self.g)
        self.t = as_float_array(self.t, "t", ndim=1)
        self.gyro = as_float_array(self.gyro, "gyro", ndim=2, last=3)
        self.accel = as_float_array(self.accel, "accel", ndim=2, last=3)
        n = self.t.shape[0]
        if n < 1:
            raise ImunavError("signals must have at least one sample")
        for name, a in (("gyro", self.gyro), ("accel", self.accel)):
            if a.shape[0] != n:
                raise ImunavError(f"{name} must have shape ({n}, 3) to match t, got {a.shape}")
        if n >= 2:
            d = np.diff(self.t) * self.rate
            if d.min() <= 0:
                i = int(np.argmin(d))
                raise ImunavError(f"t must be strictly increasing; t[{i + 1}] = "
                                  f"{self.t[i + 1]:.9g} s does not exceed t[{i}] = {self.t[i]:.9g} s")
            bad = np.abs(d - 1) > RATE_TOLERANCE
            if bad.any():
                i = int(np.argmax(bad))
                raise ImunavError(f"t is inconsistent with rate = {self.rate:g} Hz: interval {i} "
                                  f"lasts {d[i] / self.rate:.6g} s, not {1 / self.rate:.6g} s")

    @property
    def dt(self) -> float:
        """Sample interval ``1/rate`` (s)."""
        return 1.0 / self.rate

    @property
    def t0(self) -> float:
        """Start time (s): the first sample for rates, the start of the first interval
        (``t[0] − dt``) for increments."""
        return float(self.t[0]) if self.kind == "rates" else float(self.t[0]) - self.dt

    def state_times(self) -> FloatArray:
        """Times of the navigation states these signals give.

        Returns
        -------
        ndarray, shape (M,) or (M + 1,)
            A copy of ``t`` for rates (a state at each sample); :attr:`t0` followed by ``t``
            for increments (the M + 1 nodes of the M intervals).
        """
        return self.t.copy() if self.kind == "rates" else np.concatenate([[self.t0], self.t])

    def _channel(self, name: str, kind: str, arr: FloatArray) -> FloatArray:
        if self.kind != kind:
            raise ImunavError(f"{name} is only defined for {kind} signals; these are {self.kind}")
        return arr

    @property
    def omega(self) -> FloatArray:
        """Body rate samples ``ω_b`` (rad/s), shape (M, 3): the gyro channel of rates.

        Raises
        ------
        ImunavError
            For increment signals (use :attr:`dtheta`).
        """
        return self._channel("omega", "rates", self.gyro)

    @property
    def specific_force(self) -> FloatArray:
        """Specific force samples ``f_b`` (m/s²), shape (M, 3): the accelerometer channel of
        rates.

        Raises
        ------
        ImunavError
            For increment signals (use :attr:`dv`).
        """
        return self._channel("specific_force", "rates", self.accel)

    @property
    def dtheta(self) -> FloatArray:
        """Angle increments ``Δθ = ∫ω_b dt`` (rad), shape (M, 3): the gyro channel of
        increments.

        Raises
        ------
        ImunavError
            For rate signals (use :attr:`omega`).
        """
        return self._channel("dtheta", "increments", self.gyro)

    @property
    def dv(self) -> FloatArray:
        """Velocity increments ``Δv = ∫f_b dt`` (m/s), shape (M, 3): the accelerometer channel
        of increments.

        Raises
        ------
        ImunavError
            For rate signals (use :attr:`specific_force`).
        """
        return self._channel("dv", "increments", self.accel)

    def __len__(self) -> int:
        return self.t.shape[0]
