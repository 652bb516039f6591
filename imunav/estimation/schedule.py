"""When each reading is used: readings mapped to the IMU's nodes — the one schedule of the filter
and of the covariance analysis.

A reading at time ``t`` is used at the nearest node ``k`` (a multiple of the strapdown
algorithm's sample group ``align``) with ``dt = t − t_k``; the readings of one node are used in
the order of the aids (then of their times). Between two nodes with readings, the covariance is
propagated in steps of at most ``covariance_step`` (:meth:`Schedule.bounds`).

May import: ``imunav.core``.
"""

from __future__ import annotations

import numpy as np

from imunav.core.kernels import FloatArray
from imunav.core.validation import ImunavError

__all__ = ["Schedule", "step_length"]


def step_length(covariance_step: float, h: float, align: int) -> int:
    """The covariance step in IMU intervals: ``covariance_step`` rounded to whole intervals, a
    multiple of ``align`` (at least one group).

    Parameters
    ----------
    covariance_step : float
        Seconds.
    h : float
        IMU interval (s).
    align : int
        The algorithm's sample group.

    Returns
    -------
    int
    """
    m = max(1, int(round(covariance_step / h)))
    return max(align, m // align * align)


class Schedule:
    """Readings mapped to the nodes ``0 … N`` of a record starting at ``t0`` with interval ``h``.

    Parameters
    ----------
    t0 : float
        The first node's time (s).
    h : float
        The interval (s).
    N : int
        Intervals.
    align : int
        Nodes used are multiples of it.

    Attributes
    ----------
    at : dict
        ``{node: [(aid, reading, dt, t), …]}``: per node the aid's index (in the order they were
        added), the reading's index, its time offset from the node and its time.
    """

    def __init__(self, t0: float, h: float, N: int, align: int = 1):
        self.t0, self.h, self.N, self.align = float(t0), float(h), int(N), int(align)
        self.at: dict[int, list[tuple[int, int, float, float]]] = {}

    @property
    def end(self) -> float:
        """The last node's time (s).

        Returns
        -------
        float
        """
        return self.t0 + self.N * self.h

    def node(self, t: FloatArray, name: str = "reading") -> tuple[np.ndarray, FloatArray]:
        """The node of each time and the offset from it.

        Parameters
        ----------
        t : ndarray
            Times (s).
        name : str
            What they are (for the message).

        Returns
        -------
        k : ndarray of int
        dt : ndarray

        Raises
        ------
        ImunavError
            For a time outside the record.
        """
        t = np.asarray(t, dtype=float)
        end = self.end
        tol = 1e-9 * max(1.0, abs(end))
        bad = (t < self.t0 - tol) | (t > end + tol)
        if bad.any():
            i = int(np.argmax(bad))
            raise ImunavError(f"{name} reading {i} at t = {t[i]:.9g} s lies outside the IMU "
                              f"record ({self.t0:.9g} … {end:.9g} s)", argument=name)
        k = np.rint((t - self.t0) / self.h / self.align).astype(int) * self.align
        k = np.clip(k, 0, self.N)
        return k, t - (self.t0 + k * self.h)

    def add(self, aid: int, t: FloatArray, name: str = "reading") -> None:
        """Schedule the readings of one aid.

        Parameters
        ----------
        aid : int
            Its index.
        t : ndarray
            Its reading times (s).
        name : str
            Its name (for messages).
        """
        k, dt = self.node(t, name)
        for j in range(k.size):
            self.at.setdefault(int(k[j]), []).append((aid, j, float(dt[j]), float(t[j])))

    def epochs(self) -> list[int]:
        """The nodes with readings after the start, and the last node.

        Returns
        -------
        list of int
        """
        out = sorted(k for k in self.at if k > 0)
        if not out or out[-1] != self.N:
            out.append(self.N)
        return out

    def bounds(self, step: int) -> list[int]:
        """Every covariance epoch: the nodes with readings, and steps of at most ``step``
        intervals between them (from node 0).

        Parameters
        ----------
        step : int
            Intervals.

        Returns
        -------
        list of int
        """
        out, a = [0], 0
        for b in self.epochs():
            out += list(range(a, b, step))[1:] + [b]
            a = b
        return out

    def same_as(self, other: Schedule) -> bool:
        """Whether two schedules use the same readings at the same nodes and times.

        Parameters
        ----------
        other : Schedule

        Returns
        -------
        bool
        """
        return self.at.keys() == other.at.keys() and all(
            [(a, j, t) for a, j, _, t in self.at[k]] == [(a, j, t) for a, j, _, t in other.at[k]]
            for k in self.at)
