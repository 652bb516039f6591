"""Can it bridge the outage? The aided verdict, by the covariance analysis of the filter along
the true motion and by Monte Carlo of the real filter.

:func:`assess_aided` answers "with these aids, does this IMU keep the tolerance through every
GNSS outage of the motion?" by the covariance analysis of the aided filter linearised along the
true motion (:class:`~imunav.analysis.aided_covariance.AlongTruth`: the filter's gains, and the
*true* error covariance those gains leave when the filter's model differs from the simulation's —
a correlated GNSS error treated as white), and with ``runs`` by a Monte Carlo of the real EKF
(:func:`~imunav.analysis.aided_montecarlo.aided_monte_carlo`). :func:`outage_budget` splits the
error at an outage's end by its sources (the true covariance is linear in them). The aided
counterpart of :mod:`imunav.analysis.assessment`; the outage search is
:mod:`imunav.analysis.outage`, the aided design :mod:`imunav.analysis.aided_design`.

The outage of a scenario is ``[start, end]``, fixes at ``start ≤ t ≤ end`` left out (the
convention of ``[gnss] outages``); its ``position_p95_max_m`` is the largest 95th percentile of
the position-error norm at the covariance epochs from ``start`` until the first fix used after
``end`` (excluded: the error grows until that fix), and ``position_p95_end_m`` the value at the
last of them (``t_end_s``, one covariance step before that fix). On the rotating Earth the
position errors are those of local NED at the true position (metres).

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.estimation``,
``imunav.analysis``.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from imunav.analysis.aided_covariance import AlongTruth
from imunav.analysis.aided_montecarlo import aided_monte_carlo
from imunav.analysis.covariance import ENVELOPE_POINTS, envelope_index
from imunav.analysis.gaussnorm import norm_quantile
from imunav.core.constants import G0
from imunav.core.kernels import FloatArray
from imunav.core.layout import DP, PHI
from imunav.core.validation import ImunavError, check_positive
from imunav.motion.base import BaseMotion
from imunav.sensors.aids import AidingConfig
from imunav.sensors.models import ImuModel
from imunav.sensors.simulate import interval_count

__all__ = ["ATTITUDE_VALID", "P95", "active_fixes", "aided_covariance", "aided_span",
           "assess_aided", "file_outages", "format_aided_verdict", "gnss_times",
           "no_fix_warnings", "outage_budget", "outage_p95", "outage_pass", "outage_windows",
           "per_outage", "replace_outages"]


P95 = 0.95

#: p95 attitude error (rad) beyond which the linearised filter is flagged. A coarse flag: a
#: yaw not yet observed before the first accelerations reaches 0.4 rad with a BMI088 on the
#: example drive while the covariance still matches the EKF's Monte Carlo; with an MPU-6050's
#: 20 °/s turn-on bias it reaches 2.6 rad and the real filter diverges.
ATTITUDE_VALID = 0.5

def aided_span(motion: BaseMotion, rate: float, duration: float | None) -> float:
    if duration is None:
        duration = getattr(motion, "duration", None)
        if duration is None:
            raise ImunavError("this motion has no duration of its own: give duration",
                              argument="duration")
    duration = check_positive(duration, "duration")
    return interval_count(rate, duration) / rate


def file_outages(aiding: AidingConfig) -> list[tuple[float, float]]:
    return list(aiding.gnss.outages) if aiding.gnss is not None else []


def aided_covariance(motion: BaseMotion, imu: ImuModel, aiding: AidingConfig, rate: float,
                     duration: float | None = None, *, kind: str = "increments",
                     covariance_step: float = 0.1, algorithm: str | None = None,
                     g: float = G0, terms: bool = False,
                     measurements: list | None = None) -> AlongTruth:
    """The aided filter linearised along the true motion (built once; passes are cheap).

    Parameters
    ----------
    motion, imu, aiding, rate
        The truth, the IMU (simulated and assumed), the aids, the IMU rate (Hz).
    duration : float, optional
        Seconds (default the motion's own).
    kind, covariance_step, algorithm, g, terms, measurements
        As :class:`~imunav.analysis.aided_covariance.AlongTruth` (``measurements``: a user's
        own aids, their models and reading times).

    Returns
    -------
    AlongTruth
    """
    duration = aided_span(motion, rate, duration)
    at = AlongTruth(motion, imu, aiding, rate, duration, kind=kind,
                    covariance_step=covariance_step, algorithm=algorithm, g=g, terms=terms,
                    measurements=measurements)
    at.warnings += imu.missing_term_warnings()        # issue 38: no bias instability, say so
    return at


def gnss_times(at: AlongTruth) -> FloatArray:
    return np.array([r.t for rs in at.readings for r in rs if r.sensor == "gnss"])


def no_fix_warnings(at: AlongTruth, outages: list[tuple[float, float]]) -> list[str]:
    """A warning when the GNSS outages leave no fix in the record (an aided answer that is
    then the other aids' alone, which a reader of "GNSS outage 0–20 s" would not guess).

    Parameters
    ----------
    at : AlongTruth
    outages : list of (float, float)

    Returns
    -------
    list of str
        Empty, or the one warning.
    """
    tg = gnss_times(at)
    if tg.size and not active_fixes(at, [outages])[0].any():
        return ["the GNSS outages cover every fix of the record: GNSS helps nowhere, the "
                "answer is that of the other aids alone"]
    return []


def active_fixes(at: AlongTruth, outages: list[list[tuple[float, float]]]) -> np.ndarray:
    """Per scenario (a list of outages), which GNSS fixes are used."""
    tg = gnss_times(at)
    act = np.ones((len(outages), tg.size), dtype=bool)
    for b, outs in enumerate(outages):
        for t0, t1 in outs:
            act[b] &= ~((tg >= t0 - 1e-9) & (tg <= t1 + 1e-9))
    return act


def outage_p95(at: AlongTruth, outages: list[tuple[float, float]], *, imu_scale: float = 1.0
               ) -> tuple[FloatArray, FloatArray, FloatArray, list[dict]]:
    """One covariance pass with these outages: the p95 position error at every epoch, the
    filter's own p95 beside it, and each outage's largest p95.

    Parameters
    ----------
    at : AlongTruth
    outages : list of (float, float)
        GNSS outages (s), replacing the aiding file's.
    imu_scale : float
        Every IMU term times this.

    Returns
    -------
    t : ndarray, shape (E + 1,)
    truth_p95, filter_p95 : ndarray, shape (E + 1,)
        95th percentile of the position-error norm (m): the true error and the filter's belief
        (after each epoch's readings).
    per_outage : list of dict
        ``{"start", "end", "position_p95_max_m", "position_p95_end_m"}``.
    """
    return outage_pass(at, outages, imu_scale)[:4]


def outage_pass(at: AlongTruth, outages, imu_scale: float = 1.0):
    """:func:`outage_p95` and the true attitude error's p95 at every epoch."""
    wf, wt, _ = at.weights(imu_scale)
    act = active_fixes(at, [outages])
    res = at.propagate(wf, wt, act)
    truth = norm_quantile(res.truth_post[0, 0][:, DP, DP], P95)
    filt = norm_quantile(res.filter_post[0][:, DP, DP], P95)
    att = norm_quantile(res.truth_post[0, 0][:, PHI, PHI], P95)
    return res.t, truth, filt, per_outage(res.t, truth, outages,
                                           outage_windows(at, outages, act[0])), att


def outage_windows(at: AlongTruth, outages, active: np.ndarray) -> list[np.ndarray]:
    """Per outage, its epochs: from its start until the next fix used (that one excluded —
    the error grows until the fix after the outage, not only until the outage's end), or the
    end of the motion."""
    tg = gnss_times(at)
    used = tg[active]
    t = at.t
    out = []
    for t0, t1 in outages:
        nxt = used[used > t1 + 1e-9]
        stop = nxt[0] - 1e-9 if nxt.size else t[-1] + 1e-9
        out.append((t >= t0 - 1e-9) & (t < stop))
    return out


def per_outage(t: FloatArray, p95: FloatArray, outages, windows) -> list[dict]:
    out = []
    for (t0, t1), inside in zip(outages, windows, strict=True):
        if not inside.any():
            continue
        end = int(np.nonzero(inside)[0][-1])
        out.append({"start": float(t0), "end": float(t1),
                    "position_p95_max_m": float(p95[inside].max()),
                    "position_p95_end_m": float(p95[end]), "t_end_s": float(t[end])})
    return out


# ----------------------------------------------------------------------------- Monte Carlo

def outage_budget(at: AlongTruth, outages: list[tuple[float, float]], at_time: float,
                  *, imu_scale: float = 1.0) -> dict[str, float]:
    """Which source eats the tolerance: the p95 position error at ``at_time`` of each source of
    the true error alone (an IMU term, an aid's noise or states, the initial uncertainty),
    the filter's gains those of all of them (the true covariance is their sum).

    Parameters
    ----------
    at : AlongTruth
        Built with ``terms=True`` for one row per IMU term (else one ``"imu"`` row).
    outages : list of (float, float)
    at_time : float
        Seconds (the epoch at or before it).
    imu_scale : float

    Returns
    -------
    dict
        ``{source: p95 (m)}``, largest first (sources that contribute nothing left out).
    """
    e = int(np.searchsorted(at.t, at_time + 1e-9)) - 1
    e = max(0, min(e, at.t.size - 1))
    wf, wt, names = at.weights(imu_scale, split=True)
    res = at.propagate(wf, wt, active_fixes(at, [outages]), stop=e, keep=False)
    P = res.final[0, 1:, :, :]
    q = norm_quantile(P[:, DP, DP], P95)
    out = {nm: float(v) for nm, v in zip(names, q, strict=True) if v > 0}
    return dict(sorted(out.items(), key=lambda kv: -kv[1]))


# ----------------------------------------------------------------------------- assess

def assess_aided(motion: BaseMotion, imu: ImuModel, aiding: AidingConfig, rate: float,
                 tolerance: float, duration: float | None = None, *, runs: int | None = None,
                 seed: int = 0, scheduler: str | None = None, kind: str = "increments",
                 covariance_step: float = 0.1, algorithm: str | None = None,
                 budget: bool = True, progress: bool = True, g: float = G0,
                 measurements: list | None = None) -> dict:
    """The aided verdict: does the tolerance hold through every GNSS outage of ``aiding``?

    By the covariance analysis of the filter along the true motion (the true error covariance,
    the model mismatch included); with ``runs`` by a Monte Carlo of the real filter too (its
    numbers then make the verdict, the covariance's stand beside them).

    Parameters
    ----------
    motion, imu, aiding, rate
    tolerance : float
        Position (m), 95th percentile of the error norm.
    duration : float, optional
    runs : int, optional
        Monte Carlo runs of the EKF.
    seed, scheduler
        Of the Monte Carlo.
    kind, covariance_step, algorithm, g
        As :class:`~imunav.analysis.aided_covariance.AlongTruth`.
    measurements : list of Aid, optional
        A user's own aids (any :class:`~imunav.estimation.measurements.Measurement` with its
        reading times; the Monte Carlo simulates their readings).
    budget : bool
        The error budget per source at the worst outage's end.
    progress : bool

    Returns
    -------
    dict
        The JSON of ``imunav assess --aiding``: ``method``, ``suitable``,
        ``max_p95_position_m``, ``final_p95_position_m``, ``envelope`` (``t``,
        ``position_p95_m``, ``filter_position_p95_m``), ``outages`` (``start``, ``end``,
        ``position_p95_max_m``, with a Monte Carlo ``covariance_p95_max_m`` and the end values),
        ``error_budget``, ``warnings``.
    """
    tolerance = check_positive(tolerance, "tolerance")
    duration = aided_span(motion, rate, duration)
    if aiding.gnss is not None:
        aiding.gnss.check_within(0.0, duration)
    at = aided_covariance(motion, imu, aiding, rate, duration, kind=kind,
                          covariance_step=covariance_step, algorithm=algorithm, g=g,
                          terms=budget, measurements=measurements)
    outs = file_outages(aiding)
    t, truth, filt, per, att = outage_pass(at, outs)
    warnings = list(at.warnings) + no_fix_warnings(at, outs)
    if att.max() > ATTITUDE_VALID:
        i = int(np.argmax(att))
        warnings.append(f"the attitude error reaches a p95 of {att[i]:.3g} rad at t = "
                        f"{t[i]:.4g} s: beyond the filter's linearisation (the real EKF may "
                        "diverge where the covariance does not); check with --runs")
    r: dict = {"motion": motion.name, "earth": motion.frame, "imu": imu.name,
               "rate_hz": float(rate),
               "tolerance_m": tolerance, "aiding": list(aiding.sensors),
               "method": "covariance", "runs": None, "seed": None,
               "max_p95_attitude_rad": float(att.max())}
    p95 = truth
    if runs is not None:
        mc = aided_monte_carlo(motion, imu, aiding, rate, duration, runs, seed=seed, times=t,
                               algorithm=algorithm, covariance_step=covariance_step,
                               scheduler=scheduler, progress=progress, g=g,
                               measurements=measurements)
        p95 = mc.p95()
        mper = per_outage(t, p95, outs, outage_windows(at, outs, active_fixes(at, [outs])[0]))
        for o, c in zip(mper, per, strict=True):
            o["covariance_p95_max_m"] = c["position_p95_max_m"]
            o["covariance_p95_end_m"] = c["position_p95_end_m"]
        per = mper
        r.update(method="montecarlo", runs=int(runs), seed=int(seed),
                 rejected_readings=mc.rejected)
    for o in per:
        o["within_tolerance"] = bool(o["position_p95_max_m"] <= tolerance)
    over = np.nonzero(p95 > tolerance)[0]
    worst = int(np.argmax(p95))
    r.update({
        "suitable": bool(over.size == 0),
        "outages_within_tolerance": bool(all(o["within_tolerance"] for o in per)),
        "time_p95_exceeds_s": float(t[over[0]]) if over.size else None,
        "max_p95_position_m": float(p95[worst]), "time_max_p95_s": float(t[worst]),
        "final_p95_position_m": float(p95[-1]),
        "outages": per,
    })
    if budget:
        # at the end of the worst outage (else at the worst time)
        when = max(per, key=lambda o: o["position_p95_max_m"])["t_end_s"] if per else t[worst]
        r["error_budget_at_s"] = float(when)
        r["error_budget"] = outage_budget(at, outs, when)
    idx = envelope_index(t.size, ENVELOPE_POINTS)
    r["envelope"] = {"t": t[idx].tolist(), "position_p95_m": p95[idx].tolist(),
                     "filter_position_p95_m": filt[idx].tolist()}
    if runs is not None:
        r["envelope"]["covariance_position_p95_m"] = truth[idx].tolist()
    if np.any(filt < 0.8 * truth):
        i = int(np.argmax(truth / np.maximum(filt, 1e-300)))
        warnings.append(f"the filter believes its position better than it is (p95 "
                        f"{filt[i]:.3g} m believed, {truth[i]:.3g} m true at t = {t[i]:.4g} s): "
                        "its model differs from the sensors'")
    r["warnings"] = warnings
    return r


def format_aided_verdict(r: dict) -> str:
    """The aided verdict as text (what ``imunav assess --aiding`` prints).

    Parameters
    ----------
    r : dict
        :func:`assess_aided`'s result.

    Returns
    -------
    str
    """
    how = ("covariance analysis of the filter" if r["method"] == "covariance" else
           f"Monte Carlo of the filter, {r['runs']} runs")
    where = (" on the rotating WGS-84 Earth" if r.get("earth") == "wgs84" else
             " (flat frame)")
    lines = [f"Aided verdict for motion {r['motion']}{where}, IMU {r['imu']} at "
             f"{r['rate_hz']:g} Hz "
             f"with {', '.join(r['aiding'])} ({how}), tolerance {r['tolerance_m']:g} m "
             "(95th percentile of the position error):",
             f"  {'SUITABLE' if r['suitable'] else 'NOT SUITABLE'}: largest p95 "
             f"{r['max_p95_position_m']:.3g} m at t = {r['time_max_p95_s']:.4g} s, final "
             f"{r['final_p95_position_m']:.3g} m."]
    for o in r["outages"]:
        extra = (f" (covariance {o['covariance_p95_max_m']:.3g} m)"
                 if "covariance_p95_max_m" in o else "")
        lines.append(f"  GNSS outage {o['start']:g}–{o['end']:g} s: p95 up to "
                     f"{o['position_p95_max_m']:.3g} m{extra} — "
                     + ("within" if o["within_tolerance"] else "BEYOND") + " the tolerance")
    if r.get("error_budget"):
        lines.append(f"  Error budget at t = {r['error_budget_at_s']:.4g} s (p95 of each "
                     "source alone):")
        for k, v in list(r["error_budget"].items())[:8]:
            lines.append(f"    {k:28s} {v:10.3g} m")
    for w in r["warnings"]:
        lines.append(f"  warning: {w}.")
    return "\n".join(lines)


# ----------------------------------------------------------------------------- design

def replace_outages(aiding: AidingConfig, outages) -> AidingConfig:
    """``aiding`` with other GNSS outages."""
    return aiding.replace(gnss=dataclasses.replace(aiding.gnss, outages=tuple(outages)))
