"""Full-size consistency of the aided filter (issue 28): Monte Carlo NEES of position, velocity
and attitude against the 95 % χ² band, and the whiteness of the innovations, on the three
scenarios of ``tests/test_estimation_filter.py`` and the GNSS-aided drive on the rotating
WGS-84 Earth of ``tests/test_estimation_filter_earth.py`` (``gnss_drive_wgs84``: the same drive
at 50° N, 30° E, 200 m) at full size (more runs, longer drives, the ADIS16470 preset beside the
test's MEMS model). The tests run the reduced version.

    .venv/bin/python benchmarks/aided_consistency.py [--runs 50] [--out results_aided.json]
        [--only gnss_drive_wgs84 …]   (the others' results already in --out are kept)
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "tests"))

from test_estimation_filter import IMU_TERMS, drive  # noqa: E402

from imunav.analysis.aided_montecarlo import filter_monte_carlo, nees_band  # noqa: E402
from imunav.motion.geodetic import EarthMotion  # noqa: E402
from imunav.sensors.aids import AidingConfig  # noqa: E402
from imunav.sensors.models import ImuModel  # noqa: E402

#: Where the wgs84 scenario drives (rad, rad, m), as tests/test_estimation_filter_earth.py.
ORIGIN = (np.radians(50.0), np.radians(30.0), 200.0)

SCENARIOS = {
    "gnss_drive": ({"gnss": {"rate": 1, "position_sigma": 1.5, "velocity_sigma": 0.1,
                             "lever_arm": [1.0, 0.2, -1.5]}}, 300.0, False),
    "gnss_drive_wgs84": ({"gnss": {"rate": 1, "position_sigma": 1.5, "velocity_sigma": 0.1,
                                   "lever_arm": [1.0, 0.2, -1.5]}}, 300.0, False),
    "gnss_outage_60s": ({"gnss": {"rate": 1, "position_sigma": 1.5, "correlated_sigma": 1.0,
                                  "correlation_time": 60.0, "outages": [[120.0, 180.0]]}},
                        300.0, True),
    "baro_heading_nhc": ({"baro": {"rate": 2, "sigma": 0.5, "bias_drift": 0.02},
                          "heading": {"rate": 1, "sigma": "1 deg"},
                          "nhc": {"sigma": 0.05, "rate": 2}}, 300.0, False),
}


def whiteness(innovations, runs):
    out = {}
    for name in innovations[0]:
        logs = [inn[name] for inn in innovations]
        k = float(np.mean([lg.accepted.sum() for lg in logs]))
        m = logs[0].innovation.shape[1]
        rho = np.mean([lg.lag1() for lg in logs], axis=0)
        nis = np.concatenate([lg.nis[lg.accepted] for lg in logs])
        out[name] = {"lag1_per_component": rho.tolist(), "lag1_expected": -1 / k,
                     "lag1_band_pooled": 1.96 / np.sqrt(k * m * runs),
                     "lag1_band_per_component": 1.96 / np.sqrt(k * runs),
                     "mean_nis": float(nis.mean()), "dof": m,
                     "rejected": int(sum((~lg.accepted).sum() for lg in logs))}
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=50)
    ap.add_argument("--imu", nargs="*", default=["test MEMS", "ADIS16470"])
    ap.add_argument("--out", default=str(HERE / "results_aided.json"))
    ap.add_argument("--only", nargs="*", choices=sorted(SCENARIOS),
                    help="run these scenarios only (keeping the others' results in --out)")
    a = ap.parse_args(argv)
    out = Path(a.out)
    results = json.loads(out.read_text()) if a.only and out.exists() else {}
    for imu_name in a.imu:
        imu = IMU_TERMS if imu_name == "test MEMS" else ImuModel.load(imu_name)
        for name, (cfg, duration, smooth) in SCENARIOS.items():
            if a.only and name not in a.only:
                continue
            t0 = time.perf_counter()
            motion = drive(duration)
            if name.endswith("_wgs84"):
                motion = EarthMotion(motion, ORIGIN)
            mc = filter_monte_carlo(motion, imu, AidingConfig.from_dict(cfg), 100.0,
                                    duration, a.runs, seed=3, smooth=smooth,
                                    algorithm="coning2")
            s = mc.summary()
            s["whiteness"] = whiteness(mc.innovations, a.runs)
            s["seconds"] = time.perf_counter() - t0
            if smooth:
                res = mc.results[0]
                t = res.t
                mid = int(np.argmin(abs(t - 150.0)))
                s["mid_outage_sd_pn"] = {"filter": float(res.sd[mid, 0]),
                                         "smoother": float(res.smoothed.sd[mid, 0])}
            key = f"{imu_name}/{name}"
            results[key] = s
            out.write_text(json.dumps(results, indent=1) + "\n")      # as each one lands
            lo, hi = nees_band(a.runs)
            print(f"{key}: {a.runs} runs, {duration:g} s, band [{lo:.3f}, {hi:.3f}] "
                  f"({s['seconds']:.0f} s)", flush=True)
            for who in ("filter", "smoother"):
                if who in s:
                    print("  " + who + ": " + ", ".join(
                        f"{b} {v['mean']:.3f} ({100 * v['inside']:.0f} % of epochs in band)"
                        for b, v in s[who].items()), flush=True)
            for sensor, w in s["whiteness"].items():
                print(f"  {sensor}: lag-1 {np.round(w['lag1_per_component'], 4).tolist()} "
                      f"(expected {w['lag1_expected']:.4f} ± {w['lag1_band_per_component']:.4f}"
                      f" per component), mean NIS {w['mean_nis']:.3f} (dof {w['dof']})",
                      flush=True)
            if smooth:
                print(f"  mid-outage σ north: filter {s['mid_outage_sd_pn']['filter']:.2f} m, "
                      f"smoother {s['mid_outage_sd_pn']['smoother']:.2f} m", flush=True)
    out.write_text(json.dumps(results, indent=1) + "\n")


if __name__ == "__main__":
    main()
