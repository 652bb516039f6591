"""What every aid is made of: its keys in ``AIDING.toml`` (with units and physical limits), its
readings, its measurement model for the filter, and the registry that lists the aids.

An aid (GNSS, a barometer, an odometer, …) is one :class:`AidSpec` registered in :data:`AIDS`
— as an IMU error term is one :class:`~imunav.sensors.terms.Term` of ``TERMS``. The spec holds
everything the rest of imunav asks of the aid:

- its ``AIDING.toml`` table: a configuration class whose :class:`Key` declarations give each
  key's unit, default and physical range (``from_dict`` reads and checks them all);
- its reading file (``file``, the accepted headers per frame, columns in degrees on the Earth)
  and the units of its innovation components (``units``);
- its simulation from the true motion (``simulate``, from its own random stream ``stream``);
- its measurement model for the filter (``measurement``: a :class:`Measurement` — prediction
  from the navigation state, Jacobian, noise, own error states) and the readings the filter
  uses (``readings``: a GNSS outage left out, a constraint applied at its rate, …);
- when it reads along a motion (``times``), for the covariance analysis.

Every list of aid names in imunav derives from :data:`AIDS` (in registration order, which is
also the order the filter uses the readings of one epoch). A new aid is one module with its
configuration, its measurement and its spec, plus one import in :mod:`imunav.sensors.aids`.

The measurement contract (:class:`Measurement`, :class:`NavPoint`) is what the filter calls;
:mod:`imunav.estimation.measurements` re-exports it. A measurement written by a user (a
subclass with ``name``, ``columns``, ``predict``, ``jacobian``, ``noise``) needs no spec: it is
given to the filter with its readings as an :class:`Aid`.

Error conventions (those of :mod:`imunav.estimation.error_model`): ``φ`` with
``C_est = (I − [φ×]) C_nb``, ``δv = v_est − v``, ``δp = p_est − p`` (indices
:data:`~imunav.core.layout.PHI`, :data:`~imunav.core.layout.DV`, :data:`~imunav.core.layout.DP`);
a sensor or aid error state ``x = s − ŝ`` (the true error minus its estimate). A measurement's
``jacobian`` is ``H`` with ``predicted(estimate) − predicted(truth) ≈ H e``; the filter forms
``z = predicted − measured ≈ H e − noise``.

The contract lives in two modules whose names are re-exported here: the ``AIDING.toml`` keys
(:mod:`~imunav.sensors.aids.keys`) and the measurement (:mod:`~imunav.sensors.aids.contract`).

May import: ``imunav.core``, ``imunav.earth``, ``imunav.motion``, ``imunav.sensors.signals``,
``imunav.sensors.aids.keys``, ``imunav.sensors.aids.contract``.
"""

from __future__ import annotations

import numpy as np

from imunav.core.kernels import FloatArray
from imunav.core.validation import ImunavError
from imunav.sensors.aids.contract import (
    Aid,
    AidStates,
    Measurement,
    NavPoint,
    Readings,
    euler_jacobian,
    wrap_angle,
    yaw_of,
)
from imunav.sensors.aids.keys import ANGLE_UNITS, Key, TableConfig, check_keys

__all__ = ["AIDS", "ANGLE_UNITS", "Aid", "AidSpec", "AidStates", "Key", "Measurement",
           "NavPoint", "Readings", "TableConfig", "check_keys", "euler_jacobian", "reading_times",
           "register", "wrap_angle", "yaw_of"]


def reading_times(rate: float, duration: float, t0: float = 0.0) -> FloatArray:
    """When a sensor at ``rate`` reads over ``duration`` from ``t0``: ``t0 + k/rate`` for
    ``k ≥ 1`` up to ``t0 + duration`` (the one schedule of the simulation, the filter's
    constraints and the covariance analysis).

    Parameters
    ----------
    rate : float
        Hz.
    duration : float
        Seconds.
    t0 : float
        Start (s).

    Returns
    -------
    ndarray, shape (k,)
    """
    n = int(np.floor(duration * rate * (1 + 1e-12)))
    return t0 + np.arange(1, n + 1) / rate


# ----------------------------------------------------------------------------- the registry

class AidSpec:
    """One kind of aid, everything imunav asks of it (see the module docstring).

    Subclasses set the class attributes and implement :meth:`measurement` and
    :meth:`simulate`; the defaults of the other methods fit an aid that reads at ``rate``
    from a file of its own.

    Attributes
    ----------
    name : str
        Its table in ``AIDING.toml``, its file's stem, its name in every report.
    summary : str
        What it measures (one line).
    config : type
        Its :class:`TableConfig`.
    file : str
        Its reading file (``gnss.csv``).
    headers : dict
        ``{frame: (header, …)}``: the headers its file may have, the full one first.
    degrees : tuple of str
        Columns written in degrees on the Earth (converted to rad on reading).
    intervals : bool
        The file holds ``[t0, t1]`` intervals (stance), not readings.
    stream : int
        Its random stream among the aiding sensors' (fixed: adding an aid changes no other).
    """

    name = ""
    summary = ""
    config: type = TableConfig
    file = ""
    headers: dict[str, tuple[tuple[str, ...], ...]] = {}
    degrees: tuple[str, ...] = ()
    intervals = False
    stream = 0

    def units(self, config) -> tuple[str, ...]:
        """The units of its innovation components (for the statistics table).

        Parameters
        ----------
        config : TableConfig

        Returns
        -------
        tuple of str
        """
        return ()

    def measurement(self, config, *, truth: bool = False) -> Measurement:
        """Its measurement model.

        Parameters
        ----------
        config : TableConfig
        truth : bool
            As the simulation makes the readings (a correlated error always as states),
            rather than as the filter assumes them.

        Returns
        -------
        Measurement
        """
        raise NotImplementedError

    def simulate(self, motion, config, t0: float, duration: float, rng: np.random.Generator,
                 imu_rate: float):
        """Its readings on the true motion, with its own errors.

        Parameters
        ----------
        motion : BaseMotion
        config : TableConfig
        t0, duration : float
            The record (s).
        rng : numpy.random.Generator
            Its own stream.
        imu_rate : float
            The IMU rate (Hz).

        Returns
        -------
        Readings or ndarray or None
            Readings; an ``(k, 2)`` array of intervals (:attr:`intervals`); None when the
            aid needs no file (found from the IMU data).
        """
        raise NotImplementedError

    def file_needed(self, config) -> bool:
        """Whether the filter needs its file (else it works without one).

        Parameters
        ----------
        config : TableConfig

        Returns
        -------
        bool
        """
        return True

    def rate(self, config) -> float | None:
        """How often it reads (Hz), if at a fixed rate.

        Parameters
        ----------
        config : TableConfig

        Returns
        -------
        float or None
        """
        return getattr(config, "rate", None)

    def readings(self, config, data, signals) -> Readings:
        """The readings the filter uses, from the data read or simulated.

        Parameters
        ----------
        config : TableConfig
        data : AidingData
        signals : ImuSignals
            The IMU record (an aid found from the IMU data, a constraint applied at the
            IMU's nodes).

        Returns
        -------
        Readings

        Raises
        ------
        ImunavError
            When its readings are missing.
        """
        r = data.get(self.name)
        if r is None:
            raise ImunavError(f"aiding has [{self.name}] but no {self.name} readings were "
                              "given", argument="data")
        return r

    def times(self, config, motion, rate: float, duration: float) -> FloatArray:
        """When it reads along a motion (the covariance analysis's schedule).

        Parameters
        ----------
        config : TableConfig
        motion : BaseMotion
        rate : float
            IMU rate (Hz).
        duration : float
            Seconds.

        Returns
        -------
        ndarray
        """
        return reading_times(config.rate, duration)

    def analysis_warnings(self, config) -> list[str]:
        """What the covariance analysis cannot model of this aid (none by default).

        Parameters
        ----------
        config : TableConfig

        Returns
        -------
        list of str
        """
        return []


#: The aids, in the order the filter uses the readings of one epoch.
AIDS: dict[str, AidSpec] = {}


def register(spec: AidSpec) -> AidSpec:
    """Add an aid to :data:`AIDS`.

    Parameters
    ----------
    spec : AidSpec

    Returns
    -------
    AidSpec

    Raises
    ------
    ValueError
        For a name or a random stream already taken.
    """
    if spec.name in AIDS or any(s.stream == spec.stream for s in AIDS.values()):
        raise ValueError(f"aid {spec.name!r} (stream {spec.stream}) is registered already")
    AIDS[spec.name] = spec
    return spec
