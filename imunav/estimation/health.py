"""Is the filter still listening? Each aid's health over a run, and the warnings that say when
the filter has stopped trusting its aids or its aids disagree with it.

Per aid: readings, readings used and gated (rejected by the χ² gate), the longest run of
consecutive rejections (readings and seconds), the re-admissions after a lock-out, the mean
normalised innovation squared (NIS) against its band, and the innovations' lag-1
autocorrelation against its band. A consistent filter's NIS is χ² with ``m`` degrees of freedom
(mean ``m``), its whitened innovations white; the bands here are two-sided at :data:`LEVEL`
(99 %, Bonferroni-corrected over an aid's components), so a consistent filter trips a band about
once in a hundred aids.

A ``warning:`` is given (and listed in :attr:`Health.warnings`) when:

- an aid loses more than :data:`MAX_REJECTED` of its readings to the gate (a consistent filter
  with the default gate, 0.9999, loses one in ten thousand);
- a run of rejections lasts longer than :data:`MAX_REJECTED_SECONDS`;
- the filter re-admitted a reading after a lock-out (the recovery policy of
  :func:`~imunav.estimation.filters.run_filter`: after ``recover`` consecutive rejections the
  next reading is used with the navigation covariance inflated until the reading is plausible);
- the mean NIS or the lag-1 autocorrelation leaves its band and is materially off: the mean NIS
  beyond :data:`NIS_RATIO` times its expectation (or below its inverse), an autocorrelation
  above :data:`MAX_LAG1` in magnitude (over thousands of readings a band alone would flag an
  inconsistency of a few per cent, which no answer depends on);
- and, with any of those, when the filter assumed an ideal IMU (no sensor-error states): the
  likely cause.

May import: ``imunav.core``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.stats import chi2, norm

__all__ = ["LEVEL", "MAX_LAG1", "MAX_REJECTED", "MAX_REJECTED_SECONDS", "NIS_RATIO", "Health",
           "assess_health"]

#: The two-sided level of the NIS and autocorrelation bands.
LEVEL = 0.99
#: Largest share of an aid's readings the gate may reject without a warning.
MAX_REJECTED = 0.01
#: Longest run of consecutive rejections (s) without a warning.
MAX_REJECTED_SECONDS = 5.0
#: How far the mean NIS may be from its expectation (a factor) before its band counts.
NIS_RATIO = 1.5
#: The smallest lag-1 autocorrelation of the whitened innovations that counts.
MAX_LAG1 = 0.5


@dataclass
class Health:
    """Each aid's health over a run and the warnings it raises.

    Attributes
    ----------
    aids : dict
        ``{aid: {"readings", "used", "gated", "gated_share", "longest_rejection_run",
        "longest_rejection_s", "readmitted", "dof", "mean_nis", "nis_band", "lag1",
        "lag1_band"}}`` (plain numbers: the JSON of ``imunav filter --report``).
    warnings : list of str
    """

    aids: dict = field(default_factory=dict)
    warnings: list = field(default_factory=list)

    def as_dict(self) -> dict:
        """The report (JSON-ready).

        Returns
        -------
        dict
            ``{"aids": …, "warnings": […]}``.
        """
        return {"aids": self.aids, "warnings": list(self.warnings)}


def _runs(rejected: np.ndarray, t: np.ndarray) -> tuple[int, float]:
    """The longest run of consecutive True and the time it spans (from its first to the next
    reading, or its last)."""
    best, best_s, i, n = 0, 0.0, 0, rejected.size
    while i < n:
        if rejected[i]:
            j = i
            while j < n and rejected[j]:
                j += 1
            end = t[j] if j < n else t[j - 1]
            if j - i > best or (j - i == best and end - t[i] > best_s):
                best, best_s = j - i, float(end - t[i])
            i = j
        else:
            i += 1
    return best, best_s


def assess_health(innovations: dict, readmitted: dict | None = None, *, ideal_imu: bool = False
                  ) -> Health:
    """The health of a run from its innovations.

    Parameters
    ----------
    innovations : dict
        ``{aid: Innovations}`` of one run.
    readmitted : dict, optional
        ``{aid: [(t, inflation), …]}``: the readings used after a lock-out.
    ideal_imu : bool
        The filter assumed an ideal IMU.

    Returns
    -------
    Health
    """
    out = Health()
    readmitted = readmitted or {}
    for name, inn in innovations.items():
        k = int(len(inn.t))
        dof = int(inn.innovation.shape[1]) if inn.innovation.ndim == 2 else 0
        acc = np.asarray(inn.accepted, dtype=bool)
        gated = int((~acc).sum())
        run, run_s = _runs(~acc, np.asarray(inn.t, float))
        back = readmitted.get(name, [])
        d = {"readings": k, "used": int(acc.sum()), "gated": gated,
             "gated_share": gated / k if k else 0.0, "longest_rejection_run": run,
             "longest_rejection_s": run_s, "readmitted": len(back), "dof": dof,
             "mean_nis": None, "nis_band": None, "lag1": None, "lag1_band": None}
        out.aids[name] = d
        if not k:
            out.warnings.append(f"{name}: configured but no reading fell inside the run (its "
                                "readings file is empty, or its times are outside the IMU's): "
                                "the filter ran without it")
            continue
        a = (1 - LEVEL) / 2
        lo, hi = chi2.ppf([a, 1 - a], dof * k) / k
        finite = np.isfinite(inn.nis)
        d["mean_nis"] = float(np.mean(inn.nis[finite])) if finite.any() else None
        d["nis_band"] = [float(lo), float(hi)]
        where = f"{name}"
        if gated / k > MAX_REJECTED:
            out.warnings.append(f"{where}: the χ² gate rejected {gated} of {k} readings "
                                f"({100 * gated / k:.3g} %): the readings disagree with the run "
                                "(check their frame, units and time stamps, the lever arm, the "
                                "IMU model)")
        if run_s > MAX_REJECTED_SECONDS:
            i = int(np.argmax(_starts(~acc, run)))
            out.warnings.append(f"{where}: {run} consecutive readings rejected over {run_s:.3g} "
                                f"s (from t = {inn.t[i]:.6g} s): the filter stopped listening")
        if back:
            t0, f0 = back[0]
            out.warnings.append(f"{where}: locked out {len(back)} time(s); each time the next "
                                f"reading was re-admitted with the covariance "
                                f"inflated (first at t = {t0:.6g} s, ×{f0:.3g})")
        m = d["mean_nis"]
        if m is not None and not lo <= m <= hi and not 1 / NIS_RATIO <= m / dof <= NIS_RATIO:
            word = "optimistic" if m > hi else "pessimistic"
            out.warnings.append(f"{where}: mean NIS {m:.3g} outside its "
                                f"{100 * LEVEL:g} % band [{lo:.3g}, {hi:.3g}] for {dof} "
                                f"component{'' if dof == 1 else 's'}: the filter is {word} "
                                "about this aid")
        used = int(acc.sum())
        if used >= 3:
            rho = np.asarray(inn.lag1(), float)
            z = norm.ppf(1 - (1 - LEVEL) / (2 * max(dof, 1)))
            band = float(z / np.sqrt(used))
            d["lag1"] = [None if not np.isfinite(r) else float(r) for r in rho]
            d["lag1_band"] = band
            worst = float(np.nanmax(np.abs(rho))) if np.isfinite(rho).any() else 0.0
            if worst > max(band, MAX_LAG1):
                out.warnings.append(f"{where}: its innovations are correlated from reading to "
                                    f"reading (lag-1 autocorrelation up to {worst:.3g}, band "
                                    f"±{band:.3g}): an error the filter models as white is not "
                                    "(a correlated GNSS error, a time offset)")
    if ideal_imu and out.warnings:
        out.warnings.append("the filter assumed an ideal IMU (no sensor-error states, its σ "
                            "only the aids'): give the IMU's model (imu=, --imu)")
    return out


def _starts(flags: np.ndarray, length: int) -> np.ndarray:
    """Where a run of ``length`` True starts (a boolean mask)."""
    n = flags.size
    out = np.zeros(n, dtype=bool)
    for i in range(n - length + 1):
        if flags[i:i + length].all() and (i == 0 or not flags[i - 1]):
            out[i] = True
    return out
