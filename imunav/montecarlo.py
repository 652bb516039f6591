"""Monte Carlo of simulate → navigate with sensor errors, and the IMU applicability verdict.

The ideal signals are simulated once (at the sensor's internal rate if it has one); every run
adds its own errors from its own random stream (:func:`imunav.sensors.run_streams`) and all
runs of a chunk are navigated together, vectorised across runs (the high-order default
algorithm for the signal kind). Chunks are independent tasks: locally they run in turn with a
progress bar; with ``scheduler=ADDRESS`` they are sent to a Dask cluster (``imunav[dask]``).
"""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np

from imunav.errors import ImunavError, check_positive
from imunav.motion import G0, BaseMotion
from imunav.rotations import FloatArray, _angle
from imunav.sensors import ImuModel, measure
from imunav.simulate import simulate_imu

#: The algorithm used for every run: the most accurate for the kind (fit nodes, Magnus order).
_ALGO = {"increments": (8, 6), "rates": (6, 6)}


@dataclass
class MonteCarloResult:
    """Per-run error histories at the output times ``t`` (runs × samples)."""

    t: FloatArray
    position: FloatArray     # |Δr| (m)
    velocity: FloatArray     # |Δv| (m/s)
    attitude: FloatArray     # angle (rad)
    saturated: np.ndarray    # clipped output samples per run
    model: str
    rate: float
    kind: str

    @property
    def runs(self) -> int:
        return self.position.shape[0]

    def envelope(self, key: str = "position", q=(50, 68, 95)) -> dict[int, FloatArray]:
        """Percentile envelopes vs time (median, 68 %, 95 % by default)."""
        a = getattr(self, key)
        return {p: np.percentile(a, p, axis=0) for p in q}


def _mc_chunk(gyro, accel, kind, sim_rate, k, model, seeds, q0, v0, p0, g, truth_p, truth_v,
              truth_q, h):
    """One chunk of runs (module-level and picklable: a Dask task)."""
    from imunav.highorder import navigate_poly

    G, A, S = [], [], []
    for ss in seeds:
        gm, am, flags = measure(model, gyro, accel, kind, sim_rate, np.random.default_rng(ss), k)
        G.append(gm)
        A.append(am)
        S.append(int(flags.sum()))
    G = np.stack(G, axis=1)
    A = np.stack(A, axis=1)                                   # (N, R, 3)
    m, order = _ALGO[kind]
    q, v, p = navigate_poly(kind, G, A, h, q0, v0, p0, g, m=m, order=order, nsub=1)
    pos = np.linalg.norm(p - truth_p[:, None], axis=-1).T
    vel = np.linalg.norm(v - truth_v[:, None], axis=-1).T
    att = _angle(q, truth_q[:, None]).T
    return pos, vel, att, np.array(S)


def monte_carlo(motion: BaseMotion, model: ImuModel, rate: float, duration: float | None = None,
                runs: int = 100, seed: int = 0, output: str = "increments", g: float = G0,
                chunk: int | None = None, progress: bool = True,
                scheduler: str | None = None) -> MonteCarloResult:
    """``runs`` simulations of ``model`` on ``motion`` at ``rate`` Hz, each navigated back.

    Reproducible bit for bit for a given ``seed`` (whatever ``chunk`` or ``scheduler``).
    """
    rate = check_positive(rate, "rate")
    if int(runs) < 1:
        raise ImunavError(f"runs must be a positive integer, got {runs!r}")
    runs = int(runs)
    duration = duration or motion.duration
    if duration is None:
        raise ImunavError("duration must be given (the motion has no default duration)")
    k = max(1, int(round((model.internal_rate or rate) / rate)))
    sim = simulate_imu(motion, rate * k, duration, output=output, g=g)
    n_out = len(sim) // k if output == "increments" else (len(sim) - 1) // k + 1
    t = np.arange(n_out + (1 if output == "increments" else 0)) / rate
    truth_q, truth_v, truth_p = motion.attitude(t), motion.velocity(t), motion.position(t)
    h = 1.0 / rate
    seeds = np.random.SeedSequence(seed).spawn(runs)
    chunk = chunk or max(1, min(runs, int(2e6 // max(n_out, 1))))
    parts = [seeds[i:i + chunk] for i in range(0, runs, chunk)]
    args = (sim.gyro, sim.accel, output, rate * k, k, model)
    tail = (truth_q[0], truth_v[0], truth_p[0], g, truth_p, truth_v, truth_q, h)
    if scheduler:
        try:
            from dask.distributed import Client
        except ImportError:
            raise ImunavError("--scheduler needs the dask extra: pip install 'imunav[dask]'") from None
        with Client(scheduler) as client:
            futs = [client.submit(_mc_chunk, *args, part, *tail, pure=False) for part in parts]
            results = client.gather(futs)
    else:
        results = []
        bar = _progress(len(parts), runs * n_out, progress)
        for part in parts:
            results.append(_mc_chunk(*args, part, *tail))
            if bar is not None:
                bar.update(1)
        if bar is not None:
            bar.close()
    pos, vel, att, sat = (np.concatenate([r[i] for r in results]) for i in range(4))
    return MonteCarloResult(t, pos, vel, att, sat, model.name, rate, output)


def _progress(n_chunks: int, work: int, enabled: bool):
    """A tqdm bar (terminal or notebook) for long runs only."""
    if not enabled or n_chunks < 2 or work < 5e6:
        return None
    from tqdm.auto import tqdm

    return tqdm(total=n_chunks, desc="Monte Carlo", unit="chunk")


# ------------------------------------------------------------------------------ assessment

RATE_CANDIDATES = (1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000)


def min_sample_rate(motion: BaseMotion, tolerance: float, duration: float | None = None,
                    output: str = "increments", candidates=RATE_CANDIDATES) -> float | None:
    """Smallest candidate rate at which the sampling error alone (ideal sensor, default
    algorithm) stays below a tenth of ``tolerance`` over the whole motion."""
    from imunav.assess import nav_errors
    from imunav.strapdown import navigate

    duration = duration or motion.duration
    for r in candidates:
        if r * duration < 10:
            continue
        sig = simulate_imu(motion, r, duration, output=output)
        t0 = np.array([0.0])
        nav = navigate(sig, motion.attitude(t0)[0], motion.velocity(t0)[0],
                       motion.position(t0)[0])
        if nav_errors(nav, motion).position.max() <= tolerance / 10:
            return float(r)
    return None


def assess(motion: BaseMotion, model: ImuModel, rate: float, runs: int, tolerance: float,
           seed: int = 0, duration: float | None = None, output: str = "increments",
           budget_runs: int | None = None, scheduler: str | None = None,
           progress: bool = True) -> dict:
    """The applicability verdict: the numbers of ``imunav assess`` (see :func:`format_verdict`).

    ``error_budget``: each error term alone (same seed, ``budget_runs`` runs, default
    min(runs, 200)) → final 95th-percentile position error (m).
    """
    tolerance = check_positive(tolerance, "tolerance")
    mc = monte_carlo(motion, model, rate, duration, runs, seed, output, scheduler=scheduler,
                     progress=progress)
    within = float(np.mean(mc.position.max(axis=1) <= tolerance))
    p95 = np.percentile(mc.position, 95, axis=0)
    over = np.nonzero(p95 > tolerance)[0]
    budget = {}
    br = budget_runs or min(runs, 200)
    for term in model.terms():
        b = monte_carlo(motion, model.only(term), rate, duration, br, seed, output,
                        scheduler=scheduler, progress=False)
        budget[term] = float(np.percentile(b.position[:, -1], 95))
    return {
        "motion": getattr(motion, "name", "motion"), "imu": model.name, "rate_hz": float(rate),
        "tolerance_m": tolerance, "runs": runs, "seed": seed,
        "fraction_within_tolerance": within,
        "time_p95_exceeds_s": float(mc.t[over[0]]) if over.size else None,
        "final_p95_position_m": float(p95[-1]),
        "error_budget": dict(sorted(budget.items(), key=lambda kv: -kv[1])),
        "min_rate_hz": min_sample_rate(motion, tolerance, duration, output),
        "saturated_runs": int(np.sum(mc.saturated > 0)),
    }


def format_verdict(r: dict) -> str:
    """A verdict a non-specialist can act on."""
    pct = 100 * r["fraction_within_tolerance"]
    lines = [f"IMU {r['imu']} on motion {r['motion']} at {r['rate_hz']:g} Hz, "
             f"{r['runs']} runs (seed {r['seed']}), tolerance {r['tolerance_m']:g} m:"]
    ok = pct >= 95
    lines.append(f"  {'SUITABLE' if ok else 'NOT SUITABLE'}: {pct:.1f} % of runs stay within "
                 f"{r['tolerance_m']:g} m over the whole motion.")
    if r["time_p95_exceeds_s"] is None:
        lines.append("  The 95th percentile of the position error never exceeds the tolerance "
                     f"(final {r['final_p95_position_m']:.3g} m).")
    else:
        lines.append(f"  The 95th percentile crosses {r['tolerance_m']:g} m at "
                     f"t = {r['time_p95_exceeds_s']:.2f} s (final {r['final_p95_position_m']:.3g} m).")
    if r["error_budget"]:
        top = next(iter(r["error_budget"]))
        lines.append(f"  Dominant error: {top} ({r['error_budget'][top]:.3g} m alone, 95th pct).")
        lines.append("  Error budget (each term alone, final 95th-percentile position error):")
        for k, v in r["error_budget"].items():
            val = f"{v:10.3g}" if v >= 1e-9 else f"{'< 1e-9':>10s}"   # below: rounding
            lines.append(f"    {k:28s} {val} m")
    mr = r["min_rate_hz"]
    lines.append("  Sampling alone stays below a tenth of the tolerance from "
                 + (f"{mr:g} Hz." if mr else "no tested rate (≤ 5 kHz)."))
    if r["saturated_runs"]:
        lines.append(f"  Warning: {r['saturated_runs']} runs hit the sensor range (clipped).")
    return "\n".join(lines)


def write_json(r: dict, path) -> None:
    with open(path, "w") as fh:
        json.dump(r, fh, indent=1)
        fh.write("\n")


def plot_envelope(mc: MonteCarloResult, tolerance: float | None = None, ax=None, label=None):
    """Median, 68 % and 95 % envelopes of the position error vs time."""
    import matplotlib.pyplot as plt

    ax = ax or plt.figure(figsize=(8, 4)).add_subplot()
    env = mc.envelope()
    lab = label or mc.model
    ax.fill_between(mc.t, 0, env[95], alpha=0.2, label=f"{lab}: 95 %")
    ax.fill_between(mc.t, 0, env[68], alpha=0.3, label=f"{lab}: 68 %")
    ax.plot(mc.t, env[50], lw=1.5, label=f"{lab}: median")
    if tolerance:
        ax.axhline(tolerance, color="k", ls="--", lw=1, label="tolerance")
    ax.set(xlabel="t (s)", ylabel="position error (m)", title=f"{mc.runs} runs at {mc.rate:g} Hz")
    ax.legend(fontsize=7)
    return ax
