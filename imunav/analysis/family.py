"""Run the whole strapdown family on a benchmark: tidy tables of errors and fitted orders, the
cost/accuracy sweep of the high-order configurations, and the coning budget.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.strapdown``,
``imunav.analysis.metrics``, ``imunav.analysis.roundtrip``.
"""

from __future__ import annotations

import time

import numpy as np

from imunav.analysis.metrics import fit_order, nav_errors
from imunav.analysis.roundtrip import initial_state
from imunav.core.kernels import cross, quat_angle
from imunav.motion.base import BaseMotion
from imunav.sensors.simulate import simulate_imu
from imunav.strapdown import highorder
from imunav.strapdown.registry import ALGORITHMS, navigate
from imunav.strapdown.scan import cumulative_product


def run_family(motion: BaseMotion, rate: float, duration: float | None = None,
               kinds=("rates", "increments"), algorithms=None) -> list[dict]:
    """Navigate a motion's ideal signals with every algorithm and tabulate the errors.

    Each signal kind is simulated once; every algorithm navigates it from the true initial
    state and is compared with the analytic truth.

    Parameters
    ----------
    motion : BaseMotion
        The benchmark motion.
    rate : float
        Sample rate (Hz).
    duration : float, optional
        Seconds; default the motion's own.
    kinds : sequence of {"rates", "increments"}, default both
        The signal kinds to run.
    algorithms : collection of str, optional
        Only these algorithm names; default all registered for each kind.

    Returns
    -------
    list of dict
        One row per (kind, algorithm): ``kind``, ``algorithm``, ``order`` (the documented
        attitude order), ``causal``, ``final_att_deg`` and ``max_att_deg`` (degrees),
        ``max_vel`` (m/s), ``max_pos`` (m), and ``seconds`` (wall time of the navigation:
        noisy on a shared machine).

    Raises
    ------
    ImunavError
        For the reasons of :func:`~imunav.sensors.simulate.simulate_imu` (an unknown kind, a
        ``rate`` or ``duration`` that is not a finite number > 0, …).

    Examples
    --------
    >>> from imunav.motion import Motion
    >>> rows = run_family(Motion(yaw="0.5*t", duration=1.0), rate=50, kinds=("rates",),
    ...                   algorithms=["first_order", "magnus6"])
    >>> [(r["algorithm"], r["order"], r["max_att_deg"] < 1e-3) for r in rows]
    [('first_order', 1, True), ('magnus6', 6, True)]
    """
    rows = []
    for kind in kinds:
        sig = simulate_imu(motion, rate, duration, kind=kind)
        q0, v0, p0 = initial_state(motion, sig)
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
    sigs = {r: simulate_imu(motion, r, duration, kind=kind) for r in rates}
    for name, algo in ALGORITHMS[kind].items():
        if algorithms and name not in algorithms:
            continue
        errs = []
        for r in rates:
            sig = sigs[r]
            e = nav_errors(navigate(sig, *initial_state(motion, sig), algorithm=name), motion)
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


def fmt_err(x: float, floor: float = 1e-11, width: int = 9) -> str:
    """``x`` with 2 significant digits, or ``<floor`` where it is rounding noise."""
    return f"{x:{width}.1e}" if x >= floor else f"{'<' + format(floor, '.0e'):>{width}s}"


def format_family(rows: list[dict]) -> str:
    """Plain-text table of :func:`run_family` rows (errors below 1e-11 shown as a floor)."""
    head = (f"{'signals':10s} {'algorithm':18s} {'ord':>3s} {'causal':>6s} {'max att (deg)':>14s} "
            f"{'final att (deg)':>15s} {'max vel (m/s)':>13s} {'max pos (m)':>11s}")
    lines = [head]
    for r in rows:
        lines.append(f"{r['kind']:10s} {r['algorithm']:18s} {r['order']:3d} {str(r['causal']):>6s} "
                     f"{fmt_err(r['max_att_deg'], width=14)} {fmt_err(r['final_att_deg'], width=15)} "
                     f"{fmt_err(r['max_vel'], width=13)} {fmt_err(r['max_pos'], width=11)}")
    return "\n".join(lines)


def poly_sweep(motion: BaseMotion, rate: float, configs, duration: float | None = None
               ) -> list[dict]:
    """Accuracy and cost of local-fit + Magnus configurations ``(m, order, nsub)`` on increments.

    Cost is counted as rate evaluations of the fitted polynomial per interval for the
    attitude (``nsub × order/2``), a machine-independent measure; wall time is also given.
    """
    sig = simulate_imu(motion, rate, duration, kind="increments")
    q0, v0, p0 = initial_state(motion, sig)
    qt = motion.attitude(sig.state_times())
    rows = []
    for m, order, nsub in configs:
        def attitude(m=m, order=order, nsub=nsub):
            fit = highorder.LocalFit(sig.dtheta, "increments", sig.dt, m)
            return cumulative_product(q0, highorder.interval_quaternions(fit, order, nsub))

        attitude()                       # the tap weights are computed once per process
        t0 = time.perf_counter()
        q = attitude()
        dt = time.perf_counter() - t0
        rows.append({"nodes": m, "magnus": order, "substeps": nsub,
                     "evals_per_interval": nsub * order // 2,
                     "max_att_deg": float(np.degrees(quat_angle(q, qt).max())), "seconds": dt})
    return rows


def coning_correction_budget(motion: BaseMotion, rate: float, duration: float | None = None
                             ) -> dict:
    """Why exact increments need the coning term: the attitude error of ``q ⊗ exp(Δθ)`` vs the
    accumulated two-sample coning terms Σ Δθ_{k−1}×Δθ_k / 12 (both in rad, body frame)."""
    sig = simulate_imu(motion, rate, duration, kind="increments")
    q0, v0, p0 = initial_state(motion, sig)
    nav = navigate(sig, q0, v0, p0, algorithm="exact_exponential")
    th = sig.dtheta
    corr = cross(th[:-1], th[1:]) / 12
    rates = simulate_imu(motion, rate, duration, kind="rates")
    nr = navigate(rates, *initial_state(motion, rates), algorithm="exact_exponential")
    return {
        "exact_exponential_increments_rad": float(quat_angle(nav.quaternion[-1],
                                                         motion.attitude(nav.t[-1:])[0])),
        "sum_coning_terms_rad": float(np.linalg.norm(corr.sum(axis=0))),
        "exact_exponential_rates_rad": float(quat_angle(nr.quaternion[-1],
                                                    motion.attitude(nr.t[-1:])[0])),
        "coning2_increments_rad": float(quat_angle(
            navigate(sig, q0, v0, p0, algorithm="coning2").quaternion[-1],
            motion.attitude(nav.t[-1:])[0])),
    }
