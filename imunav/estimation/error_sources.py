"""The sensor error terms as error sources of the navigation error model: each term's
:class:`~imunav.sensors.terms.SensorErrorStates` (its linearisation) becomes an
:class:`ErrorSource` — the navigation errors and ``k`` sensor states driven by white noise —
along a :class:`~imunav.estimation.nominal.Trajectory` (:func:`linearise`).

May import: ``imunav.core``, ``imunav.sensors``, ``imunav.estimation.nominal``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from imunav.core.deprecation import renamed
from imunav.core.kernels import FloatArray
from imunav.core.layout import DV, NAV, PHI
from imunav.estimation.nominal import Trajectory
from imunav.sensors.models import ImuModel
from imunav.sensors.terms import TERMS, LinearisationContext, SensorErrorStates

__all__ = ["MAX_DECAY_STEP", "TRIAD_ROWS", "ErrorSource", "linearise"]

#: The rows of the navigation error a triad's error drives: the gyro φ, the accelerometer δv.
TRIAD_ROWS = {"gyro": PHI, "accel": DV}

#: Largest step (in correlation times) of a decaying sensor state: longer output steps are cut
#: into this many sub-steps, so the midpoint linearisation of fast Gauss–Markov states holds.
MAX_DECAY_STEP = 0.5


@dataclass
class ErrorSource:
    """One independent sensor error source as a linear system of the navigation errors and
    ``k`` sensor states (its :class:`~imunav.sensors.terms.SensorErrorStates`).

    Attributes
    ----------
    states : SensorErrorStates
    sub : int
        Sub-steps per output step (``h/sub ≤`` :data:`MAX_DECAY_STEP` correlation times).
    """

    states: SensorErrorStates
    sub: int = 1

    @property
    def name(self) -> str:
        """``"gyro.bias"`` etc."""
        return self.states.name

    @property
    def size(self) -> int:
        """Sensor states ``k``."""
        return self.states.size

    @property
    def differenced(self) -> bool:
        """Whether the source is a differenced white error (quantised increments)."""
        return bool(self.states.differenced_white)

    def constant_input(self) -> FloatArray | None:
        """The input matrix ``M`` (3, k) if it does not depend on what the triad measures
        (a bias: the same every step), else None (a scale factor, a misalignment).

        Returns
        -------
        ndarray or None
        """
        u = np.array([[0.3, -1.1, 2.7], [-5.0, 0.7, 0.2]])
        f = np.array([[1.9, 0.4, -9.6], [0.1, -3.3, 4.4]])
        M = self.states.input_matrix(u, f)
        return M[0].copy() if np.array_equal(M[0], M[1]) else None

    @property
    def block_size(self) -> int:
        """States the propagation carries besides the navigation errors: ``size``, or 3 (the
        last quantisation residual) for a differenced source."""
        return 3 if self.differenced else self.size

    def initial_covariance(self) -> FloatArray:
        """``P₀`` of ``[e, x]``: the navigation errors 0, the sensor states ``states.P0``.

        Returns
        -------
        ndarray, shape (9 + k, 9 + k)
            ``k`` = :attr:`block_size`.
        """
        k = self.block_size
        P0 = np.zeros((NAV + k, NAV + k))
        if not self.differenced:
            P0[NAV:, NAV:] = self.states.P0
        return P0

    def noise_psd(self) -> FloatArray:
        """Diagonal PSD ``Qc`` of the white inputs.

        The triad's white noise on its navigation rows (isotropic, so ``C Q Cᵀ = Q``), then the
        driving noise of the sensor states.

        Returns
        -------
        ndarray, shape (9 + k,)
        """
        q = np.zeros(NAV)
        q[TRIAD_ROWS[self.states.triad]] = self.states.white_psd
        return np.concatenate([q, self.states.Qs])


@renamed(model="imu", output="kind")
def linearise(imu: ImuModel, traj: Trajectory, kind: str = "increments", decimate: int = 1
              ) -> tuple[list[ErrorSource], list[str]]:
    """Every registered sensor error term of ``imu`` as error sources along ``traj``.

    Parameters
    ----------
    imu : ImuModel
    traj : Trajectory
    kind : {"increments", "rates"}
        The signal kind (quantisation and aliasing differ).
    decimate : int
        Internal samples per output sample (``imu.decimation(rate)``).

    Returns
    -------
    sources : list of ErrorSource
        Gyro terms, then accelerometer terms; within a triad the white inputs (sources without
        states of their own: white noise, quantisation) first, then the sources with states,
        each group in registry order.
    warnings : list of str
        From the terms without a linear model (the motion exceeding a range).

    Raises
    ------
    NotImplementedError
        If a present term has a realisation but no linearisation.
    """
    sources, warnings = [], []
    for triad in ("gyro", "accel"):
        m = getattr(imu, triad)
        peak = traj.max_rate if triad == "gyro" else traj.max_force
        ctx = LinearisationContext(triad, traj.h, kind, decimate, peak, warnings)
        own = []
        for term in TERMS.values():
            if triad not in term.triads:
                continue
            for states in term.linearise(m, ctx):
                rate = np.max(np.abs(states.D), initial=0.0)
                sub = max(1, int(np.ceil(rate * traj.h / MAX_DECAY_STEP)))
                own.append(ErrorSource(states, sub))
        sources += sorted(own, key=lambda s: s.size > 0)          # stable: white inputs first
    return sources, warnings
