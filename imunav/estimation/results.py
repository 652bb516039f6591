"""What the aided filter gives: its estimate and standard deviations (:class:`FilterResult`, one
run; :class:`BatchResult`, R runs at once), each aid's innovations (:class:`Innovations`) and the
standard deviations in the output's terms (:func:`nav_sd`).

May import: ``imunav.core``, ``imunav.sensors``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from imunav.core.kernels import FloatArray, quat_to_dcm
from imunav.core.layout import DP, DV, PHI
from imunav.core.states import States
from imunav.sensors.aids import euler_jacobian

__all__ = ["SD_COLUMNS", "BatchResult", "FilterResult", "Innovations", "nav_sd"]

#: The standard-deviation columns of the filter's output, in order (m, m/s, rad).
SD_COLUMNS = ("sd_pn", "sd_pe", "sd_pd", "sd_vn", "sd_ve", "sd_vd", "sd_roll", "sd_pitch",
              "sd_yaw")


@dataclass
class Innovations:
    """One aid's innovations over a run.

    Attributes
    ----------
    name : str
    t : ndarray, shape (k,)
        Reading times (s).
    innovation : ndarray, shape (k, m)
        ``predicted − measured``.
    S : ndarray, shape (k, m, m)
        Their covariances ``H P Hᵀ + R``.
    nis : ndarray, shape (k,)
        ``νᵀ S⁻¹ ν``.
    accepted : ndarray of bool, shape (k,)
        False where the gate rejected the reading.
    units : tuple of str
        The components' units (empty if unknown).
    """

    name: str
    t: FloatArray
    innovation: FloatArray
    S: FloatArray
    nis: FloatArray
    accepted: np.ndarray
    units: tuple = ()

    @property
    def normalised(self) -> FloatArray:
        """Whitened innovations ``L⁻¹ ν`` (``S = L Lᵀ``): independent N(0, 1) components for a
        consistent filter.

        Returns
        -------
        ndarray, shape (k, m)
        """
        if not len(self.t):
            return np.zeros_like(self.innovation)
        S = 0.5 * (self.S + np.swapaxes(self.S, -1, -2))
        # a covariance inflated by orders of magnitude (readings in the wrong units, a
        # lock-out's recovery) can leave S numerically indefinite: those readings get NaN
        # rather than stopping the whole run's report
        bad = ~(np.linalg.eigvalsh(S)[:, 0] > 0)
        L = np.linalg.cholesky(np.where(bad[:, None, None], np.eye(S.shape[-1]), S))
        z = np.linalg.solve(L, self.innovation[..., None])[..., 0]
        z[bad] = np.nan
        return z

    def lag1(self) -> FloatArray:
        """Lag-1 autocorrelation of each whitened component over the accepted readings.

        Returns
        -------
        ndarray, shape (m,)
            NaN with fewer than 3 readings.
        """
        z = self.normalised[self.accepted]
        z = z[np.isfinite(z).all(axis=1)]
        if z.shape[0] < 3:
            return np.full(self.innovation.shape[1], np.nan)
        z = z - z.mean(axis=0)
        return (z[1:] * z[:-1]).sum(axis=0) / (z * z).sum(axis=0)

    def stats(self) -> dict:
        """The statistics ``imunav filter`` prints.

        Returns
        -------
        dict
            ``readings``, ``rejected``, ``dof``, ``mean_nis`` (expected ``dof``), ``rms``
            (per component), ``lag1`` (per component; 95 % band ``±1.96/√readings``).
        """
        acc = self.accepted
        return {"readings": int(len(self.t)), "rejected": int((~acc).sum()),
                "dof": int(self.innovation.shape[1]),
                "mean_nis": float(self.nis[acc].mean()) if acc.any() else float("nan"),
                "rms": np.sqrt((self.innovation[acc] ** 2).mean(axis=0)).tolist()
                if acc.any() else [],
                "lag1": self.lag1().tolist()}


@dataclass
class FilterResult:
    """What the filter (or the smoother) estimated.

    Attributes
    ----------
    states : States
        The estimate at every IMU node (times ``signals.state_times()``).
    sd : ndarray, shape (N + 1, 9)
        Standard deviations :data:`SD_COLUMNS` (m, m/s, rad) at every node.
    epochs : ndarray of int, shape (E,)
        The covariance epochs (node indices).
    P_nav : ndarray, shape (E, 9, 9)
        The navigation-error covariance (``φ``, ``δv``, ``δp``) at each epoch (after its update);
        on the Earth that of the local NED errors (``δp`` in metres north, east, down).
    innovations : dict
        ``{aid: Innovations}``.
    estimates : ndarray, shape (E, n − 9)
        The sensor and aid error estimates ``ŝ`` at each epoch.
    layout : dict
        The error state's blocks (:attr:`AidedSystem.layout`).
    smoothed : FilterResult or None
        The RTS smoother's result (same fields; its ``innovations`` and ``estimates`` are the
        filter's).
    warnings : list of str
    health : Health or None
        Each aid's health (:mod:`imunav.estimation.health`).
    """

    states: States
    sd: FloatArray
    epochs: np.ndarray
    P_nav: FloatArray
    innovations: dict
    estimates: FloatArray
    layout: dict
    smoothed: FilterResult | None = None
    warnings: list = field(default_factory=list)
    health: object = None

    @property
    def t(self) -> FloatArray:
        """Node times (s).

        Returns
        -------
        ndarray
        """
        return self.states.t


@dataclass
class BatchResult:
    """What the filter estimated in each of R runs filtered at once (:func:`run_filter_batch`).

    Attributes
    ----------
    t : ndarray, shape (N + 1,)
        Node times (s).
    quaternion : ndarray, shape (N + 1, R, 4)
    velocity, position : ndarray, shape (N + 1, R, 3)
        The estimates at every node (on the Earth: local NED, ``[lat, lon, h]``).
    epochs : ndarray of int, shape (E,)
        The covariance epochs (node indices).
    P_nav : ndarray, shape (E, R, 9, 9)
        The navigation-error covariance at each epoch after its readings (on the Earth: of the
        local NED errors).
    readings : dict
        ``{aid: readings per run}``.
    rejected : dict
        ``{aid: (R,) readings the gate rejected}``.
    algorithm : str
    warnings : list of str
    innovations : list of dict
        Per run, ``{aid: Innovations}``.
    results : list of FilterResult
        The whole results of the first ``keep`` runs.
    readmitted : dict
        ``{aid: (R,) readings re-admitted after a lock-out}``.
    smoothed : dict or None
        With ``smooth``: ``quaternion``, ``velocity``, ``position`` and ``P_nav`` of the
        smoother.
    frame : str
    """

    t: FloatArray
    quaternion: FloatArray
    velocity: FloatArray
    position: FloatArray
    epochs: np.ndarray
    P_nav: FloatArray
    readings: dict
    rejected: dict
    algorithm: str
    warnings: list = field(default_factory=list)
    innovations: list = field(default_factory=list)
    results: list = field(default_factory=list)
    readmitted: dict = field(default_factory=dict)
    smoothed: dict | None = None
    frame: str = "flat"


def nav_sd(P_nav: FloatArray, q: FloatArray) -> FloatArray:
    """Standard deviations in the output's terms from navigation-error covariances.

    Parameters
    ----------
    P_nav : ndarray, shape (..., 9, 9)
        Covariance of ``φ``, ``δv``, ``δp``.
    q : ndarray, shape (..., 4)
        The attitude there (the Euler-angle σ depend on it).

    Returns
    -------
    ndarray, shape (..., 9)
        :data:`SD_COLUMNS`: north, east, down position; velocity; roll, pitch, yaw.
    """
    T = euler_jacobian(quat_to_dcm(q))                       # rows yaw, pitch, roll
    Pe = T @ P_nav[..., PHI, PHI] @ np.swapaxes(T, -1, -2)
    var = np.concatenate([np.diagonal(P_nav[..., DP, DP], axis1=-2, axis2=-1),
                          np.diagonal(P_nav[..., DV, DV], axis1=-2, axis2=-1),
                          np.diagonal(Pe, axis1=-2, axis2=-1)[..., ::-1]], axis=-1)
    return np.sqrt(np.maximum(var, 0.0))


