"""Run the whole strapdown family on a benchmark: tidy tables of errors and fitted orders."""

from __future__ import annotations

import time

import numpy as np

from imunav.assess import fit_order, nav_errors
from imunav.motion import BaseMotion
from imunav.simulate import simulate_imu
from imunav.strapdown import ALGORITHMS, navigate


def _initial(motion: BaseMotion, sig):
    t0 = np.array([sig.t[0] if sig.kind == "rates" else sig.t[0] - sig.dt])
    return motion.attitude(t0)[0], motion.velocity(t0)[0], motion.position(t0)[0]


def run_family(motion: BaseMotion, rate: float, duration: float | None = None,
               kinds=("rates", "increments"), algorithms=None) -> list[dict]:
    """One row per (kind, algorithm): documented order, causal flag, final and maximum
    attitude (deg), velocity (m/s) and position (m) errors against the analytic truth, and
    the navigation time (s)."""
    rows = []
    for kind in kinds:
        sig = simulate_imu(motion, rate, duration, output=kind)
        q0, v0, p0 = _initial(motion, sig)
        for name, algo in ALGORITHMS[kind].items():
            if algorithms and name not in algorithms:
                continue
            t = time.perf_counter()
            nav = navigate(sig, q0, v0, p0, algorithm=name)
            dt = time.perf_counter() - t
            e = nav_errors(nav, motion)
            rows.append({
                "kind": kind, "algorithm": name, "order": algo.order[0], "causal": algo.causal,
                "final_att_deg": float(np.degrees(e.attitude[-1])),
                "max_att_deg": float(np.degrees(e.attitude.max())),
                "max_vel": float(e.velocity.max()), "max_pos": float(e.position.max()),
                "seconds": dt,
            })
    return rows


def convergence(motion: BaseMotion, rates, kind: str, algorithms=None,
                duration: float | None = None) -> list[dict]:
    """Maximum errors at each rate and the fitted orders (slope of log error vs log step)."""
    rows = []
    sigs = {r: simulate_imu(motion, r, duration, output=kind) for r in rates}
    for name, algo in ALGORITHMS[kind].items():
        if algorithms and name not in algorithms:
            continue
        errs = []
        for r in rates:
            sig = sigs[r]
            e = nav_errors(navigate(sig, *_initial(motion, sig), algorithm=name), motion)
            errs.append((e.attitude.max(), e.velocity.max(), e.position.max()))
        errs = np.array(errs)
        steps = [1 / r for r in rates]
        rows.append({"kind": kind, "algorithm": name, "documented": algo.order,
                     "rates": list(rates), "max_att_rad": errs[:, 0].tolist(),
                     "max_vel": errs[:, 1].tolist(), "max_pos": errs[:, 2].tolist(),
                     "order_att": fit_order(steps, errs[:, 0]),
                     "order_vel": fit_order(steps, errs[:, 1]),
                     "order_pos": fit_order(steps, errs[:, 2])})
    return rows


def format_family(rows: list[dict]) -> str:
    """Plain-text table of :func:`run_family` rows."""
    head = (f"{'signals':10s} {'algorithm':18s} {'ord':>3s} {'causal':>6s} {'max att (deg)':>14s} "
            f"{'final att (deg)':>15s} {'max vel (m/s)':>13s} {'max pos (m)':>11s}")
    lines = [head]
    for r in rows:
        lines.append(f"{r['kind']:10s} {r['algorithm']:18s} {r['order']:3d} {str(r['causal']):>6s} "
                     f"{r['max_att_deg']:14.2e} {r['final_att_deg']:15.2e} {r['max_vel']:13.2e} "
                     f"{r['max_pos']:11.2e}")
    return "\n".join(lines)
