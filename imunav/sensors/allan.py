"""Allan deviation: the overlapping estimator, and the analytic Allan variance of the processes
the error models use (for self-checks and fits).

May import: ``imunav.core``.
"""

from __future__ import annotations

import numpy as np

from imunav.core.rotations import FloatArray
from imunav.core.validation import ImunavError


def gauss_markov_allan_variance(tau: FloatArray, sigma: float, T: float) -> FloatArray:
    """Allan variance of a first-order Gauss–Markov process (std σ, correlation time T).

    ``σ²_A(τ) = (q T² / τ) [1 − (3 − 4 e^{−τ/T} + e^{−2τ/T}) / (2τ/T)]`` with ``q = 2σ²/T``:
    it rises as ``2σ²τ/(3T)`` for τ ≪ T, peaks near τ ≈ 1.89 T and falls as ``2σ²T/τ`` for τ ≫ T.

    Parameters
    ----------
    tau : ndarray
        Averaging times (s), > 0; any shape.
    sigma : float
        The process's steady-state standard deviation (its unit, e.g. rad/s for a gyro bias).
    T : float
        Correlation time (s), > 0.

    Returns
    -------
    ndarray
        The Allan variance at each ``tau`` (the unit of ``sigma``, squared), shaped like ``tau``.

    Examples
    --------
    >>> import numpy as np
    >>> gauss_markov_allan_variance(np.array([1.0, 100.0]), sigma=1.0, T=1.0).round(4)
    array([0.3362, 0.0197])
    """
    q = 2 * sigma**2 / T
    x = tau / T
    return q * T**2 / tau * (1 - (3 - 4 * np.exp(-x) + np.exp(-2 * x)) / (2 * x))


def allan_deviation(x: FloatArray, rate: float, taus=None) -> tuple[FloatArray, FloatArray]:
    """Overlapping Allan deviation of rate samples.

    The samples are integrated (``θ_j = Σ x / rate``) and, for each cluster size m,
    ``σ²(τ) = ⟨(θ_{j+2m} − 2θ_{j+m} + θ_j)²⟩ / (2τ²)`` with ``τ = m / rate``.

    Parameters
    ----------
    x : ndarray, shape (n,) or (n, k)
        Rate samples (e.g. ω_b in rad/s or f_b in m/s²), one column per axis.
    rate : float
        Sample rate (Hz).
    taus : array_like, optional
        Averaging times (s) wanted; each is rounded to a whole number of samples (at least 1)
        and those beyond ``(n − 1) // 2`` samples are dropped. Default: 40 log-spaced cluster
        sizes from 1 sample to ``n // 3``.

    Returns
    -------
    taus : ndarray, shape (m,)
        The averaging times used (s), increasing and distinct.
    adev : ndarray, shape (m,) or (m, k)
        The Allan deviation at each τ (the unit of ``x``).

    Examples
    --------
    White noise of σ = 0.1 at 100 Hz has σ(τ) = 0.1 / √(100 τ):

    >>> import numpy as np
    >>> x = np.random.default_rng(0).normal(0.0, 0.1, 100_000)
    >>> taus, adev = allan_deviation(x, rate=100, taus=[0.1, 1.0])
    >>> taus, adev.round(3)
    (array([0.1, 1. ]), array([0.032, 0.01 ]))
    """
    x = np.asarray(x, float)
    n = x.shape[0]
    if taus is None:
        ms = np.unique(np.logspace(0, np.log10(n // 3), 40).astype(int))
    else:
        ms = np.unique(np.maximum(1, np.round(np.asarray(taus) * rate).astype(int)))
        ms = ms[ms <= (n - 1) // 2]
    theta = np.concatenate([np.zeros((1,) + x.shape[1:]), np.cumsum(x, axis=0)]) / rate
    out = []
    for m in ms:
        d = theta[2 * m:] - 2 * theta[m:-m] + theta[: -2 * m]
        tau = m / rate
        out.append(np.sqrt(np.mean(d * d, axis=0) / (2 * tau * tau)))
    return ms / rate, np.array(out)


# ----------------------------------------------------------------------------- model fitting

#: The terms fitted, in the order of the model's columns, with their IEEE 952 slopes.
FIT_TERMS = ("noise_density", "bias_instability", "random_walk")


def allan_dof(n: int, m: FloatArray) -> FloatArray:
    """Equivalent degrees of freedom of the overlapping Allan variance of ``n`` samples at
    cluster sizes ``m`` (white frequency noise: Howe, Allan & Barnes 1981)."""
    m = np.asarray(m, float)
    return np.maximum(1.0, 3 * (n - 1) / (2 * m) - 2 * (n - 2) / n)


def _rel_se(dof: FloatArray, share: FloatArray, dominant: np.ndarray) -> float:
    """Relative standard error of a fitted term: that of the Allan deviation at the τ where the
    term's share of the model is largest (σ² has relative SE √(2/ν), σ half of that).

    Neighbouring τ of one record are strongly correlated, so the least-squares covariance
    (which counts them as independent) is far too optimistic; the τ of largest share is where
    the term is read off. Measured over 12 simulated 8-hour records (N, B, K each dominating
    over ≥ 0.5 decade): this figure is 1.3–2× the actual scatter of B and K (conservative) and
    0.8× that of N, whose own error is below 1 %.
    """
    if not dominant.any():
        return np.inf
    return 0.5 * float(np.sqrt(2 / dof[int(np.argmax(share))]))


def fit_allan(x: FloatArray, rate: float, *, min_share: float = 0.5, min_decades: float = 0.5,
              max_rel_se: float = 0.3) -> dict:
    """Fit ``σ²(τ) = N²/τ + B² + K²τ/3`` to the overlapping Allan variance of a static record.

    ``x`` (n,) or (n, k): rate samples at ``rate`` Hz (one triad's axes are fitted together:
    their Allan variances are averaged). ``B`` is the Allan floor as datasheets quote it (the
    IEEE 952 flicker coefficient is B/0.664). Weighted least squares with non-negative
    coefficients, each τ weighted by its degrees of freedom over the model's variance (Var σ̂² =
    2σ⁴/ν), iterated. A term is kept only if it dominates (more than ``min_share`` of the model)
    over at least ``min_decades`` of the measured τ and its estimate's relative standard error
    is below ``max_rel_se``; otherwise it is dropped with the reason, and the rest refitted.

    Parameters
    ----------
    x : ndarray, shape (n,) or (n, k)
        Rate samples of a static record (rad/s for a gyro, m/s² for an accelerometer).
    rate : float
        Sample rate (Hz).
    min_share : float, default 0.5
        The share of the model's Allan variance a term must exceed to count as dominating.
    min_decades : float, default 0.5
        The span of τ (decades) over which a term must dominate to be kept.
    max_rel_se : float, default 0.3
        The largest relative standard error of a kept term.

    Returns
    -------
    dict
        ``"taus"`` (s) and ``"avar"`` (the axis-averaged Allan variance), ``"adev_axes"`` (the
        Allan deviation per axis, shape (m, k)), ``"dof"`` (degrees of freedom at each τ),
        ``"terms"`` (for each name of :data:`FIT_TERMS` either ``{"value", "se",
        "tau_range"}`` or ``{"value": None, "why"}``), ``"model"`` (the fitted Allan deviation
        at ``taus``), ``"samples"`` (n) and ``"rate"``. Values are SI: rad/s/√Hz, rad/s and
        rad/s/√s for a gyro (m/s²/√Hz, m/s² and m/s²/√s for an accelerometer);
        ``se`` is the Allan deviation's sampling error where the term dominates most.

    Examples
    --------
    White noise of σ = 0.1 rad/s at 100 Hz is a noise density of 0.1/√100 = 0.01 rad/s/√Hz:

    >>> import numpy as np
    >>> fit = fit_allan(np.random.default_rng(0).normal(0.0, 0.1, 100_000), rate=100)
    >>> round(fit["terms"]["noise_density"]["value"], 4), fit["terms"]["random_walk"]["value"]
    (0.01, None)
    """
    from scipy.optimize import nnls

    x = np.asarray(x, float)
    x = x[:, None] if x.ndim == 1 else x
    n, k = x.shape
    ms = np.unique(np.logspace(0, np.log10(max(1, n // 10)), 60).astype(int))
    taus, adev = allan_deviation(x, rate, ms / rate)
    avar = (np.asarray(adev).reshape(len(taus), -1) ** 2).mean(axis=1)
    dof = k * allan_dof(n, taus * rate)
    X = np.column_stack([1 / taus, np.ones_like(taus), taus / 3])    # N², B², K² columns
    if not np.all(np.isfinite(avar)) or avar.max() <= 0:
        # a constant record (an ideal or fully quantised signal): no noise, nothing to fit —
        # and zero variances would give the weights below no scale (they were infinite)
        why = ("the record is constant on every axis (zero Allan deviation): there is no "
               "noise to fit")
        return {"taus": taus, "avar": avar, "adev_axes": np.asarray(adev).reshape(len(taus), -1),
                "dof": dof, "terms": {name: {"value": None, "why": why} for name in FIT_TERMS},
                "model": np.zeros_like(taus), "samples": n, "rate": rate}
    floor = 1e-12 * float(avar.max())          # a weight's scale: never infinite, never binding
    keep = [0, 1, 2]
    why = {}
    for _ in range(3):                                                 # drop, refit
        coef = np.zeros(3)
        model = avar.copy()
        for _ in range(8):                                             # IRLS
            w = np.sqrt(dof / 2) / np.maximum(model, floor)           # 1/SE of each σ̂²
            c, _ = nnls(X[:, keep] * w[:, None], avar * w)
            coef[:] = 0.0
            coef[keep] = c
            model = X @ coef
        dropped = False
        for j in list(keep):
            share = X[:, j] * coef[j] / np.maximum(model, floor)
            dom = share > min_share
            span = np.log10(taus[dom].max() / taus[dom].min()) if dom.sum() > 1 else 0.0
            rel = _rel_se(dof, share, dom)
            if coef[j] <= 0 or span < min_decades or rel > max_rel_se:
                keep.remove(j)
                why[FIT_TERMS[j]] = (
                    f"not detected: no share of the Allan variance within the record's "
                    f"τ ≤ {taus[-1]:.3g} s (too small to matter there, or absent)"
                    if coef[j] <= 0 else
                    f"never dominates within the record's τ ≤ {taus[-1]:.3g} s (a longer "
                    "record would be needed, or the term is too small to matter)"
                    if not dom.any() else
                    f"dominates over only {span:.2g} decade(s) of τ (needs {min_decades:g}): "
                    "the record is too short to determine it"
                    if span < min_decades else
                    f"too uncertain (±{100 * rel:.0f} %)")
                dropped = True
        if not dropped:
            break
    terms = {}
    for j, name in enumerate(FIT_TERMS):
        if j in keep and coef[j] > 0:
            share = X[:, j] * coef[j] / model
            dom = share > min_share
            value = float(np.sqrt(coef[j]))
            terms[name] = {"value": value, "se": value * _rel_se(dof, share, dom),
                           "tau_range": (float(taus[dom].min()), float(taus[dom].max()))}
        else:
            terms[name] = {"value": None, "why": why.get(name, "not present in the record")}
    return {"taus": taus, "avar": avar, "adev_axes": np.asarray(adev).reshape(len(taus), -1),
            "dof": dof, "terms": terms, "model": np.sqrt(X @ coef), "samples": n, "rate": rate}


#: The largest spread of a static record's one-second means (SI): a sensor at rest drifts
#: far less (bias instability, random walk, temperature), any motion far more.
STATIC_SPREAD = {"gyro": np.radians(2.0), "accel": 0.5}

#: Fewest samples an Allan fit takes.
MIN_SAMPLES = 100


def check_static(x: FloatArray, rate: float, triad: str, what: str = "the record") -> None:
    """Refuse a record that is not at rest: the means of one-second blocks (at least 10
    samples) of each axis must stay within :data:`STATIC_SPREAD` of each other.

    Parameters
    ----------
    x : ndarray, shape (n, 3)
        Rate samples.
    rate : float
        Hz.
    triad : {"gyro", "accel"}
    what : str
        How the message names the record.

    Raises
    ------
    ImunavError
        Naming the triad, the axis, the spread and the limit.
    """
    x = np.asarray(x, float)
    block = max(10, int(round(rate)))
    nb = x.shape[0] // block
    if nb < 2:
        return
    means = x[:nb * block].reshape(nb, block, -1).mean(axis=1)
    spread = means.max(axis=0) - means.min(axis=0)
    axis = int(np.argmax(spread))
    limit = STATIC_SPREAD[triad]
    if spread[axis] > limit:
        unit, scale = ("°/s", np.degrees(1.0)) if triad == "gyro" else ("m/s²", 1.0)
        raise ImunavError(
            f"{what} is not a static record: the {triad}'s {block / rate:.3g}-s means on axis "
            f"{'xyz'[axis] if axis < 3 else axis} vary by {spread[axis] * scale:.3g} {unit} (a "
            f"sensor at rest, less than {limit * scale:g} {unit}); an Allan fit needs the IMU "
            "at rest for the whole record")


def allan_fits(signals, what: str = "the record") -> dict:
    """The Allan fits of a static record's gyro and accelerometer (:func:`fit_allan`), after
    checking that it is one (:func:`check_static`) and long enough.

    Parameters
    ----------
    signals : ImuSignals
        Rate samples.
    what : str
        How messages name the record (its file).

    Returns
    -------
    dict
        ``{"gyro": fit, "accel": fit}``.

    Raises
    ------
    ImunavError
        For too few samples, or a record that is not static.
    """
    if len(signals) < MIN_SAMPLES:
        raise ImunavError(f"{what}: {len(signals)} samples are too few for an Allan deviation "
                          f"(at least {MIN_SAMPLES}: a static record of minutes to hours is "
                          "needed)")
    gyro, accel = signals.omega, signals.specific_force
    check_static(gyro, signals.rate, "gyro", what)
    check_static(accel, signals.rate, "accel", what)
    return {"gyro": fit_allan(gyro, signals.rate), "accel": fit_allan(accel, signals.rate)}
