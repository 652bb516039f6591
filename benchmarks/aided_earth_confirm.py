"""The aided covariance analysis on the rotating Earth against a Monte Carlo of the Earth filter
(issue 35's check): ``imunav assess --aiding examples/drive_aiding.toml --earth wgs84 --origin
45,7,300`` on ``examples/drive.toml`` with the tactical preset, and 100 runs of the real EKF on
the same Earth motion: the p95 position error at each outage's end, covariance beside Monte
Carlo (target: within 15 %), and the flat frame's covariance beside them. Writes
``benchmarks/results_aided_earth.json``.

    python benchmarks/aided_earth_confirm.py [--runs 100]
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

import numpy as np

from imunav.analysis.aided_assessment import assess_aided
from imunav.analysis.assessment import runs_interval
from imunav.io.files import load_motion
from imunav.motion import EarthMotion
from imunav.sensors.aids import AidingConfig
from imunav.sensors.models import ImuModel

ROOT = Path(__file__).resolve().parents[1]
ORIGIN_DEG = (45.0, 7.0, 300.0)
RATE, TOLERANCE = 50.0, 5.0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=100)
    ap.add_argument("--seed", type=int, default=2)
    args = ap.parse_args(argv)
    m, _, _ = load_motion(ROOT / "examples" / "drive.toml")
    lat, lon, h = ORIGIN_DEG
    em = EarthMotion(m, (np.radians(lat), np.radians(lon), h))
    aiding = AidingConfig.from_toml(ROOT / "examples" / "drive_aiding.toml")
    imu = ImuModel.load("tactical")
    t0 = time.perf_counter()
    earth = assess_aided(em, imu, aiding, RATE, TOLERANCE, runs=args.runs, seed=args.seed,
                         budget=False, progress=False)
    flat = assess_aided(m, imu, aiding, RATE, TOLERANCE, budget=False, progress=False)
    rows = []
    for o, f in zip(earth["outages"], flat["outages"], strict=True):
        ratio = o["position_p95_end_m"] / o["covariance_p95_end_m"]
        rows.append({"start": o["start"], "end": o["end"],
                     "montecarlo_p95_end_m": o["position_p95_end_m"],
                     "covariance_p95_end_m": o["covariance_p95_end_m"],
                     "flat_covariance_p95_end_m": f["position_p95_end_m"],
                     "montecarlo_over_covariance": ratio, "within_15_percent": abs(ratio - 1) <= 0.15})
        print(f"outage {o['start']:g}–{o['end']:g} s: Monte Carlo p95 {o['position_p95_end_m']:.3f} "
              f"m, covariance {o['covariance_p95_end_m']:.3f} m (×{ratio:.3f}); flat frame "
              f"{f['position_p95_end_m']:.3f} m")
    # how far a p95 from this many runs can be from the truth: the binomial interval of the
    # share of runs below the covariance's p95
    lo, hi = runs_interval(int(round(0.95 * args.runs)), args.runs)
    out = {"motion": "examples/drive.toml", "aiding": "examples/drive_aiding.toml",
           "imu": "tactical", "origin_deg": ORIGIN_DEG, "rate_hz": RATE, "runs": args.runs,
           "seed": args.seed, "outages": rows,
           "p95_share_interval_95": [lo, hi],
           "seconds": time.perf_counter() - t0}
    (ROOT / "benchmarks" / "results_aided_earth.json").write_text(json.dumps(out, indent=1) + "\n")
    return 0 if all(r["within_15_percent"] for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
