"""Flat vs Earth (issue 27's closing note): the 95th-percentile position error at the end, by
covariance, for each IMU preset, on the flat frame and on the WGS-84 Earth (vertical free — in
all and its horizontal part — and held). Run from the repository root:

    IMUNAV_BLAS_THREADS=1 .venv/bin/python benchmarks/flat_vs_earth.py

(about 20 minutes on a loaded 2-core machine, most of it the hour at rest)."""
import time

import numpy as np

from imunav.analysis.covariance import covariance
from imunav.analysis.gaussnorm import norm_quantile
from imunav.io.files import load_motion
from imunav.motion import EarthMotion, Motion
from imunav.sensors import ImuModel
from imunav.sensors.presets import PRESETS

DEG = np.pi / 180
cases = [("examples/route.toml (60 s drive), 100 Hz, origin 30° N 120° E 10 m",
          load_motion("examples/route.toml")[0], 100.0, (30 * DEG, 120 * DEG, 10.0)),
         ("1 h at rest, level, 10 Hz, origin 45° N 7° E 100 m",
          Motion(duration=3600.0), 10.0, (45 * DEG, 7 * DEG, 100.0))]
for title, m, rate, origin in cases:
    print(f"\n{title}")
    print(f"  {'IMU':10s} {'flat':>10s} {'wgs84 free':>11s} {'(horiz.)':>10s} {'wgs84 hold':>11s}")
    for name in [n for n in PRESETS if n != "ideal"]:
        imu = ImuModel.load(name)
        t0 = time.perf_counter()
        flat = covariance(m, imu, rate).position_quantile(0.95)[-1]
        em = EarthMotion(m, origin)
        free_c = covariance(em, imu, rate, vertical="free")
        free = free_c.position_quantile(0.95)[-1]
        P3 = free_c.total[-1:, 6:9, 6:9].copy()
        P3[:, 2, :] = 0.0
        P3[:, :, 2] = 0.0
        P3[:, 2, 2] = 1e-30 * P3[:, 0, 0]
        horiz = norm_quantile(P3, 0.95)[0]
        hold = covariance(em, imu, rate, vertical="hold").position_quantile(0.95)[-1]
        print(f"  {name:10s} {flat:10.3g} {free:11.3g} {horiz:10.3g} {hold:11.3g}   "
              f"({time.perf_counter() - t0:.0f} s)", flush=True)
