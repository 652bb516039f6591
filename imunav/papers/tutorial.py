"""The gyroscope quaternion-integration tutorial (MATLAB example, after Madgwick's library).

Faithful reproduction: ``dt = 0.5`` s, loop ``i = 2..100``; ``Sw = [0, π/8, 0, 0]`` (X) while
``i < 50`` else ``[0, 0, π/16, 0]`` (Y); ``Q(i) = Q(i−1) + ½ Q(i−1) ⊗ Sw · dt``, normalised;
points rotated by ``M = quatern2rotMat(Q(i))``. Madgwick's ``quatern2rotMat`` returns the
*transpose* of the rotation matrix of ``q`` (his quaternions describe the earth frame relative
to the sensor), so the plotted points turn the opposite way to the body; we keep that for the
reproduction and say so.

The exact update for a rate that is constant over each step, ``Q(i) = Q(i−1) ⊗ exp(ω dt)``,
is the true rotation here (the rate is piecewise constant), so the first-order error can be
measured exactly.

May import: anything below the papers (``imunav.core`` … ``imunav.io``), ``imunav.symbolic``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from imunav.analysis import recordings as R
from imunav.analysis.metrics import fit_order
from imunav.core.kernels import quat_angle as _angle
from imunav.core.kernels import quat_exp as _exp
from imunav.core.kernels import quat_mul as _mul
from imunav.core.kernels import quat_to_dcm as _dcm
from imunav.core.rotations import FloatArray
from imunav.core.validation import ImunavError, check_positive
from imunav.motion.analytic import Motion
from imunav.papers.records import record
from imunav.sensors.models import ImuModel
from imunav.sensors.simulate import simulate_imu
from imunav.strapdown.scan import cumulative_product

#: The document, as its text prints it: no author, year, venue or DOI ("Credit: based on the
#: Madgwick's quaternion library for Matlab").
CITATION = {"authors": None, "title": "gyroscope quaternion-integration tutorial (web page)",
            "venue": None, "year": None, "doi": None}


P0 = np.array([1.0, 2.0, 3.0])
PX0, PY0, PZ0 = np.array([2.0, 2.0, 3.0]), np.array([1.0, 3.0, 3.0]), np.array([1.0, 2.0, 4.0])
UPDATES = ("first_order", "exact")
#: Readable names of the two updates.
UPDATE_NAMES = {"first_order": "first-order + normalise (the tutorial's)",
                "exact": "exact rotation"}
#: Stored figures' resolution (dpi).
FIG_DPI = 150


def quatern2rotMat(q: FloatArray) -> FloatArray:
    """Madgwick's ``quatern2rotMat``: the transpose of the rotation matrix of ``q``."""
    return np.swapaxes(_dcm(q / np.linalg.norm(q, axis=-1, keepdims=True)), -1, -2)


@dataclass
class TutorialRun:
    t: FloatArray          # (n,)
    rates: FloatArray      # (n−1, 3) body rate used on each step
    Q: FloatArray          # (n, 4)
    P: FloatArray          # (n, 3) rotated point and its axis markers
    PX: FloatArray
    PY: FloatArray
    PZ: FloatArray


def run(dt: float = 0.5, steps: int = 100, rate_x: float = np.pi / 8, rate_y: float = np.pi / 16,
        switch: int = 50, update: str = "first_order", duration: float | None = None) -> TutorialRun:
    """The tutorial's loop. ``duration`` (s), if given, overrides ``steps`` (the loop then runs
    ``duration/dt`` steps: 99 for 49.5 s at 0.5 s, as the example) and puts the switch at the
    same time as the example's (``(switch − 1)·0.5`` s), for convergence studies at other
    ``dt``."""
    dt = check_positive(dt, "dt")
    if update not in UPDATES:
        raise ImunavError(f"update must be one of {UPDATES}, got {update!r}")
    if duration is not None:
        steps = int(round(duration / dt)) + 1          # the loop runs steps − 1 steps
        t_switch = (switch - 1) * 0.5
    else:
        t_switch = (switch - 1) * dt
    i = np.arange(2, steps + 1)                      # MATLAB's loop index
    t_step = (i - 1) * dt                            # end time of step i
    on_x = t_step < t_switch - 1e-9 * dt             # i < switch ⇔ (i−1)·dt < (switch−1)·dt
    w = np.where(on_x[:, None], [rate_x, 0.0, 0.0], [0.0, rate_y, 0.0])
    Q = np.empty((steps, 4))
    Q[0] = [1.0, 0.0, 0.0, 0.0]
    if update == "first_order":
        for k in range(1, steps):
            q = Q[k - 1]
            qdot = _mul(0.5 * q, np.concatenate([[0.0], w[k - 1]]))   # quaternProd(0.5*Q, Sw)
            q = q + qdot * dt
            Q[k] = q / np.linalg.norm(q)
    else:
        for k in range(1, steps):
            Q[k] = _mul(Q[k - 1], _exp(w[k - 1] * dt))
    M = quatern2rotMat(Q)
    pts = [np.einsum("kij,j->ki", M, p) for p in (P0, PX0, PY0, PZ0)]
    return TutorialRun(np.arange(steps) * dt, w, Q, *pts)


def schedule(dt: float = 0.5, steps: int = 100, switch: int = 50) -> dict:
    """What the MATLAB loop actually runs: ``for i=2:100`` is 99 steps of ``dt`` (49.5 s), the
    X rotation while ``i < 50`` (48 steps: 24 s), the Y rotation for ``i = 50..100`` (51 steps:
    25.5 s) — the text says 50 s, 25 s + 25 s (and the code's comments "50 first/last steps")."""
    i = np.arange(2, steps + 1)
    return {"x_s": float(np.sum(i < switch) * dt), "y_s": float(np.sum(i >= switch) * dt),
            "total_s": float(i.size * dt), "x_steps": int(np.sum(i < switch)),
            "y_steps": int(np.sum(i >= switch))}


def madgwick_rotmat_raw(q: FloatArray) -> FloatArray:
    """Madgwick's ``quatern2rotMat`` exactly as written (``2q₀² − 1 + 2q₁²`` …): it assumes a unit
    quaternion and does not normalise, so a grown quaternion scales and shears the points."""
    w, x, y, z = np.moveaxis(np.asarray(q, float), -1, 0)
    return np.stack([
        np.stack([2 * w * w - 1 + 2 * x * x, 2 * (x * y + w * z), 2 * (x * z - w * y)], -1),
        np.stack([2 * (x * y - w * z), 2 * w * w - 1 + 2 * y * y, 2 * (y * z + w * x)], -1),
        np.stack([2 * (x * z + w * y), 2 * (y * z - w * x), 2 * w * w - 1 + 2 * z * z], -1)], -2)


def unnormalised(dt: float = 0.5, steps: int = 100, rate_x: float = np.pi / 8,
                 rate_y: float = np.pi / 16, switch: int = 50) -> dict:
    """The example without its normalisation line. Each first-order step multiplies |Q| by
    √(1 + (|ω| dt/2)²) exactly (``Q ⊗ [0, ω]`` is orthogonal to ``Q``), so the final norm has
    the closed form ∏ √(1 + (|ω_k| dt/2)²); the direction is the same as with normalisation
    (the update is linear in Q). The points, rotated by the raw ``quatern2rotMat``, leave the
    sphere they should stay on. Returns the computed and closed-form final norm, the final
    angle to the normalised run, and the largest relative change of |P|."""
    sch = schedule(dt, steps, switch)
    Q = np.empty((steps, 4))
    Q[0] = [1.0, 0.0, 0.0, 0.0]
    for k in range(1, steps):
        w = [rate_x, 0.0, 0.0] if k + 1 < switch else [0.0, rate_y, 0.0]
        Q[k] = Q[k - 1] + _mul(0.5 * Q[k - 1], np.concatenate([[0.0], w])) * dt
    closed = (np.sqrt(1 + (rate_x * dt / 2) ** 2) ** sch["x_steps"]
              * np.sqrt(1 + (rate_y * dt / 2) ** 2) ** sch["y_steps"])
    norms = np.linalg.norm(Q, axis=1)
    P = np.einsum("kij,j->ki", madgwick_rotmat_raw(Q), P0)
    radius = np.linalg.norm(P, axis=1) / np.linalg.norm(P0)
    ref = run(dt, steps, rate_x, rate_y, switch)
    return {"final_norm": float(norms[-1]), "closed_form_norm": float(closed), "norms": norms,
            "angle_to_normalised_deg": float(np.degrees(_angle(Q[-1] / norms[-1], ref.Q[-1]))),
            "max_radius_change": float(np.abs(radius - 1).max()), "radius": radius}


def gyro_units_real() -> dict:
    """What the recordings shipped with imunav declare their gyro columns to be: the column
    headers of the x-IMU3 and x-IMU files (the manufacturer's own export), e.g.
    ``"Gyroscope X (deg/s)"`` — a rate, not an acceleration."""
    out = {}
    for name, parts in (("x-IMU3", ("real_imu", "xio_ximu3", "Inertial.csv")),
                        ("x-IMU", ("real_imu", "xio_ximu", "00033_CalInertialAndMag.csv"))):
        with open(R.data_path(*parts), encoding="utf-8") as fh:
            header = fh.readline().strip().split(",")
        out[name] = [h for h in header if h.startswith("Gyroscope")]
    return out


def gyro_is_rate_real(window: float = 0.5) -> dict:
    """Is a gyroscope's output an angular velocity (the tutorial's first sentence says
    acceleration)? The units settle it (:func:`gyro_units_real`: the files declare deg/s); the
    data are consistent with them, independently of imunav's simulator: over windows of the
    x-IMU3 recording, the gyro integrated *once*, as the rate its file declares (rate × time is
    an angle), follows the rotation the device's own orientation (its onboard fusion, which
    also uses the accelerometer) reports. Returns the median |error| (deg) and the median
    device rotation over the windows."""
    rec = R.read_ximu3()
    sig = rec.signals
    qd = R.device_as_q_nb(rec)
    n = int(round(window * sig.rate))
    h = 1.0 / sig.rate
    once, turned = [], []
    for i in range(int(sig.rate), len(sig) - n - 1, n):
        a = int(np.searchsorted(rec.device_t, sig.t[i]))
        b = int(np.searchsorted(rec.device_t, sig.t[i + n]))
        if b >= len(rec.device_t):
            break
        q1 = cumulative_product(np.array([1.0, 0, 0, 0]), _exp(sig.gyro[i:i + n] * h))[-1]
        rel = _mul(qd[a] * [1, -1, -1, -1], qd[b])
        once.append(np.degrees(_angle(q1, rel)))
        turned.append(np.degrees(_angle(qd[a], qd[b])))
    return {"window_s": window, "windows": len(once), "device_turn_deg": float(np.median(turned)),
            "as_rate_error_deg": float(np.median(once))}


def drift_still_real() -> dict:
    """Drift measured where the truth needs no reference: the x-IMU3 recording starts with the
    device still (the first :func:`~imunav.analysis.recordings.static_segments` stretch: gyro
    spread < 3°/s, |f| within 3 % of g), so its true attitude is constant and whatever the raw
    gyro, integrated alone, turns by is drift. Returns the stretch's length (s), the angle the
    integrated gyro turns by (at the end and at most), the gyro's mean rate over the stretch
    (its bias, deg/s) and that rate times the length; and, for comparison, how much the
    device's own fused orientation changes over the same stillness."""
    rec = R.read_ximu3()
    sig = rec.signals
    i0, i1 = R.static_segments(sig)[0]
    h = 1.0 / sig.rate
    g = sig.gyro[i0:i1]
    q = cumulative_product(np.array([1.0, 0, 0, 0]), _exp(g[:-1] * h))
    ang = np.degrees(_angle(q, np.array([1.0, 0, 0, 0])))
    qd = R.device_as_q_nb(rec)
    a = int(np.searchsorted(rec.device_t, sig.t[i0]))
    b = int(np.searchsorted(rec.device_t, sig.t[i1 - 1]))
    T = (i1 - i0 - 1) * h
    bias = float(np.degrees(np.linalg.norm(g[:-1].mean(axis=0))))   # the samples integrated
    return {"duration_s": float(T), "final_deg": float(ang[-1]), "max_deg": float(ang.max()),
            "bias_deg_s": bias, "bias_times_duration_deg": bias * T, "t": np.arange(len(ang)) * h,
            "angle_deg": ang, "device_change_deg": float(np.degrees(_angle(qd[a], qd[b]))),
            "accel_over_g": float(np.linalg.norm(sig.accel[i0:i1], axis=1).mean() / sig.g)}


#: The gyro errors of the simulated drift (the BMI088 preset's gyro: data sheet
#: BST-BMI088-DS001, zero-rate offset ±1 °/s, rate noise density 0.014 °/s/√Hz).
DRIFT_GYRO = {"bias": "1 deg/s", "noise_density": "0.014 deg/s/sqrt(Hz)"}


def drift_simulated(times=(0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 60.0), rate: float = 100.0,
                    runs: int = 100, seed: int = 0) -> dict:
    """Drift of a gyro integrated alone on a still body, simulated with datasheet errors
    (:data:`DRIFT_GYRO`, imunav's sensor model): the true attitude is constant, so the angle the
    integrated gyro turns by is the drift. Two cases, ``runs`` seeds each: the gyro as shipped
    (turn-on bias and white noise) and with the bias calibrated out (white noise only). Returns
    the median drift (deg) at ``times`` for each, and each case's fitted growth exponent
    (drift ∝ t^p: 1 for a constant bias, ½ for white noise — angle random walk)."""
    motion = Motion(duration=max(times))
    q0 = np.array([1.0, 0.0, 0.0, 0.0])
    h = 1.0 / rate
    idx = np.round(np.asarray(times) * rate).astype(int)
    out = {"times_s": list(times), "rate_hz": rate, "runs": runs, "gyro": dict(DRIFT_GYRO)}
    for case, terms in (("as_shipped", DRIFT_GYRO),
                        ("bias_removed", {"noise_density": DRIFT_GYRO["noise_density"]})):
        imu = ImuModel.from_dict({"gyro": terms}, f"still gyro, {case}")
        w = np.stack([simulate_imu(motion, rate, imu=imu, seed=seed + k).gyro
                      for k in range(runs)], 1)                        # (N+1, runs, 3)
        q = cumulative_product(np.tile(q0, (runs, 1)), _exp(w[:-1] * h))
        med = np.median(np.degrees(_angle(q[idx], q0)), axis=1)
        out[case] = {"median_deg": med.tolist(), "exponent": fit_order(times, med)}
    return out


def order_with_sampled_rate(dts=(0.5, 0.25, 0.125, 0.0625, 0.03125), duration: float = 20.0,
                            rate: float = np.pi / 8) -> dict:
    """Why the first-order update is of order 2 in this tutorial and of order 1 on rate samples
    (notebook 00): about a fixed axis, with a rate that *varies* within each step,
    ω(t) = r (1 + ½ sin t), sampled at each step's start as a real gyro's samples are. The true
    angle is ∫ω dt = r (t + ½ (1 − cos t)) in closed form. Fitted orders (final angle error vs
    dt) of the first-order normalised update and of the exact rotation by ω(t_k)·dt, beside the
    first-order update on the tutorial's constant rate."""
    out = {"dts": list(dts)}
    errs = {"sampled_first_order": [], "sampled_exponential": [], "constant_first_order": []}
    truth = rate * (duration + 0.5 * (1 - np.cos(duration)))
    for dt in dts:
        n = int(round(duration / dt))
        tk = np.arange(n) * dt
        w = rate * (1 + 0.5 * np.sin(tk)) * dt                    # ω(t_k)·dt per step
        fo = 2 * np.arctan(w / 2)          # a normalised first-order step about a fixed axis
        errs["sampled_first_order"].append(abs(fo.sum() - truth))
        errs["sampled_exponential"].append(abs(w.sum() - truth))
        errs["constant_first_order"].append(abs(n * (rate * dt - 2 * np.arctan(rate * dt / 2))))
    for k, e in errs.items():
        out[k] = {"final_error_rad": e, "order": fit_order(dts, e)}
    return out


def angle_error(dt: float = 0.5, duration: float | None = None, **kw) -> FloatArray:
    """Angle (rad) between the first-order and the exact (true) attitude at every step."""
    a = run(dt, update="first_order", duration=duration, **kw)
    b = run(dt, update="exact", duration=duration, **kw)
    return _angle(a.Q, b.Q)


def error_vs_dt(dts=(0.5, 0.25, 0.125, 0.0625, 0.03125), duration: float = 49.5
                ) -> tuple[FloatArray, float]:
    """Final angle error (rad) vs dt over the same 49.5 s schedule, and the fitted order."""
    e = np.array([angle_error(dt, duration=duration)[-1] for dt in dts])
    return e, fit_order(dts, e)


def gyro_measures_rate_demo() -> dict:
    """A body turning at a constant π/8 rad/s about x: the (ideal) gyroscope reads π/8 rad/s,
    while the angular acceleration is zero — a gyroscope measures angular *velocity*."""
    sig = simulate_imu(Motion(roll="pi/8*t"), 10.0, 2.0)
    return {"gyro_x_rad_s": sig.gyro[:, 0], "angular_acceleration": np.gradient(sig.gyro[:, 0], 0.1)}


def plot_error_vs_dt(dts, errs, order: float, ax=None):
    """Final first-order error (deg) vs step, log–log, ticks at the steps themselves."""
    import matplotlib.pyplot as plt

    ax = ax or plt.figure(figsize=(5.5, 4)).add_subplot()
    ax.loglog(dts, np.degrees(errs), "o-", label=f"fitted order {order:.2f}")
    ax.loglog(dts, np.degrees(errs[0]) * (np.asarray(dts) / dts[0]) ** 2, "k:", lw=1,
              label="∝ dt²")
    ax.set_xticks(dts, [f"{d:g}" for d in dts])
    ax.minorticks_off()
    ax.set(xlabel="dt (s)", ylabel="final error (deg)", title="error vs step")
    ax.legend()
    return ax


#: What the tutorial's 3-D plot draws (its key): the point P = (1, 2, 3) and three markers one
#: unit from it along its x, y and z axes, each joined to P every third step.
PLOT_KEY = (("k", "the point P"), ("r", "marker at P + x"), ("g", "marker at P + y"),
            ("b", "marker at P + z"))


def plot_run(res: TutorialRun, ax=None, title: str = ""):
    """The tutorial's 3-D plot: the point (black), its axis markers (r, g, b: :data:`PLOT_KEY`,
    each dot labelled for a legend) and the lines joining them to the point."""
    import matplotlib.pyplot as plt

    if ax is None:
        ax = plt.figure(figsize=(6, 6)).add_subplot(projection="3d")
    ax.plot(*res.P.T, "k.", ms=3, label=PLOT_KEY[0][1])
    for Pm, (c, lab) in zip((res.PX, res.PY, res.PZ), PLOT_KEY[1:], strict=True):
        ax.plot(*Pm.T, ".", color=c, ms=2, label=lab)
        for k in range(0, len(res.P), 3):
            ax.plot(*np.stack([res.P[k], Pm[k]]).T, color=c, lw=0.6)
    ax.set(xlabel="x", ylabel="y", zlabel="z", title=title)   # the tutorial's own frame
    ax.set_box_aspect(None, zoom=0.82)  # room for the z label inside the axes (two side by side)
    return ax


def reproduce(out) -> list[dict]:
    """Figures ``tutorial_*.png`` and the record of the first-order final angle error."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(11, 5))
    plot_run(run(), fig.add_subplot(1, 2, 1, projection="3d"), "first-order + normalise (as written)")
    plot_run(run(update="exact"), fig.add_subplot(1, 2, 2, projection="3d"), "exact update")
    fig.tight_layout()
    fig.savefig(out / "tutorial_example.png", dpi=FIG_DPI)
    plt.close(fig)
    e = angle_error()
    dts = (0.5, 0.25, 0.125, 0.0625, 0.03125)
    errs, order = error_vs_dt(dts)
    fig, axs = plt.subplots(1, 2, figsize=(11, 4))
    axs[0].plot(run().t, np.degrees(e))
    axs[0].set(xlabel="t (s)", ylabel="deg", title="first-order vs true attitude, dt = 0.5 s")
    plot_error_vs_dt(dts, errs, order, axs[1])
    fig.tight_layout()
    fig.savefig(out / "tutorial_error.png", dpi=FIG_DPI)
    plt.close(fig)
    sch = schedule()
    un = unnormalised()
    real = gyro_is_rate_real()
    units = gyro_units_real()
    still = drift_still_real()
    sim = drift_simulated()
    return [
        record("tutorial.final_angle_error_first_order_deg", "angle between the first-order "
               "(normalised) and the true attitude after the 100-step example", None,
               float(np.degrees(e[-1])), "deg", "no paper value",
               "the tutorial shows the plot only; the exact update is the true rotation here "
               f"(piecewise-constant rate), and the error falls as dt^{order:.2f}"),
        record("tutorial.update_order_in_dt", "fitted order in dt of the final angle error of "
               "the first-order normalised update (dt = 0.5 … 0.03125 s, same 49.5 s schedule)",
               None, order, "1", "no paper value",
               "against the exact rotation the normalised first-order update is second order "
               f"here (dt^{order:.2f}): the axis is fixed within each phase, so only the "
               "per-step angle deficit (|ω|dt)³/12 accumulates"),
        record("tutorial.schedule.total_s", "duration the MATLAB loop runs", 50.0,
               sch["total_s"], "s", "differs",
               "counted exactly: for i=2:100 is 99 steps of 0.5 s, 49.5 s, not 50 s"),
        record("tutorial.schedule.x_rotation_s", "time rotating about X", 25.0, sch["x_s"], "s",
               "differs", "counted exactly: i < 50 holds for 48 steps, 24 s, not the stated 25 s"),
        record("tutorial.schedule.y_rotation_s", "time rotating about Y", 25.0, sch["y_s"], "s",
               "differs", "counted exactly: i = 50..100 is 51 steps, 25.5 s, not the stated 25 s"),
        record("tutorial.schedule.x_steps", "steps about X (the code's comment: 'the 50 first "
               "steps')", 50.0, float(sch["x_steps"]), "1", "differs",
               f"counted exactly: the loop's i < 50 runs {sch['x_steps']} steps about X"),
        record("tutorial.schedule.y_steps", "steps about Y (the code's comment: 'the 50 last "
               "steps')", 50.0, float(sch["y_steps"]), "1", "differs",
               f"counted exactly: i = 50..100 is {sch['y_steps']} steps about Y"),
        record("tutorial.unnormalised.final_norm", "|Q| after the example without its "
               "normalisation line", None, un["final_norm"], "1", "no paper value",
               "each first-order step multiplies |Q| by √(1 + (|ω| dt/2)²): the closed form "
               f"gives {un['closed_form_norm']:.12f}; the direction is unchanged "
               + ("(to rounding, < 1e-10°)" if un["angle_to_normalised_deg"] < 1e-10 else
                  f"({un['angle_to_normalised_deg']:.1e}°)")),
        record("tutorial.unnormalised.max_point_radius_change", "largest relative change of "
               "the rotated point's distance from the origin, unnormalised, raw quatern2rotMat",
               None, un["max_radius_change"], "1", "no paper value",
               "quatern2rotMat assumes |Q| = 1: the grown quaternion scales the points off "
               "their sphere, which is why the normalisation line matters"),
        record("tutorial.claim.gyro_measures_angular_acceleration", "median angle (deg) "
               "between the x-IMU3 gyro integrated once, as the rate its file declares, and the "
               f"device's own orientation over {real['window_s']} s windows", None,
               real["as_rate_error_deg"], "deg", "differs",
               "the units settle it: both recordings declare their gyro columns in "
               f"{units['x-IMU3'][0].split('(')[-1].rstrip(')')} ('{units['x-IMU3'][0]}'), a "
               "rate, and a rate integrated once over time is an angle; an angular "
               "acceleration would be in deg/s² and need two integrations. The data agree: "
               f"integrated once, the gyro follows the device's fused orientation within "
               f"{real['as_rate_error_deg']:.1f}° over turns of "
               f"{real['device_turn_deg']:.0f}° (median)"),
        record("tutorial.claim.drift", "angle the x-IMU3's raw gyro, integrated alone, turns "
               "by over the recording's first still stretch (the body does not turn)", None,
               still["final_deg"], "deg", "holds",
               f"still for {still['duration_s']:.2f} s, the integrated gyro turns by "
               f"{still['final_deg']:.3f}° (its mean rate, {still['bias_deg_s']:.3f}°/s, is a "
               "bias); simulated with a data-sheet gyro (±1 °/s offset, 0.014 °/s/√Hz) on a "
               f"still body it drifts {sim['as_shipped']['median_deg'][-1]:.0f}° in "
               f"{sim['times_s'][-1]:g} s, ∝ t^{sim['as_shipped']['exponent']:.2f} (the bias), "
               f"and {sim['bias_removed']['median_deg'][-1]:.2f}° with the bias removed, "
               f"∝ t^{sim['bias_removed']['exponent']:.2f} (angle random walk): the cumulated "
               "error the tutorial calls drift",
               f"x-IMU3 recording shipped with imunav ({still['duration_s']:.2f} s still at "
               "50 Hz, raw gyro, no bias removed); simulation: median of "
               f"{sim['runs']} seeds at {sim['rate_hz']:g} Hz"),
    ]


#: The coverage table of notebook 03: (what the tutorial says, where it is settled, record id,
#: imunav's words). Rendered from the ledger by :func:`imunav.papers.records.coverage_table`.
COVERAGE = (
    ("'a gyroscope measures the angular acceleration … integrating twice'", "§4",
     "tutorial.claim.gyro_measures_angular_acceleration", "x-IMU3, deg/s integrated once: off by"),
    ("'it don't work properly in practice due to the cumulated errors … drift'", "§4",
     "tutorial.claim.drift", "x-IMU3 still, gyro alone turns by"),
    (r"the update $\hat Q_k = \hat Q_{k-1} + \Delta t\,\frac12\hat Q_{k-1}\otimes "
     r"S_\omega$, normalised, against the exact rotation", "§2",
     "tutorial.final_angle_error_first_order_deg", "final error"),
    ("— its order in Δt", "§2", "tutorial.update_order_in_dt", None),
    ("'for some applications, the quaternion must be normalized'", "§3",
     "tutorial.unnormalised.final_norm", "without it |Q| ends at"),
    ("— what the growth does to the rotated point", "§3",
     "tutorial.unnormalised.max_point_radius_change", "largest change of |P|/|P₀| − 1"),
    ("the example 'simulates … during 50 seconds'", "§1", "tutorial.schedule.total_s", None),
    ("'along the X … axis during … the 25 first seconds'", "§1", "tutorial.schedule.x_rotation_s",
     None),
    ("'… and [Y] during the 25 last seconds'", "§1", "tutorial.schedule.y_rotation_s", None),
    ("the code's comment 'pi/8 rad/s along X axis for the 50 first steps'", "§1",
     "tutorial.schedule.x_steps", None),
    ("the code's comment 'pi/16 rad/s along Y axis for the 50 last steps'", "§1",
     "tutorial.schedule.y_steps", None),
    ("the 3-D plot of the rotated point and its axes", "§1", None, "drawn, as written and "
     "with the exact update; nothing to compare"),
)
