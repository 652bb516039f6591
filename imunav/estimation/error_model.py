"""The navigation error model: the error state, its continuous dynamics along a trajectory, and
how each sensor error term enters it.

Error state (flat, non-rotating NED, as the navigation), indices :data:`PHI`, :data:`DV`,
:data:`DP`, then the states of the sensor error terms::

    φ   attitude error, C_est = (I − [φ×]) C_nb        φ̇  = −C_nb δω
    δv  velocity error                                δv̇ = [f_n×] φ + C_nb δf
    δp  position error                                δṗ = δv

with ``f_n = a_n − g_n`` the specific force in the navigation frame and ``δω``, ``δf`` the gyro
and accelerometer errors. A sensor error term (:mod:`imunav.sensors.terms`) linearises itself
as ``k`` states ``x`` with ``ẋ = diag(D) x + w`` entering its triad as ``δu = M(t) x``, plus white
noise; here that becomes an :class:`ErrorSource`: the system

    d/dt [e; x] = [[A(t), B(t)], [0, diag(D)]] [e; x] + G(t) w,      B = [−C M; 0; 0] (gyro)
                                                                       or [0; C M; 0] (accel)

The frame enters only through the navigation block ``A(t)`` (:meth:`FlatErrorModel.nav_matrix`),
the exact discretisation of a step (:meth:`FlatErrorModel.discretise`) and the map of the error
state onto the errors a user reads (:meth:`FlatErrorModel.local`: the identity here).

**On the rotating Earth** (:class:`EarthErrorModel`, ``Trajectory.of`` an
:class:`~imunav.motion.geodetic.EarthMotion`) the error state is that of the navigation's own
frame, the inertial frame ``i`` that coincides with ECEF at ``t = 0``
(:mod:`imunav.strapdown.rotating`): φ, δv, δr in ``i``, ``Ĉ_ib = (I − [φ×]) C_ib``, and

    φ̇ = −C_ib δω,    δv̇ = [f_i×] φ + Γ δr + C_ib δf,    δṙ = δv,

with ``f_i = C_ib f^b`` and ``Γ = ∂G/∂r`` the gradient of the gravitation
(:func:`imunav.earth.gravitation_gradient`: +2g/R vertically, −g/R horizontally — the Schuler
loop and the unstable vertical channel). The Earth rate and the transport rate are not lost:
they are in ``C_ib`` and ``f_i``, which turn with the Earth and the vehicle, and in the exact
map onto the errors in the local NED frame at the true position (:meth:`EarthErrorModel.local`),

    φ_n = C_ni φ + K C_ni δr,   δv_n = C_ni δv − C_ni [Ω×] δr + [v_n×] K C_ni δr,   δp_n = C_ni δr,

``K`` the curvature matrix (:func:`imunav.earth.curvature_matrix`; the frame at the estimated
position is turned by ``K δp``) and Ω the Earth rate — so the local-level error equations of
the textbooks (Earth-rate coupling, the Coriolis terms, the Foucault turn of the Schuler
oscillation) follow from these (``tests/estimation/test_error_model_earth.py`` checks them against the
closed forms and Monte Carlo of the full nonlinear chain). An aided filter on the Earth uses the
same state: a measurement of ECEF position, say, has ``H = C_ei [0, 0, I]``.

The model lives in four modules, re-exported here (the documented home of its names): the
nominal trajectory (:mod:`~imunav.estimation.nominal`: :class:`Trajectory`,
:class:`LazyTrajectory`, :func:`local_error_map`), the sensor terms as error sources
(:mod:`~imunav.estimation.error_sources`: :class:`ErrorSource`, :func:`linearise`), the flat
frame's dynamics (:mod:`~imunav.estimation.flat_model`: :class:`FlatErrorModel`, :data:`FLAT`)
and the Earth's (:mod:`~imunav.estimation.earth_model`: :class:`EarthErrorModel`,
:data:`EARTH`, :data:`EARTH_HOLD`); :func:`frame_model` picks the model of a trajectory's frame.
(It was called ``error_model``, the name of this module, which it hid: the old call still
works for one release with a warning.)

May import: ``imunav.core``, ``imunav.estimation`` modules below (the four above).
"""

from __future__ import annotations

from imunav.core.deprecation import callable_module, deprecated_names
from imunav.core.layout import DP, DV, NAV, PHI
from imunav.core.validation import ImunavError
from imunav.estimation.earth_model import EARTH, EARTH_HOLD, EarthErrorModel
from imunav.estimation.error_sources import MAX_DECAY_STEP, TRIAD_ROWS, ErrorSource, linearise
from imunav.estimation.flat_model import FLAT, FlatErrorModel
from imunav.estimation.nominal import LazyTrajectory, Trajectory, local_error_map

__all__ = ["DP", "DV", "EARTH", "EARTH_HOLD", "FLAT", "MAX_DECAY_STEP", "NAV", "PHI",
           "TRIAD_ROWS", "EarthErrorModel", "ErrorSource", "FlatErrorModel", "LazyTrajectory",
           "Trajectory", "frame_model", "linearise", "local_error_map"]


def frame_model(traj: Trajectory, vertical: str = "free") -> FlatErrorModel:
    """The error model of ``traj``'s frame: :data:`FLAT`, :data:`EARTH` or :data:`EARTH_HOLD`.

    Parameters
    ----------
    traj : Trajectory
    vertical : {"free", "hold"}
        On the Earth: the vertical channel free or held (a perfect height aid).

    Returns
    -------
    FlatErrorModel

    Raises
    ------
    ImunavError
        For ``vertical="hold"`` in the flat frame, or another value.
    """
    if vertical not in ("free", "hold"):
        raise ImunavError(f"vertical must be 'free' or 'hold', got {vertical!r}",
                          argument="vertical")
    if traj.frame != "wgs84":
        if vertical == "hold":
            raise ImunavError("vertical='hold' applies to the WGS-84 Earth only",
                              argument="vertical")
        return FLAT
    return EARTH_HOLD if vertical == "hold" else EARTH



#: ``error_model`` (the function) was renamed: it hid this module of the same name.
__getattr__ = deprecated_names(__name__, {
    "error_model": (frame_model, "imunav.estimation.error_model.frame_model")})
callable_module(__name__, "error_model", frame_model, "imunav.estimation.frame_model")
