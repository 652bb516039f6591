"""What a covariance analysis returns: every output time's covariances per error term
(:class:`CovarianceResult`, from :func:`~imunav.analysis.covariance.covariance`), or what an
assessment reads of them, gathered while streaming (:class:`CovarianceSummary`, from
:func:`~imunav.analysis.covariance.covariance_summary`); the same reading methods on both
(quantiles and probabilities of the position and attitude error norms).

May import: ``imunav.core``, ``imunav.estimation``, ``imunav.analysis.gaussnorm``,
``imunav.analysis.trackers``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from imunav.analysis.gaussnorm import norm_cdf, norm_quantile
from imunav.analysis.trackers import MaxQuantileTracker, WithinTracker
from imunav.core.kernels import FloatArray
from imunav.estimation.propagation import CHUNK

__all__ = ["CovarianceResult", "CovarianceSummary"]


@dataclass
class CovarianceResult:
    """Nav-error covariances (N + 1, 9, 9) per error term and in total, at the output times.

    What :func:`covariance` returns. The error state is ``[φ, δv, δp]``: attitude error (rad),
    velocity error (m/s) and position error (m), each in the navigation frame (NED; on the
    WGS-84 Earth the local NED frame).

    Attributes
    ----------
    t : ndarray, shape (N + 1,)
        The output times (s).
    terms : dict of str to ndarray, shape (N + 1, 9, 9)
        Each error term's covariance, keyed ``"gyro.bias"`` etc. (independent sources: they
        add).
    total : ndarray, shape (N + 1, 9, 9)
        Their sum.
    rate : float
        The output rate (Hz).
    model : str
        The IMU model's name.
    max_rate : float
        The motion's largest ``|ω_b|`` (rad/s).
    max_force : float
        The motion's largest ``|f_b|`` (m/s²).
    warnings : list of str
        Where the linear model may not hold (a range exceeded, large attitude errors).

    Examples
    --------
    An accelerometer bias of σ = 0.01 m/s² per axis, at rest for 10 s: δp = ½ b t² is normal
    with σ = 0.5 m per axis, so its norm's 95th percentile is 0.5 m × √χ²₃(0.95):

    >>> import numpy as np
    >>> from scipy.stats import chi2
    >>> from imunav.motion import Motion
    >>> from imunav.sensors.models import ImuModel, TriadModel
    >>> r = covariance(Motion(duration=10.0), ImuModel(accel=TriadModel(bias=0.01)), rate=10)
    >>> list(r.terms), r.t.shape
    (['accel.bias'], (101,))
    >>> bool(np.isclose(r.position_quantile(index=-1), 0.5 * np.sqrt(chi2.ppf(0.95, 3))))
    True
    """

    t: FloatArray
    terms: dict[str, FloatArray]
    total: FloatArray
    rate: float
    model: str
    max_rate: float
    max_force: float
    warnings: list[str]

    def position_quantile(self, p: float = 0.95, term: str | None = None,
                          index=slice(None)) -> FloatArray:
        """The ``p``-quantile of the position error's norm ``|δp|`` (m).

        Parameters
        ----------
        p : float, default 0.95
            The probability, in (0, 1).
        term : str, optional
            One term alone (a key of :attr:`terms`); default all together.
        index : int, slice or array, default all
            Output times.

        Returns
        -------
        ndarray or float
            The quantile (m) at each selected output time.
        """
        P = self.total if term is None else self.terms[term]
        return norm_quantile(P[index, 6:9, 6:9], p)

    def attitude_quantile(self, p: float = 0.95, term: str | None = None,
                          index=slice(None)) -> FloatArray:
        """The ``p``-quantile of the attitude error's norm ``|φ|`` (rad).

        Parameters
        ----------
        p : float, default 0.95
            The probability, in (0, 1).
        term : str, optional
            One term alone (a key of :attr:`terms`); default all together.
        index : int, slice or array, default all
            Output times.

        Returns
        -------
        ndarray or float
            The quantile (rad) at each selected output time.
        """
        P = self.total if term is None else self.terms[term]
        return norm_quantile(P[index, 0:3, 0:3], p)

    def position_within(self, tolerance: float) -> FloatArray:
        """``P(|δp(t)| ≤ tolerance)`` at every output time.

        Parameters
        ----------
        tolerance : float
            The radius (m).

        Returns
        -------
        ndarray, shape (N + 1,)
            The probability at each output time.
        """
        return norm_cdf(self.total[:, 6:9, 6:9], tolerance)

    def max_position_quantile(self, p: float = 0.95, term: str | None = None) -> float:
        """``max_t`` of the ``p``-quantile of the position error's norm.

        Exact quantiles are computed only where eigenvalue bounds leave the maximum possible
        (:class:`MaxQuantileTracker`).

        Parameters
        ----------
        p : float, default 0.95
            The probability, in (0, 1).
        term : str, optional
            One term alone; default all together.

        Returns
        -------
        float
            The largest quantile over the output times (m).
        """
        P = (self.total if term is None else self.terms[term])[:, 6:9, 6:9]
        track = MaxQuantileTracker(p)
        for lo in range(0, P.shape[0], CHUNK):
            track.update(P[lo:lo + CHUNK])
        return track.maximum

    def within_summary(self, tolerance: float, level: float) -> tuple[float, int | None]:
        """The smallest probability of staying within ``tolerance``, and when it first drops
        below ``level``.

        Exact CDFs are computed only where the eigenvalue bounds leave the answer open
        (:class:`WithinTracker`).

        Parameters
        ----------
        tolerance : float
            The radius (m).
        level : float
            The probability whose first crossing is wanted (0: none).

        Returns
        -------
        minimum : float
            ``min_t P(|δp(t)| ≤ tolerance)``.
        first : int or None
            The first output index where that probability is below ``level``, or None.
        """
        track = WithinTracker(tolerance, level)
        P = self.total[:, 6:9, 6:9]
        for lo in range(0, P.shape[0], CHUNK):
            track.update(P[lo:lo + CHUNK], lo)
        return track.minimum, track.first

    def min_position_within(self, tolerance: float) -> float:
        """``min_t P(|δp(t)| ≤ tolerance)`` (see :meth:`within_summary`).

        Parameters
        ----------
        tolerance : float
            The radius (m).

        Returns
        -------
        float
            The smallest probability over the output times.
        """
        return self.within_summary(tolerance, 0.0)[0]

    def time_at(self, index: int) -> float:
        """The output time of ``index`` (s).

        Parameters
        ----------
        index : int

        Returns
        -------
        float
        """
        return float(self.t[index])


@dataclass
class CovarianceSummary:
    """What an assessment reads of a covariance analysis, gathered while it is streamed
    (:func:`covariance_summary`): the covariances on the envelope's grid only, and the exact
    extrema over every output time that the verdict and the design need.

    The same reading methods as :class:`CovarianceResult` (a verdict and a plot take either);
    ``index`` arguments count the grid's points.

    Attributes
    ----------
    t : ndarray, shape (G,)
        The grid's times (s): :func:`envelope_index` of the output times.
    index : ndarray of int, shape (G,)
        The grid's output indices.
    terms : dict of str to ndarray, shape (G, 9, 9)
        Each error term's navigation-error covariance on the grid.
    total : ndarray, shape (G, 9, 9)
        Their sum.
    rate : float
    model : str
    max_rate, max_force : float
        The motion's largest ``|ω_b|``, ``|f_b|``.
    warnings : list of str
    h : float
        The output step (s).
    steps : int
        Output steps N (the output times are ``k·h``, k = 0 … N).
    tolerance : float or None
        The radius whose probability was tracked.
    level : float
        The probability whose first crossing was tracked.
    within : tuple or None
        ``(min_t P(|δp| ≤ tolerance), first index below level or None)``.
    p : float
        The quantile whose maxima were tracked.
    maxima : dict
        ``max_t`` of the ``p``-quantile of the position error, per term name and (key None)
        in total, if asked for.
    exact_evaluations : int
        Steps that needed the exact integrals (the rest were decided by bounds).
    """

    t: FloatArray
    index: np.ndarray
    terms: dict[str, FloatArray]
    total: FloatArray
    rate: float
    model: str
    max_rate: float
    max_force: float
    warnings: list[str]
    h: float
    steps: int
    tolerance: float | None = None
    level: float = 0.0
    within: tuple[float, int | None] | None = None
    p: float = 0.95
    maxima: dict = field(default_factory=dict)
    exact_evaluations: int = 0

    def position_quantile(self, p: float = 0.95, term: str | None = None,
                          index=slice(None)) -> FloatArray:
        """The ``p``-quantile of the position error's norm on the grid.

        Parameters
        ----------
        p : float
        term : str, optional
            One term alone (default all together).
        index : int, slice or array
            Grid points.

        Returns
        -------
        ndarray or float
        """
        P = self.total if term is None else self.terms[term]
        return norm_quantile(P[index, 6:9, 6:9], p)

    def attitude_quantile(self, p: float = 0.95, term: str | None = None,
                          index=slice(None)) -> FloatArray:
        """The ``p``-quantile of the attitude error's norm (rad) on the grid.

        Parameters
        ----------
        p : float
        term : str, optional
        index : int, slice or array

        Returns
        -------
        ndarray or float
        """
        P = self.total if term is None else self.terms[term]
        return norm_quantile(P[index, 0:3, 0:3], p)

    def position_within(self, tolerance: float) -> FloatArray:
        """``P(|δp| ≤ tolerance)`` on the grid.

        Parameters
        ----------
        tolerance : float

        Returns
        -------
        ndarray
        """
        return norm_cdf(self.total[:, 6:9, 6:9], tolerance)

    def within_summary(self, tolerance: float, level: float) -> tuple[float, int | None]:
        """The tracked ``(min_t P(|δp| ≤ tolerance), first output index below level)``.

        Parameters
        ----------
        tolerance, level : float
            As tracked (:func:`covariance_summary`); the minimum alone for level 0.

        Returns
        -------
        tuple

        Raises
        ------
        ValueError
            For a tolerance or level that was not tracked.
        """
        if self.within is None or tolerance != self.tolerance or (level and level != self.level):
            raise ValueError(f"this summary tracked tolerance {self.tolerance} and level "
                             f"{self.level}, not {tolerance} and {level}")
        return self.within if level else (self.within[0], None)

    def min_position_within(self, tolerance: float) -> float:
        """The tracked ``min_t P(|δp| ≤ tolerance)``.

        Parameters
        ----------
        tolerance : float

        Returns
        -------
        float
        """
        return self.within_summary(tolerance, 0.0)[0]

    def max_position_quantile(self, p: float = 0.95, term: str | None = None) -> float:
        """The tracked ``max_t`` of the ``p``-quantile of the position error.

        Parameters
        ----------
        p : float
        term : str, optional

        Returns
        -------
        float

        Raises
        ------
        ValueError
            If that maximum was not tracked.
        """
        if p != self.p or term not in self.maxima:
            raise ValueError(f"this summary tracked the maxima of the {self.p} quantile"
                             + ("" if self.maxima else " of nothing"))
        return self.maxima[term]

    def time_at(self, index: int) -> float:
        """The time of output ``index`` (s): ``index·h``.

        Parameters
        ----------
        index : int

        Returns
        -------
        float
        """
        return float(np.float64(index) * self.h)
