"""Monte Carlo of simulate → navigate with sensor errors.

The ideal signals are simulated once (at the sensor's internal rate if it has one); every run
adds its own errors from its own random stream (``SeedSequence(seed).spawn(runs)[r]``) and all
runs of a chunk are navigated together, vectorised across runs, through the algorithm registry
(:func:`imunav.strapdown.registry.navigate_batch`; the default algorithm for the signal kind
unless one is named). Chunks are independent tasks: locally they run in turn with a progress
bar; with ``scheduler=ADDRESS`` they are sent to a Dask cluster (``imunav[dask]``).

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.strapdown``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from imunav.core.constants import G0
from imunav.core.kernels import quat_angle
from imunav.core.resources import check_memory
from imunav.core.rotations import FloatArray
from imunav.core.validation import ImunavError, check_int, check_positive
from imunav.motion.base import BaseMotion, span
from imunav.sensors.models import ImuModel, measure
from imunav.sensors.simulate import interval_count, simulate_imu
from imunav.strapdown.registry import navigate_batch


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
              truth_q, rate, algorithm):
    """One chunk of runs (module-level and picklable: a Dask task)."""
    G, A, S = [], [], []
    for ss in seeds:
        gm, am, flags = measure(model, gyro, accel, kind, sim_rate, np.random.default_rng(ss), k)
        G.append(gm)
        A.append(am)
        S.append(int(flags.sum()))
    G = np.stack(G, axis=1)
    A = np.stack(A, axis=1)                                   # (N, R, 3)
    q, v, p = navigate_batch(kind, G, A, rate, q0, v0, p0, g, algorithm=algorithm)
    pos = np.linalg.norm(p - truth_p[:, None], axis=-1).T
    vel = np.linalg.norm(v - truth_v[:, None], axis=-1).T
    att = quat_angle(q, truth_q[:, None]).T
    return pos, vel, att, np.array(S)


def monte_carlo(motion: BaseMotion, model: ImuModel, rate: float, duration: float | None = None,
                runs: int = 100, seed: int = 0, output: str = "increments", g: float = G0,
                chunk: int | None = None, progress: bool = True,
                scheduler: str | None = None, algorithm: str | None = None) -> MonteCarloResult:
    """``runs`` simulations of ``model`` on ``motion`` at ``rate`` Hz, each navigated back with
    ``algorithm`` (default: the registry's default for ``output``).

    Reproducible bit for bit for a given ``seed`` (whatever ``chunk`` or ``scheduler``).
    """
    rate = check_positive(rate, "rate")
    runs = check_int(runs, "runs", 1)
    seed = check_int(seed, "seed", 0)
    duration = span(motion, rate, duration)
    k = model.decimation(rate)
    n = interval_count(rate, duration)
    chunk = chunk or max(1, min(runs, int(2e6 // max(n, 1))))
    # ideal signals at the internal rate, the per-run histories, one chunk's working set
    need = 8 * (6 * (n * k + 1) + 3 * runs * (n + 1) + 40 * chunk * (n + 1) * min(k, 4))
    check_memory(need, f"{runs:,} Monte Carlo runs of {n:,} samples (internal rate "
                       f"{rate * k:g} Hz)")
    sim = simulate_imu(motion, rate * k, duration, output=output, g=g)
    n_out = len(sim) // k if output == "increments" else (len(sim) - 1) // k + 1
    t = np.arange(n_out + (1 if output == "increments" else 0)) / rate
    truth_q, truth_v, truth_p = motion.attitude(t), motion.velocity(t), motion.position(t)
    seeds = np.random.SeedSequence(seed).spawn(runs)
    parts = [seeds[i:i + chunk] for i in range(0, runs, chunk)]
    args = (sim.gyro, sim.accel, output, rate * k, k, model)
    tail = (truth_q[0], truth_v[0], truth_p[0], g, truth_p, truth_v, truth_q, rate, algorithm)
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


