"""The initial alignment in the error state: what levelling from the accelerometer leaves.

An assessment that starts the navigation from the true attitude (``alignment="truth"``) charges
every accelerometer bias to the position: ``½ b t²``. A real strapdown system first *levels*: at
rest it averages its accelerometer over a window and takes roll and pitch from the measured
gravity (:func:`imunav.strapdown.initial.level_attitude`; the heading is given). The biased
accelerometer then tilts the initial attitude by just the angle that cancels its own horizontal
bias — the bias/tilt equivalence — and only what *changes* after the window (noise, a wandering
bias, errors that depend on the motion: scale factor, misalignment under acceleration) grows
into position.

``alignment="level"`` models that: the IMU is at rest at the motion's initial attitude ``q0``
for a window ``W`` before ``t = 0`` (it is switched on at ``−W``), levels from its mean
accelerometer output ``f̄ = f_s + δf̄`` over the window, and navigates from ``t = 0`` with the
true velocity and position. To first order the levelled attitude error is

    φ₀ = J δf̄,    δf̄ = (1/W) ∫_{−W}^{0} (M_s x(s) + w(s)) ds,

``J = ∂φ/∂f̄`` (:func:`levelling_jacobian`: at a level attitude ``φ₀ = (δf̄_y, −δf̄_x, 0)/g``),
``M_s`` the term's input matrix at rest. Each error source's initial covariance of
``[φ, δv, δp, x]`` (:func:`levelled_sources`) then couples φ₀ with the sensor states ``x(0)``
through the joint distribution of ``x(0)`` and ``∫ x ds`` over the window
(:func:`window_statistics`, exact for the states' linear dynamics). Gyro terms do not enter the
levelling, but a gyro random walk has grown over the window too. Per source, so the error
budget and the inverse design stay exact.

May import: ``imunav.core``, ``imunav.sensors``, ``imunav.estimation``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

from imunav.core.constants import G0
from imunav.core.kernels import FloatArray, quat_to_dcm
from imunav.core.rotations import quat_to_euler
from imunav.core.validation import ImunavError, check_gravity, check_positive
from imunav.estimation.discretisation import phi_functions
from imunav.estimation.error_model import NAV, PHI, ErrorSource
from imunav.sensors.simulate import interval_count
from imunav.sensors.terms import SensorErrorStates

__all__ = ["ALIGNMENTS", "WINDOW", "LevelledSource", "check_alignment", "levelled_sources",
           "levelling_jacobian", "window_samples", "window_statistics"]

#: The initial attitude of an assessment: the truth, or levelled from the accelerometer.
ALIGNMENTS = ("truth", "level")

#: Seconds at rest the levelling averages by default.
WINDOW = 10.0


def check_alignment(alignment: str, window: float, frame: str = "flat") -> tuple[str, float]:
    """``(alignment, window)`` checked: one of :data:`ALIGNMENTS`, a window > 0 s, and
    ``"level"`` on the flat frame only.

    Parameters
    ----------
    alignment : {"truth", "level"}
    window : float
        Seconds at rest averaged by the levelling.
    frame : {"flat", "wgs84"}
        The motion's frame.

    Returns
    -------
    tuple of (str, float)

    Raises
    ------
    ImunavError
        Naming ``alignment`` or ``align_window``.
    """
    if alignment not in ALIGNMENTS:
        raise ImunavError(f"alignment must be one of {', '.join(ALIGNMENTS)}, got {alignment!r}",
                          argument="alignment")
    window = check_positive(window, "align_window")
    if alignment == "level" and frame != "flat":
        raise ImunavError("alignment 'level' models levelling on the flat frame; on the "
                          "WGS-84 Earth use alignment 'truth'", argument="alignment")
    return alignment, float(window)


def window_samples(rate: float, window: float) -> int:
    """Output samples of a levelling window: ``round(window × rate)`` (at least one).

    Parameters
    ----------
    rate : float
        Output rate (Hz).
    window : float
        Seconds.

    Returns
    -------
    int
    """
    return interval_count(rate, window)


def levelling_jacobian(q0: npt.ArrayLike, g: float = G0) -> FloatArray:
    """``J = ∂φ/∂f̄``: the attitude error (navigation frame, ``Ĉ_nb = (I − [φ×]) C_nb``) that
    levelling at rest at attitude ``q0`` makes per m/s² of error in the mean accelerometer
    output (body axes), heading held.

    Levelling takes θ = atan2(f_x, √(f_y² + f_z²)) and φ = atan2(−f_y, −f_z) from the mean
    specific force and keeps the yaw; a change (dθ, dφ) turns the attitude by
    ``dθ·R_z(ψ) e_y + dφ·R_z(ψ) R_y(θ) e_x`` in the navigation frame, and φ is minus that.

    Parameters
    ----------
    q0 : array_like, shape (4,)
        The attitude ``q_nb`` at rest.
    g : float
        Gravity magnitude (m/s²).

    Returns
    -------
    ndarray, shape (3, 3)
        Level (``q0`` = identity): ``[[0, 1/g, 0], [−1/g, 0, 0], [0, 0, 0]]``.
    """
    g = check_gravity(g)
    q0 = np.asarray(q0, float)
    C = quat_to_dcm(q0)
    fx, fy, fz = C.T @ np.array([0.0, 0.0, -g])            # the accelerometer at rest
    rho2 = fy * fy + fz * fz
    rho = np.sqrt(rho2)
    dtheta = np.array([rho, -fx * fy / rho, -fx * fz / rho]) / (fx * fx + rho2)
    droll = np.array([0.0, fz, -fy]) / rho2
    yaw, pitch, _ = quat_to_euler(q0)
    cy, sy, cp, sp = np.cos(yaw), np.sin(yaw), np.cos(pitch), np.sin(pitch)
    about_pitch = np.array([-sy, cy, 0.0])                 # R_z(ψ) e_y
    about_roll = np.array([cy * cp, sy * cp, -sp])         # R_z(ψ) R_y(θ) e_x
    return -(np.outer(about_pitch, dtheta) + np.outer(about_roll, droll))


def window_statistics(states: SensorErrorStates, window: float
                      ) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The sensor states at the end of a window of ``window`` seconds that starts from their
    initial distribution (``x ~ N(0, P0)`` when the IMU is switched on), and their integral
    ``z = ∫ x ds`` over it: ``(Cov x(W), Cov(z, x(W)), Cov z)``.

    Per state (``ẋ = d x + w``, PSD ``q``), with ``a = e^{dW}`` and the φ-functions
    ``φ_i(d, W) = ∫₀ᵂ (W−s)^i/i! e^{ds} ds``:
    ``x(W) = a x₀ + …``, ``z = φ₀(d) x₀ + …``, and the driven parts
    ``Var x(W) = q φ₀(2d)``, ``Cov(z, x(W)) = q φ₀(d)²/2``, ``Var z = 2q (2φ₂(2d) − φ₂(d))``.

    Parameters
    ----------
    states : SensorErrorStates
    window : float
        Seconds (> 0).

    Returns
    -------
    Pxx, Pzx, Pzz : ndarray, shape (k, k)
    """
    W = check_positive(window, "align_window")
    d, q, P0 = states.D, states.Qs, states.P0
    p0, _, p2 = phi_functions(d, W)
    p0_2, _, p2_2 = phi_functions(2 * d, W)
    a = np.exp(d * W)
    Pxx = a[:, None] * P0 * a[None, :] + np.diag(q * p0_2)
    Pzx = p0[:, None] * P0 * a[None, :] + np.diag(q * p0 * p0 / 2)
    Pzz = p0[:, None] * P0 * p0[None, :] + np.diag(2 * q * (2 * p2_2 - p2))
    return Pxx, Pzx, Pzz


@dataclass
class LevelledSource(ErrorSource):
    """An error source whose navigation starts from a levelled attitude: its initial
    covariance of ``[φ, δv, δp, x]`` (:func:`levelled_sources`) instead of zero errors.

    Attributes
    ----------
    initial : ndarray, shape (9 + k, 9 + k)
        ``k`` = :attr:`block_size`.
    """

    initial: FloatArray | None = None

    def initial_covariance(self) -> FloatArray:
        """``P₀`` of ``[e, x]`` after levelling.

        Returns
        -------
        ndarray, shape (9 + k, 9 + k)
        """
        return self.initial.copy()


def levelled_sources(sources: list[ErrorSource], q0: npt.ArrayLike, window: float,
                     rate: float, g: float = G0) -> list[LevelledSource]:
    """Each error source with the initial covariance that levelling at rest at ``q0`` over
    ``window`` seconds leaves (see the module's docstring).

    Parameters
    ----------
    sources : list of ErrorSource
        From :func:`~imunav.estimation.error_model.linearise`.
    q0 : array_like, shape (4,)
        The motion's initial attitude: the IMU rests there during the window.
    window : float
        Seconds; the levelling averages ``round(window × rate)`` output samples.
    rate : float
        Output rate (Hz).
    g : float
        Gravity magnitude (m/s²).

    Returns
    -------
    list of LevelledSource
        In the order given.
    """
    W = window_samples(rate, window) / float(rate)
    J = levelling_jacobian(q0, g)
    f_s = (quat_to_dcm(np.asarray(q0, float)).T @ np.array([0.0, 0.0, -g]))[None]
    out = []
    for s in sources:
        st = s.states
        accel = st.triad == "accel"
        k = s.block_size
        P = np.zeros((NAV + k, NAV + k))
        if s.differenced:
            # the window's mean of (e_i − e_{i−1})/h telescopes to e(0)/W (the residual starts
            # at 0 when the IMU is switched on); e(0) is the state the navigation starts with
            var = st.differenced_white
            P[NAV:, NAV:] = var * np.eye(3)
            if accel:
                P[PHI, PHI] = var * J @ J.T / W ** 2
                P[PHI, NAV:] = var * J / W
        elif st.size:
            Pxx, Pzx, Pzz = window_statistics(st, W)
            P[NAV:, NAV:] = Pxx
            if accel:
                JM = J @ st.input_matrix(f_s, f_s)[0] / W          # φ₀ per unit of ∫x
                P[PHI, PHI] = JM @ Pzz @ JM.T
                P[PHI, NAV:] = JM @ Pzx
        if accel and st.white_psd:
            P[PHI, PHI] += st.white_psd / W * J @ J.T                # the window's mean noise
        P[NAV:, :NAV] = P[:NAV, NAV:].T
        out.append(LevelledSource(st, s.sub, initial=P))
    return out
