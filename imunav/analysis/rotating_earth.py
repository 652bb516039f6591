"""Studies of navigation on the rotating Earth: the free error dynamics (Schuler, Foucault, the
Earth-rate loop, the unstable vertical channel), the response to a known sensor bias, and when
the flat frame suffices.

- :func:`local_error_dynamics` — the error dynamics in the local NED frame along a motion,
  ``A_n = Ḣ H⁻¹ + H A H⁻¹`` from the inertial-frame model (:class:`~imunav.estimation.EarthErrorModel`)
  and its output map ``H``: the matrix of the textbooks' local-level error equations.
- :func:`error_periods` — its eigenvalues for a vehicle at constant velocity, classified.
- :func:`bias_response` — the NED position, velocity and attitude errors a known constant bias
  gives, through the same error model (free or with the vertical held).
- :func:`flat_frame_error` — what ignoring the Earth costs: the error of navigating the rotating
  Earth's ideal signals in the flat frame.
- :func:`flat_frame_suffices` — for IMU models, how long that cost stays below the IMU's own
  error (the 95th percentile of a flat-frame covariance analysis).

May import: ``imunav.core``, ``imunav.earth``, ``imunav.motion``, ``imunav.sensors``,
``imunav.strapdown``, ``imunav.estimation``, ``imunav.analysis``.
"""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from imunav.analysis.covariance import covariance
from imunav.analysis.metrics import nav_errors
from imunav.core.kernels import FloatArray
from imunav.core.validation import ImunavError, check_positive
from imunav.earth import check_origin, normal_gravity
from imunav.estimation.error_model import EARTH, NAV, Trajectory, frame_model, linearise
from imunav.motion.analytic import Motion
from imunav.motion.base import BaseMotion
from imunav.motion.geodetic import EarthMotion
from imunav.sensors.models import ImuModel, TriadModel
from imunav.sensors.simulate import simulate_imu
from imunav.strapdown.registry import navigate

__all__ = ["bias_response", "error_periods", "flat_frame_error", "flat_frame_suffices",
           "local_error_dynamics"]


def local_error_dynamics(motion: EarthMotion, rate: float, t: float) -> FloatArray:
    """The 9×9 error dynamics in the local NED frame at time ``t`` of ``motion``:
    ``A_n = Ḣ H⁻¹ + H A H⁻¹`` (φ, δv, δp in NED), ``A`` the inertial-frame model's and ``H`` its
    map onto the local errors (``Ḣ`` by a central difference over one step of ``1/rate``).

    Parameters
    ----------
    motion : EarthMotion
    rate : float
        Sampling of the difference (Hz).
    t : float
        Time (s), at least one step inside the motion.

    Returns
    -------
    ndarray, shape (9, 9)
    """
    rate = check_positive(rate, "rate")
    h = 1.0 / rate
    k = int(round(t * rate))
    if k < 1:
        raise ImunavError("t must be at least one step (1/rate) into the motion", argument="t")
    traj = Trajectory.of(motion, rate, (k + 1) * h)
    A = EARTH.nav_matrix(traj)
    H = traj.output
    Hi = np.linalg.inv(H[k])
    return (H[k + 1] - H[k - 1]) / (2 * h) @ Hi + H[k] @ (0.5 * (A[k - 1] + A[k])) @ Hi


def error_periods(lat: float, speed_east: float = 0.0, h: float = 0.0) -> list[dict]:
    """The modes of the free error dynamics of a vehicle at latitude ``lat`` driving east at
    ``speed_east``: the eigenvalues of :func:`local_error_dynamics`, classified.

    Parameters
    ----------
    lat : float
        Latitude (rad).
    speed_east : float
        Speed (m/s) due east, constant (a steady motion: the local dynamics are constant).
    h : float
        Height (m).

    Returns
    -------
    list of dict
        ``{"mode", "rate_rad_s", "period_s"}`` (``period_s`` None for real modes, whose
        ``rate_rad_s`` is the growth or decay rate): the two Schuler modes split by the Foucault
        rate, the Earth-rate loop, the vertical pair and the heading mode (≈ 0).
    """
    lat, _, h = check_origin(lat, 0.0, h, "lat")
    m = EarthMotion(Motion(y=f"{float(speed_east)!r}*t", duration=60.0), (lat, 0.0, h))
    ev = np.linalg.eigvals(local_error_dynamics(m, 1.0, 30.0))
    osc = sorted({round(abs(e.imag), 15) for e in ev if abs(e.imag) > 1e-7})
    real = sorted(float(e.real) for e in ev if abs(e.imag) <= 1e-7)
    out = []
    names = {0: "Earth-rate loop (+ transport rate)",
             1: "Schuler − Foucault", 2: "Schuler + Foucault"}
    for i, w in enumerate(osc):
        out.append({"mode": names.get(i, f"oscillation {i}"), "rate_rad_s": w,
                    "period_s": 2 * np.pi / w})
    for r in real:
        mode = ("vertical, growing" if r > 1e-5 else "vertical, decaying" if r < -1e-5
                else "heading (no feedback)")
        out.append({"mode": mode, "rate_rad_s": r, "period_s": None})
    return out


def bias_response(motion: EarthMotion, rate: float, duration: float, *,
                  accel: npt.ArrayLike = (0.0, 0.0, 0.0), gyro: npt.ArrayLike = (0.0, 0.0, 0.0),
                  vertical: str = "free") -> dict:
    """The errors a known constant bias gives along ``motion``, through the error model.

    Parameters
    ----------
    motion : EarthMotion
    rate : float
        Step of the model (Hz).
    duration : float
        Seconds.
    accel, gyro : array_like, shape (3,)
        Constant biases in the body frame (m/s², rad/s).
    vertical : {"free", "hold"}
        The vertical channel free or held (a perfect height aid).

    Returns
    -------
    dict
        ``t`` (N+1,), ``position`` (N+1, 3) NED metres, ``velocity`` (N+1, 3) NED m/s and
        ``attitude`` (N+1, 3) rad, the errors in the local NED frame.
    """
    traj = Trajectory.of(motion, rate, duration)
    em = frame_model(traj, vertical)
    ba = np.asarray(accel, dtype=float)
    bg = np.asarray(gyro, dtype=float)
    parts = []
    for triad, b in (("gyro", bg), ("accel", ba)):
        if np.any(b):
            m = ImuModel(TriadModel(bias=1.0) if triad == "gyro" else TriadModel(),
                         TriadModel(bias=1.0) if triad == "accel" else TriadModel())
            src = next(s for s in linearise(m, traj, "increments")[0] if s.states.triad == triad)
            parts.append((em.discretise(traj, src)[0], b))
    xs = np.zeros((traj.steps + 1, NAV))
    for Phi, b in parts:                       # independent: the responses add
        z = np.concatenate([np.zeros(NAV), b])
        out = [z[:NAV]]
        for i in range(traj.steps):
            z = Phi[i] @ z
            out.append(z[:NAV])
        xs += np.array(out)
    loc = np.einsum("nij,nj->ni", traj.output, xs)
    return {"t": traj.t, "attitude": loc[:, 0:3], "velocity": loc[:, 3:6],
            "position": loc[:, 6:9]}


def flat_frame_error(motion: BaseMotion, origin: tuple[float, float, float], rate: float,
                     duration: float | None = None, algorithm: str | None = None) -> dict:
    """What ignoring the Earth costs: an ideal IMU moving as ``motion`` (read in the local NED
    frame at ``origin``) on the rotating Earth, its signals navigated in the flat frame (gravity
    the normal gravity at the origin), against the same motion in the flat frame.

    Parameters
    ----------
    motion : BaseMotion
        A motion in the flat local frame.
    origin : tuple of float
        ``(lat, lon, h)`` (rad, rad, m).
    rate : float
        Sample rate (Hz).
    duration : float, optional
        Seconds; default the motion's own.
    algorithm : str, optional
        Strapdown algorithm (default the registry's).

    Returns
    -------
    dict
        ``t``, ``position`` (m, the norm), ``attitude`` (rad) of the flat navigation's error
        against the local truth.
    """
    on_earth = EarthMotion(motion, origin)
    sig = simulate_imu(on_earth, rate, duration, kind="increments")
    g = float(normal_gravity(origin[0], origin[2]))
    nav = navigate(sig, *motion.states([sig.t0]).initial(), algorithm=algorithm, g=g)
    e = nav_errors(nav, motion)
    return {"t": nav.t, "position": e.position, "attitude": e.attitude}


def flat_frame_suffices(motion: BaseMotion, origin: tuple[float, float, float],
                        models: dict[str, ImuModel], rate: float = 10.0,
                        duration: float | None = None, cov_rate: float = 1.0,
                        percentile: float = 95.0) -> list[dict]:
    """For each IMU model: how long navigating in the flat frame costs less than the IMU's own
    error — the first time the error of :func:`flat_frame_error` exceeds the IMU's
    ``percentile`` position error (a flat-frame covariance analysis of the same motion at
    ``cov_rate``).

    Parameters
    ----------
    motion : BaseMotion
        A motion in the flat local frame.
    origin : tuple of float
        ``(lat, lon, h)`` (rad, rad, m).
    models : dict of str → ImuModel
    rate : float
        Sample rate of the flat-frame navigation (Hz).
    duration : float, optional
        Seconds; default the motion's own.
    cov_rate : float
        Rate of the covariance analysis (Hz).
    percentile : float
        The IMU's error level (a percentile of the position error norm).

    Returns
    -------
    list of dict
        ``{"imu", "seconds"}``: ``seconds`` None if the flat frame's cost stays below over
        the whole duration.
    """
    flat = flat_frame_error(motion, origin, rate, duration)
    out = []
    for name, model in models.items():
        cov = covariance(motion, model, cov_rate, duration)
        own = cov.position_quantile(percentile / 100)
        cost = np.interp(cov.t, flat["t"], flat["position"])
        over = np.nonzero((cost > own) & (cov.t > 0))[0]
        out.append({"imu": name, "seconds": float(cov.t[over[0]]) if over.size else None,
                    "own_error_at_end_m": float(own[-1]), "flat_cost_at_end_m": float(cost[-1])})
    return out
