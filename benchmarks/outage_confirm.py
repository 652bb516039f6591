"""Confirm ``max_outage_s`` by a Monte Carlo of the real EKF (issue 29).

``imunav design --aiding … --find outage`` answers by the covariance analysis of the filter
along the true motion. This script takes its answer — the longest GNSS outage, its start — and
runs the real filter (:func:`imunav.analysis.outage.aided_monte_carlo`) on simulated sensors
with exactly that outage: the 95th percentile of the position error just before the first fix
after the outage must be within 15 % of the tolerance (the outage is the longest within it, so
its p95 sits just below the tolerance). The drive is cut one GNSS interval after the outage's
end (the filter is causal: what comes later does not change it).

Usage::

    python benchmarks/outage_confirm.py [--imu ADIS16470] [--rate 100] [--tolerance 10]
        [--runs 200] [--outage-start S] [--out outage_confirm.json]

Exit 1 if the Monte Carlo disagrees by more than 15 % of the tolerance.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import sys
import time
from pathlib import Path

import numpy as np

from imunav.analysis.aided_assessment import aided_covariance
from imunav.analysis.aided_montecarlo import aided_monte_carlo
from imunav.analysis.outage import find_outage
from imunav.io.files import load_motion
from imunav.sensors.aids import AidingConfig
from imunav.sensors.models import ImuModel

HERE = Path(__file__).resolve().parent


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--motion", default=str(HERE.parent / "examples" / "drive.toml"))
    ap.add_argument("--aiding", default=str(HERE.parent / "examples" / "drive_aiding.toml"))
    ap.add_argument("--imu", default="ADIS16470")
    ap.add_argument("--rate", type=float, default=100.0)
    ap.add_argument("--tolerance", type=float, default=10.0)
    ap.add_argument("--runs", type=int, default=200)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--outage-start", type=float, default=None)
    ap.add_argument("--out", default=None)
    a = ap.parse_args(argv)
    motion = load_motion(a.motion)[0]
    aiding = AidingConfig.from_toml(a.aiding)
    imu = ImuModel.load(a.imu)
    t0 = time.perf_counter()
    at = aided_covariance(motion, imu, aiding, a.rate)
    f = find_outage(motion, imu, aiding, a.rate, a.tolerance, at=at, start=a.outage_start,
                    budget=False)
    t_cov = time.perf_counter() - t0
    s, L = f["outage_start_s"], f["max_outage_s"]
    print(f"covariance ({t_cov:.1f} s): max_outage_s = {L:g} s from {s:g} s, p95 "
          f"{f['position_p95_end_m']:.3g} m at its end (tolerance {a.tolerance:g} m)", flush=True)
    if L <= 0 or f["limited_by_motion"]:
        print("nothing to confirm (no outage bridged, or cut by the end of the motion)")
        return 0
    dt = f["gnss_interval_s"]
    t_end = s + L + dt - 0.1                 # the last covariance epoch before the next fix
    one = dataclasses.replace(aiding, gnss=dataclasses.replace(aiding.gnss,
                                                               outages=((s, s + L),)))
    duration = min(float(at.t[-1]), s + L + 2 * dt)
    t0 = time.perf_counter()
    mc = aided_monte_carlo(motion, imu, one, a.rate, duration, a.runs, seed=a.seed,
                           times=np.array([t_end]), progress=True)
    t_mc = time.perf_counter() - t0
    p95 = float(mc.p95()[0])
    rel = abs(p95 - a.tolerance) / a.tolerance
    ok = rel <= 0.15
    print(f"Monte Carlo of the EKF ({a.runs} runs, {t_mc:.0f} s, load "
          f"{os.getloadavg()[0]:.2f}): p95 {p95:.3g} m at t = {t_end:g} s — "
          f"{100 * (p95 / a.tolerance - 1):+.1f} % of the tolerance "
          f"({'CONFIRMED' if ok else 'NOT CONFIRMED'}, within 15 %); gate rejections "
          f"{mc.rejected}")
    if a.out:
        Path(a.out).write_text(json.dumps({
            "command": "python benchmarks/outage_confirm.py " + " ".join(
                sys.argv[1:] if argv is None else argv),
            "imu": a.imu, "rate_hz": a.rate, "tolerance_m": a.tolerance, "runs": a.runs,
            "seed": a.seed, "max_outage_s": L, "outage_start_s": s,
            "covariance_p95_end_m": f["position_p95_end_m"], "montecarlo_p95_end_m": p95,
            "montecarlo_over_tolerance": p95 / a.tolerance, "t_end_s": t_end,
            "rejected_readings": mc.rejected, "seconds_covariance": t_cov,
            "seconds_montecarlo": t_mc, "load_average_1min": os.getloadavg()[0],
            "confirmed": ok}, indent=2) + "\n")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
