"""Monte Carlo of the aided filter with known truth: does its covariance tell the truth?

Each run simulates the IMU's errors (its own stream, ``SeedSequence(seed).spawn(runs)[r]``, as
:func:`imunav.analysis.montecarlo.monte_carlo`) on the exact increments of the motion, the
aiding sensors' readings (their own streams, :func:`imunav.sensors.aiding.aiding_streams`), and
runs :func:`imunav.estimation.filters.run_filter` (and its smoother) from the true initial
state. At every covariance epoch the normalised estimation error squared (NEES) of position,
velocity and attitude is ``eᵀ P⁻¹ e`` with ``e`` the error against the exact motion (attitude:
``φ`` with ``C_est = (I − [φ×]) C``); for a consistent filter its average over ``R`` runs is
``χ²(3R)/R``.

May import: ``imunav.core``, ``imunav.motion``, ``imunav.sensors``, ``imunav.estimation``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.stats import chi2

from imunav.core.kernels import FloatArray, quat_conj, quat_log, quat_mul
from imunav.estimation.error_model import DP, DV, PHI
from imunav.estimation.filters import FilterResult, run_filter
from imunav.motion.base import BaseMotion
from imunav.sensors.aiding import AidingConfig, simulate_aiding
from imunav.sensors.models import ImuModel, measure
from imunav.sensors.signals import ImuSignals
from imunav.sensors.simulate import simulate_imu

__all__ = ["BLOCKS", "FilterMonteCarlo", "filter_monte_carlo", "nees", "nees_band"]

#: The NEES blocks and their rows of the navigation error.
BLOCKS = {"position": DP, "velocity": DV, "attitude": PHI}


def nees(result: FilterResult, motion: BaseMotion, skip: float = 0.0) -> dict[str, FloatArray]:
    """NEES of position, velocity and attitude at the covariance epochs after ``skip`` s.

    Parameters
    ----------
    result : FilterResult
        A filter's (or smoother's) result.
    motion : BaseMotion
        The truth.
    skip : float
        Seconds after the start left out (where the covariance starts near zero).

    Returns
    -------
    dict
        ``{"position" | "velocity" | "attitude": (E,) NEES}``, and ``"t"`` the epochs' times.
    """
    keep = result.t[result.epochs] >= result.t[0] + skip
    ep, P = result.epochs[keep], result.P_nav[keep]
    tr = motion.states(result.t[ep])
    st = result.states
    err = {"position": st.position[ep] - tr.position,
           "velocity": st.velocity[ep] - tr.velocity,
           "attitude": -quat_log(quat_mul(st.quaternion[ep], quat_conj(tr.quaternion)))}
    out = {k: np.einsum("ni,ni->n", e, np.linalg.solve(P[:, BLOCKS[k], BLOCKS[k]],
                                                        e[..., None])[..., 0])
           for k, e in err.items()}
    out["t"] = result.t[ep]
    return out


def nees_band(runs: int, dof: int = 3, level: float = 0.95) -> tuple[float, float]:
    """The two-sided ``level`` band of the run-average NEES: ``χ²(dof·runs)/runs``.

    Parameters
    ----------
    runs : int
    dof : int
    level : float

    Returns
    -------
    tuple of float
    """
    a = (1 - level) / 2
    lo, hi = chi2.ppf([a, 1 - a], dof * runs) / runs
    return float(lo), float(hi)


@dataclass
class FilterMonteCarlo:
    """NEES per run and the innovations of a Monte Carlo of the aided filter.

    Attributes
    ----------
    t : ndarray, shape (E,)
        Epoch times of the NEES (s).
    filter : dict
        ``{block: (runs, E) NEES}`` of the filter.
    smoother : dict
        The same for the smoother (empty without smoothing).
    innovations : list of dict
        Per run, ``{sensor: Innovations}``.
    results : list of FilterResult
        The runs kept (``keep``).
    """

    t: FloatArray
    filter: dict
    smoother: dict = field(default_factory=dict)
    innovations: list = field(default_factory=list)
    results: list = field(default_factory=list)

    @property
    def runs(self) -> int:
        """Number of runs.

        Returns
        -------
        int
        """
        return int(next(iter(self.filter.values())).shape[0])

    def summary(self, level: float = 0.95) -> dict:
        """Time-averaged run-average NEES per block, the band and the fraction of epochs in it.

        Parameters
        ----------
        level : float

        Returns
        -------
        dict
            ``{"band": (lo, hi), "filter": {block: {"mean", "inside"}}, "smoother": …}``.
        """
        lo, hi = nees_band(self.runs, 3, level)
        out: dict = {"band": (lo, hi), "runs": self.runs}
        for name, d in (("filter", self.filter), ("smoother", self.smoother)):
            if d:
                out[name] = {}
                for k, a in d.items():
                    avg = a.mean(axis=0)
                    out[name][k] = {"mean": float(avg.mean()),
                                    "inside": float(np.mean((avg >= lo) & (avg <= hi)))}
        return out


def filter_monte_carlo(motion: BaseMotion, imu: ImuModel, aiding: AidingConfig, rate: float,
                       duration: float, runs: int, *, seed: int = 0, smooth: bool = False,
                       algorithm: str | None = None, skip: float = 5.0, keep: int = 1,
                       covariance_step: float = 0.1) -> FilterMonteCarlo:
    """Run the aided filter ``runs`` times on simulated data with known truth.

    Parameters
    ----------
    motion : BaseMotion
    imu : ImuModel
        The IMU simulated and assumed by the filter.
    aiding : AidingConfig
        The aids simulated and assumed.
    rate : float
        IMU rate (Hz).
    duration : float
        Seconds.
    runs : int
    seed : int
    smooth : bool
        Also the smoother's NEES.
    algorithm : str, optional
        Strapdown algorithm.
    skip : float
        Seconds at the start left out of the NEES.
    keep : int
        How many runs' full results to keep.
    covariance_step : float
        The filter's covariance step (s).

    Returns
    -------
    FilterMonteCarlo
    """
    k = imu.decimation(rate)
    ideal = simulate_imu(motion, rate * k, duration, output="increments")
    st0 = motion.states(np.array([0.0]))
    seeds = np.random.SeedSequence(seed).spawn(runs)
    acc: dict[str, dict[str, list]] = {"filter": {}, "smoother": {}}
    out = FilterMonteCarlo(np.zeros(0), {})
    for r in range(runs):
        gm, am, _ = measure(imu, ideal.gyro, ideal.accel, "increments", rate * k,
                            np.random.default_rng(seeds[r]), k)
        sig = ImuSignals(ideal.t[k - 1::k][:gm.shape[0]], gm, am, "increments", rate, ideal.g)
        data = simulate_aiding(motion, aiding, duration, seed=seed, run=r, imu_rate=rate)
        res = run_filter(sig, st0.quaternion[0], st0.velocity[0], st0.position[0], aiding, data,
                         imu=imu, smooth=smooth, algorithm=algorithm,
                         covariance_step=covariance_step)
        for name, R in (("filter", res),) + ((("smoother", res.smoothed),) if smooth else ()):
            n = nees(R, motion, skip)
            out.t = n.pop("t")
            for block, v in n.items():
                acc[name].setdefault(block, []).append(v)
        out.innovations.append(res.innovations)
        if r < keep:
            out.results.append(res)
    out.filter = {k: np.array(v) for k, v in acc["filter"].items()}
    out.smoother = {k: np.array(v) for k, v in acc["smoother"].items()}
    return out
