"""Covariance propagation of the navigation errors, step by step along a trajectory.

Each :class:`~imunav.estimation.error_model.ErrorSource` is independent of the others, so its
covariance is propagated on its own (``P ← Φ P Φᵀ + Q_d`` per sub-step) and the total is the
sum. The trajectory is taken in pieces of :data:`CHUNK` steps (:func:`propagate_chunks`): the
discrete systems of one piece are built together (vectorised), the covariances carried from
piece to piece, and only the navigation block of each step is handed out — so the memory of the
propagation itself does not grow with the record; :func:`propagate` collects every step.
Sources with the same state size and sub-stepping are propagated together (one batched product
per step instead of one per source and step).

A quantisation error of increments with a carried residual (differenced white noise,
``δu_k = (e_k − e_{k−1})/h``) is propagated exactly with the last ``e`` as 3 extra states.

May import: ``imunav.core``, ``imunav.estimation``.
"""

from __future__ import annotations

from collections.abc import Iterator

import numpy as np

from imunav.core.kernels import FloatArray, skew
from imunav.estimation.discretisation import flat_transition
from imunav.estimation.error_model import FLAT, NAV, ErrorSource, FlatErrorModel, Trajectory

__all__ = ["CHUNK", "propagate", "propagate_chunks"]

#: Steps of the trajectory whose discrete systems are built at once.
CHUNK = 1024


def propagate_chunks(sources: list[ErrorSource], traj: Trajectory,
                     model: FlatErrorModel = FLAT, chunk: int = CHUNK
                     ) -> Iterator[tuple[int, int, list[FloatArray]]]:
    """Propagate every source along ``traj`` a piece at a time.

    Parameters
    ----------
    sources : list of ErrorSource
    traj : Trajectory
    model : FlatErrorModel
        The error model (its ``discretise`` and ``transition``).
    chunk : int
        Steps per piece.

    Yields
    ------
    lo, hi : int
        The piece: steps ``lo … hi − 1``.
    covariances : list of ndarray, shape (hi − lo, 9, 9)
        Per source (in the order given), the navigation-error covariance at the end of each
        step of the piece (times ``t_{lo+1} … t_hi``).
    """
    N = traj.steps
    groups: dict[tuple[int, int], list[int]] = {}
    diff = []
    for j, s in enumerate(sources):
        if s.differenced:
            diff.append(j)
        else:
            groups.setdefault((NAV + s.size, s.sub), []).append(j)
    P = {key: np.stack([sources[j].initial_covariance() for j in members])
         for key, members in groups.items()}
    Pd = {j: np.zeros((NAV + 3, NAV + 3)) for j in diff}
    for lo in range(0, N, chunk):
        hi = min(N, lo + chunk)
        piece = traj.piece(lo, hi)
        out: list[FloatArray | None] = [None] * len(sources)
        for key, members in groups.items():
            sub = key[1]
            systems = [model.discretise(piece, sources[j]) for j in members]
            Phi = np.stack([s[0] for s in systems], axis=1)          # (n, T, m, m)
            Qd = np.stack([s[1] for s in systems], axis=1)
            PhiT = np.swapaxes(Phi, -1, -2)
            hist = np.empty((hi - lo, len(members), NAV, NAV))
            Pk = P[key]
            for i in range(hi - lo):
                Pi, PiT, Qi = Phi[i], PhiT[i], Qd[i]
                for _ in range(sub):
                    Pk = Pi @ Pk @ PiT + Qi
                hist[i] = Pk[:, :NAV, :NAV]
            P[key] = Pk
            for c, j in enumerate(members):
                out[j] = hist[:, c]
        for j in diff:
            out[j], Pd[j] = _differenced(sources[j], piece, Pd[j])
        yield lo, hi, out


def _differenced(source: ErrorSource, traj: Trajectory, P: FloatArray
                 ) -> tuple[FloatArray, FloatArray]:
    """A differenced white input over the steps of ``traj``: the state augmented with the last
    ``e`` (3 states); over each step the rate error is constant, ``(e_k − e_{k−1})/h``."""
    var = source.states.differenced_white
    N, h = traj.steps, traj.h
    F = skew(traj.f_n)
    B = FLAT.sensor_input(traj, source.states)
    Phi = flat_transition(F, np.zeros((N, NAV, 0)), np.zeros(0), h)
    # response at the step's end to a unit constant input through B: Γ = Σ Aⁱ B hⁱ⁺¹/(i+1)!
    G = flat_transition(F, B, np.zeros(3), h)[:, :NAV, NAV:]
    out = np.empty((N, NAV, NAV))
    for i in range(N):
        T = np.zeros((NAV + 3, NAV + 3))
        T[:NAV, :NAV] = Phi[i]
        T[:NAV, NAV:] = -G[i] / h                        # − e_{k−1}/h
        W = np.concatenate([G[i] / h, np.eye(3)])        # + e_k/h, and e_k becomes the new state
        P = T @ P @ T.T + var * W @ W.T
        out[i] = P[:NAV, :NAV]
    return out, P


def propagate(sources: list[ErrorSource], traj: Trajectory, model: FlatErrorModel = FLAT,
              chunk: int = CHUNK) -> list[FloatArray]:
    """The navigation-error covariance of each source at every output time.

    Parameters
    ----------
    sources : list of ErrorSource
    traj : Trajectory
    model : FlatErrorModel
    chunk : int
        Steps per piece (:func:`propagate_chunks`); the result does not depend on it.

    Returns
    -------
    list of ndarray, shape (N + 1, 9, 9)
        Per source, at ``t_0 … t_N`` (the first is the initial covariance of the navigation
        errors, zero).
    """
    N = traj.steps
    hist = [np.empty((N + 1, NAV, NAV)) for _ in sources]
    for h in hist:
        h[0] = 0.0
    for lo, hi, covs in propagate_chunks(sources, traj, model, chunk):
        for h, c in zip(hist, covs, strict=True):
            h[lo + 1:hi + 1] = c
    return hist
