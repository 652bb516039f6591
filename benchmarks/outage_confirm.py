"""Confirm ``design --find outage`` by a Monte Carlo of the real EKF (issues 29 and 38).

``imunav design --aiding … --find outage`` answers by the covariance analysis of the filter
along the true motion: the longest GNSS outage — from the last fix used to the next
(``max_outage_s = next_fix_s − last_fix_s``) — through which the probability that the 3-D
position error stays within the tolerance at *every* epoch is at least 95 %
(``p_within_whole_outage``, :mod:`imunav.analysis.crossing`). This script takes its answer
and runs the real filter (:func:`imunav.analysis.aided_montecarlo.aided_monte_carlo`) on
simulated sensors with the fixes of that outage lost — and of the outage one GNSS interval
longer (the same runs: the filter is causal, so until the next fix the two are the same) —
and counts the runs whose error stays within the tolerance at every covariance epoch of the
outage.

**Confirmed** when the covariance's probability lies inside the Monte Carlo's 95 %
Clopper–Pearson interval (:func:`imunav.analysis.assessment.runs_interval`), for the outage
found and for the one a GNSS interval longer. The 95th percentile at the outage's end is
printed beside with its 95 % order-statistic interval
(:func:`imunav.analysis.aided_assessment.quantile_interval`). The run count sets the width of
those intervals; the script says what they can and cannot resolve.

Each probability is split in its two parts, each with its interval: within the tolerance at
the outage's last epoch (what the covariance gives exactly, its marginal), and within there
but outside at an earlier epoch (what the whole outage adds: the joint law over the epochs,
:mod:`imunav.analysis.crossing`'s part). A disagreement in the first is the linear covariance
analysis's against the EKF (the runs' mean error at the end, printed, is one the linear
analysis cannot have); in the second, the crossing computation's.

The drive is cut one GNSS interval after the longer outage's next fix.

Usage::

    python benchmarks/outage_confirm.py [--imu BMI088] [--rate 100] [--tolerance 10]
        [--runs 1000] [--seed 0] [--outage-start S] [--out outage_confirm.json]

Exit 1 if the Monte Carlo does not confirm the probabilities.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

from imunav.analysis.aided_assessment import (
    aided_covariance,
    gnss_times,
    quantile_interval,
    replace_outages,
    runs_within,
)
from imunav.analysis.aided_montecarlo import aided_monte_carlo
from imunav.analysis.assessment import runs_interval
from imunav.analysis.crossing import walk
from imunav.analysis.gaussnorm import norm_quantile
from imunav.analysis.outage import baseline_states, find_outage
from imunav.io.files import load_motion
from imunav.sensors.aids import AidingConfig
from imunav.sensors.models import ImuModel

HERE = Path(__file__).resolve().parent


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--motion", default=str(HERE.parent / "examples" / "drive.toml"))
    ap.add_argument("--aiding", default=str(HERE.parent / "examples" / "drive_aiding.toml"))
    ap.add_argument("--imu", default="BMI088")
    ap.add_argument("--rate", type=float, default=100.0)
    ap.add_argument("--tolerance", type=float, default=10.0)
    ap.add_argument("--runs", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--outage-start", type=float, default=None)
    ap.add_argument("--out", default=None)
    a = ap.parse_args(argv)
    motion = load_motion(a.motion)[0]
    aiding = AidingConfig.from_toml(a.aiding)
    imu = ImuModel.load(a.imu)
    tol = a.tolerance
    t0 = time.perf_counter()
    at = aided_covariance(motion, imu, aiding, a.rate, terms=True)
    f = find_outage(motion, imu, aiding, a.rate, tol, at=at, start=a.outage_start, budget=False)
    t_cov = time.perf_counter() - t0
    last, nxt, L = f["last_fix_s"], f["next_fix_s"], f["max_outage_s"]
    print(f"covariance ({t_cov:.1f} s): max_outage_s = {L:g} s, from the last fix at {last:g} s "
          f"to the next at {nxt:g} s; within {tol:g} m at every epoch with probability "
          f"{100 * f['p_within_whole_outage']:.2f} % (± "
          f"{100 * f['p_within_whole_outage_se']:.2f} %, sampled), p95 "
          f"{f['position_p95_end_m']:.3g} m at t = {f['t_end_s']:g} s", flush=True)
    if L <= 0 or f["limited_by_motion"]:
        print("nothing to confirm (no outage bridged, or cut by the end of the motion)")
        return 0
    dt = f["gnss_interval_s"]
    tg = gnss_times(at)
    longer = nxt + dt
    # the covariance's probability of the outage one interval longer: the same walk, further
    e0 = int(np.searchsorted(at.t, last - 1e-9))
    (w,) = walk(at, [e0], baseline_states(at, [e0]), tol,
                stops=[int(np.searchsorted(at.t, longer - 1e-9)) - 1], seed=a.seed + 2)
    (p_long,), (se_long,) = w.p_within([longer])
    lost = tg[(tg > last + 1e-9) & (tg < longer - 1e-9)]
    one = replace_outages(aiding, [(float(lost[0]), float(lost[-1]))])
    duration = min(float(at.t[-1]), longer + dt)
    times = at.t[(at.t >= last - 1e-9) & (at.t < longer - 1e-9)]
    t0 = time.perf_counter()
    mc = aided_monte_carlo(motion, imu, one, a.rate, duration, a.runs, seed=a.seed,
                           times=times, progress=True)
    t_mc = time.perf_counter() - t0
    assert np.allclose(mc.t, times, atol=0.5 / a.rate)
    norms = np.linalg.norm(mc.position_error, axis=-1)
    horiz = np.linalg.norm(mc.position_error[..., :2], axis=-1)
    rows = []
    for label, until, p_cov, se_cov in (("found", nxt, f["p_within_whole_outage"],
                                          f["p_within_whole_outage_se"]),
                                         ("one interval longer", longer, float(p_long),
                                          float(se_long))):
        window = times < until - 1e-9
        inside, n = runs_within(norms, window, tol)
        lo, hi = runs_interval(inside, n)
        inside_h, _ = runs_within(horiz, window, tol)
        end = int(np.nonzero(window)[0][-1])
        q_lo, q_hi = quantile_interval(norms[:, end])
        p95_mc = float(np.percentile(norms[:, end], 95))
        k_end = w.epochs(until) - 1
        p95_cov = float(norm_quantile(w.cov[k_end], 0.95))
        # the two parts of the probability: inside at the outage's last epoch (the marginal,
        # exact from the covariance), and inside there but outside at an earlier epoch (what
        # the whole outage adds: the joint law)
        at_end = int(np.count_nonzero(norms[:, end] <= tol))
        e_lo, e_hi = runs_interval(at_end, n)
        back = at_end - inside
        b_lo, b_hi = runs_interval(back, n)
        marg_cov = float(w.marginal()[k_end])
        mean = mc.position_error[:, end].mean(axis=0)
        mean_se = mc.position_error[:, end].std(axis=0, ddof=1) / np.sqrt(n)
        rows.append({"outage": label, "last_fix_s": last, "next_fix_s": float(until),
                     "max_outage_s": float(until - last),
                     "covariance_p_within_whole_outage": p_cov,
                     "covariance_p_within_whole_outage_se": se_cov,
                     "montecarlo_p_within_whole_outage": inside / n,
                     "montecarlo_interval": [lo, hi],
                     "montecarlo_p_within_whole_outage_horizontal": inside_h / n,
                     "montecarlo_inside_at_end": at_end / n,
                     "montecarlo_inside_at_end_interval": [e_lo, e_hi],
                     "covariance_inside_at_end": marg_cov,
                     "montecarlo_inside_at_end_outside_before": back / n,
                     "montecarlo_inside_at_end_outside_before_interval": [b_lo, b_hi],
                     "covariance_inside_at_end_outside_before": marg_cov - p_cov,
                     "montecarlo_mean_error_end_m": mean.tolist(),
                     "montecarlo_mean_error_end_se_m": mean_se.tolist(),
                     "t_end_s": float(times[end]), "covariance_p95_end_m": p95_cov,
                     "montecarlo_p95_end_m": p95_mc, "montecarlo_p95_end_interval_m": [q_lo, q_hi],
                     "confirmed": bool(lo <= p_cov <= hi)})
    print(f"Monte Carlo of the EKF ({a.runs} runs, {t_mc:.0f} s, load {os.getloadavg()[0]:.2f}; "
          f"fixes {lost[0]:g}–{lost[-1]:g} s lost; gate rejections {mc.rejected}):")
    for r in rows:
        lo, hi = r["montecarlo_interval"]
        q_lo, q_hi = r["montecarlo_p95_end_interval_m"]
        print(f"  outage {r['outage']} ({r['last_fix_s']:g} → {r['next_fix_s']:g} s, "
              f"{r['max_outage_s']:g} s): {100 * r['montecarlo_p_within_whole_outage']:.1f} % of "
              f"the runs within {tol:g} m at every epoch [{100 * lo:.1f}–{100 * hi:.1f} %, 95 % "
              f"Clopper–Pearson]; covariance {100 * r['covariance_p_within_whole_outage']:.1f} % "
              f"— {'CONFIRMED (inside' if r['confirmed'] else 'NOT CONFIRMED (outside'} the "
              f"interval); "
              f"horizontal {100 * r['montecarlo_p_within_whole_outage_horizontal']:.1f} %")
        e_lo, e_hi = r["montecarlo_inside_at_end_interval"]
        b_lo, b_hi = r["montecarlo_inside_at_end_outside_before_interval"]
        print(f"    its parts: within at its last epoch (t = {r['t_end_s']:g} s) "
              f"{100 * r['montecarlo_inside_at_end']:.1f} % [{100 * e_lo:.1f}–{100 * e_hi:.1f} %]"
              f", covariance {100 * r['covariance_inside_at_end']:.1f} % (exact); within there "
              f"but not at an earlier epoch {100 * r['montecarlo_inside_at_end_outside_before']:.1f}"
              f" % [{100 * b_lo:.1f}–{100 * b_hi:.1f} %], covariance "
              f"{100 * r['covariance_inside_at_end_outside_before']:.1f} %")
        print(f"    p95 at t = {r['t_end_s']:g} s: Monte Carlo {r['montecarlo_p95_end_m']:.3g} m "
              f"[{q_lo:.3g}–{q_hi:.3g} m, 95 % order statistics], covariance "
              f"{r['covariance_p95_end_m']:.3g} m; the runs' mean error there (N, E, D) "
              + ", ".join(f"{m_:.2f} ± {s_:.2f}" for m_, s_ in zip(
                  r["montecarlo_mean_error_end_m"], r["montecarlo_mean_error_end_se_m"],
                  strict=True))
              + " m (the linear covariance's is zero)")
    half = max((r["montecarlo_interval"][1] - r["montecarlo_interval"][0]) / 2 for r in rows)
    margin = abs(f["p_within_whole_outage"] - f["level"])
    enough = half < 0.05
    print(f"  With {a.runs} runs the intervals reach ± {100 * half:.1f} %: "
          + ("narrower than the 5 % the verdict leaves outside, so they tell the covariance's "
             "probability from one off by more than that" if enough else
             "wider than the 5 % the verdict leaves outside: too few runs to confirm it")
          + ("" if half < margin else
             f"; not which side of {100 * f['level']:g} % a probability {100 * margin:.1f} % "
             f"from it falls on — the covariance's own sampling error "
             f"(± {100 * f['p_within_whole_outage_se']:.2f} %) is what decides that") + ".")
    ok = enough and all(r["confirmed"] for r in rows)
    if a.out:
        Path(a.out).write_text(json.dumps({
            "command": "python benchmarks/outage_confirm.py " + " ".join(
                sys.argv[1:] if argv is None else argv),
            "imu": a.imu, "rate_hz": a.rate, "tolerance_m": tol, "runs": a.runs,
            "seed": a.seed, "max_outage_s": L, "last_fix_s": last, "next_fix_s": nxt,
            "outage_start_s": f["outage_start_s"], "gnss_outage_s": f["gnss_outage_s"],
            "p_within_whole_outage": f["p_within_whole_outage"],
            "p_within_whole_outage_se": f["p_within_whole_outage_se"],
            "position_p95_end_m": f["position_p95_end_m"], "interval": "Clopper-Pearson 95 %",
            "quantile_interval": "order statistics 95 %", "outages": rows,
            "rejected_readings": mc.rejected, "seconds_covariance": t_cov,
            "seconds_montecarlo": t_mc, "load_average_1min": os.getloadavg()[0],
            "confirmed": ok}, indent=2, ensure_ascii=False) + "\n")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
