"""Motions from data (issue 16): pose and waypoint splines against analytic truth, exact
increments for the spline, the files and their errors."""

import numpy as np
import pytest
from scipy.integrate import quad

from imunav import ImunavError, Motion, simulate_imu
from imunav.analysis.metrics import fit_order
from imunav.cli import main
from imunav.core.constants import G0
from imunav.core.rotations import quat_angle
from imunav.io import load_motion, read_signals
from imunav.motion.catalog import figure_eight
from imunav.motion.trajectory import PoseMotion, WaypointMotion

TRUE = figure_eight()            # 20 s, turning about all axes: the analytic truth
INTERIOR = np.linspace(2.0, 18.0, 4001)   # away from the not-a-knot ends


def _poses(rate, motion=TRUE, t0=0.0):
    t = np.arange(0.0, motion.duration + 1e-9, 1.0 / rate)
    return t + t0, motion.position(t), motion.attitude(t)


def _errors(rate):
    pm = PoseMotion(*_poses(rate))
    return (np.abs(pm.angular_rate(INTERIOR) - TRUE.angular_rate(INTERIOR)).max(),
            np.abs(pm.specific_force(INTERIOR) - TRUE.specific_force(INTERIOR)).max())


def test_pose_spline_passes_through_every_pose():
    t, p, q = _poses(37.0, t0=5.0)
    pm = PoseMotion(t, p, q)
    assert pm.time_offset == 5.0 and pm.duration == pytest.approx(t[-1] - 5.0)
    assert np.abs(pm.position(t - 5.0) - p).max() < 1e-9
    assert quat_angle(pm.attitude(t - 5.0), q).max() < 1e-9


def test_pose_spline_convergence_against_the_analytic_motion():
    """RotationSpline (cubic in rotation vectors): ω_b converges at order 3; the quintic
    position spline: f_b at order 4 (measured 25→100 Hz: ω 4.2e-7 → 6.6e-9 rad/s,
    f 4.8e-8 → 2.8e-10 m/s²; at 200 Hz f meets the rounding of twice-differentiated
    positions, ≈1e-9)."""
    rates = (25.0, 50.0, 100.0)
    ew, ef = np.array([_errors(r) for r in rates]).T
    assert fit_order(1 / np.array(rates), ew) == pytest.approx(3.0, abs=0.2)
    assert fit_order(1 / np.array(rates), ef) == pytest.approx(4.0, abs=0.5)
    assert ew[-1] < 1e-8 and ef[-1] < 1e-9                 # 100 Hz poses (docs/guide_real_logs.md)


def test_increments_are_exact_for_the_spline():
    """The increments integrate the spline's own ω_b and f_b: against scipy's adaptive quad
    (given the knots inside each interval), to rounding."""
    pm = PoseMotion(*_poses(50.0))
    sig = simulate_imu(pm, 200.0, kind="increments")
    rng = np.random.default_rng(3)
    for k in rng.choice(len(sig), 6, replace=False):
        a, b = k / 200, (k + 1) / 200
        pts = [x for x in pm.breakpoints if a < x < b] or None
        for i in range(3):
            w = quad(lambda s, i=i: pm.angular_rate(np.array([s]))[0, i], a, b, points=pts,
                     epsabs=1e-17, epsrel=1e-13, limit=200)[0]
            f = quad(lambda s, i=i: pm.specific_force(np.array([s]))[0, i], a, b, points=pts,
                     epsabs=1e-17, epsrel=1e-13, limit=200)[0]
            assert sig.gyro[k, i] == pytest.approx(w, rel=1e-12, abs=1e-17)
            assert sig.accel[k, i] == pytest.approx(f, rel=1e-12, abs=1e-15)


def test_runs_stop_inside_the_data():
    t, p, q = _poses(50.0)
    pm = PoseMotion(t[:-3], p[:-3], q[:-3])          # 19.94 s of data
    sig = simulate_imu(pm, 30.0)                        # 19.94 × 30 = 598.2 → 598 intervals
    assert sig.t[-1] <= pm.duration and len(sig) == 599
    with pytest.raises(ImunavError, match="defined from 0"):
        pm.position([pm.duration + 0.01])


def test_smoothing_against_capture_noise():
    """1 mm of position noise at 100 Hz: twice differentiated, an interpolating spline turns it
    into tens of m/s² of specific-force error; the smoothing spline (σ = 1 mm) removes most of
    it. Likewise 1 mrad of attitude noise and ω_b."""
    t, p, q = _poses(100.0)
    rng = np.random.default_rng(11)
    pn = p + rng.normal(0, 1e-3, p.shape)
    rv = rng.normal(0, 1e-3, (t.size, 3))
    half = np.linalg.norm(rv, axis=1, keepdims=True) / 2
    dq = np.concatenate([np.cos(half), np.sinc(half / np.pi) * rv / 2], axis=1)
    from imunav.core.rotations import quat_mul
    qn = quat_mul(q, dq)
    raw = PoseMotion(t, pn, qn)
    smooth = PoseMotion(t, pn, qn, smoothing=1e-3, attitude_smoothing=1e-3)

    def rms(m, f):
        return np.sqrt(np.mean((getattr(m, f)(INTERIOR) - getattr(TRUE, f)(INTERIOR)) ** 2))

    assert rms(raw, "specific_force") > 10.0             # measured ≈ 40 m/s²
    assert rms(smooth, "specific_force") < 0.05 * rms(raw, "specific_force")
    assert rms(smooth, "angular_rate") < 0.2 * rms(raw, "angular_rate")


# ----------------------------------------------------------------------------- waypoints

ROUTE_T = [0.0, 10.0, 20.0, 30.0]
ROUTE_P = [[0, 0, 0], [50, 10, -2], [80, 60, -5], [60, 100, -5]]


def test_waypoints_at_rest_and_through_every_point():
    ypr = [[0, 0, 0], [0.5, 0.05, 0.1], [1.5, 0.0, -0.1], [2.5, 0.0, 0.0]]
    wp = WaypointMotion(ROUTE_T, ROUTE_P, ypr)
    ends = np.array([0.0, 30.0])
    for f in ("velocity", "acceleration", "angular_rate"):
        assert np.abs(getattr(wp, f)(ends)).max() < 1e-12, f
    assert np.abs(wp.position(np.array(ROUTE_T)) - ROUTE_P).max() < 1e-9
    assert np.abs(wp.euler(np.array(ROUTE_T)) - ypr).max() < 1e-9


def _numeric_rate(m, t, h=1e-5):
    from imunav.core.rotations import quat_mul
    qa, qb, q0 = m.attitude(t - h), m.attitude(t + h), m.attitude(t)
    dq = (qb - qa) / (2 * h)
    return 2 * quat_mul(q0 * [1, -1, -1, -1], dq)[..., 1:]


def test_follow_heads_along_the_path_with_exact_rates():
    wp = WaypointMotion(ROUTE_T, ROUTE_P, orientation="follow")
    t = np.linspace(0.5, 29.5, 59)
    v = wp.velocity(t)
    yaw, pitch, roll = np.moveaxis(wp.euler(t), -1, 0)
    np.testing.assert_allclose(yaw, np.arctan2(v[:, 1], v[:, 0]), atol=1e-12)
    np.testing.assert_allclose(pitch, np.arctan2(-v[:, 2], np.hypot(v[:, 0], v[:, 1])),
                               atol=1e-12)
    h = 1e-5
    dyaw = (np.unwrap(np.stack([wp.euler(t - h)[:, 0], wp.euler(t + h)[:, 0]]), axis=0)[1]
            - wp.euler(t - h)[:, 0]) / (2 * h)
    np.testing.assert_allclose(roll, np.arctan(np.linalg.norm(v, axis=1) * dyaw / G0), atol=1e-7)
    # ω_b from the closed-form chain vs central differences of the attitude, also at the ends
    tt = np.concatenate([[1e-6, 1e-3], t, [30 - 1e-3, 30 - 1e-6]])
    np.testing.assert_allclose(wp.angular_rate(tt), _numeric_rate(wp, np.clip(tt, 1e-5, 30 - 1e-5)),
                               atol=2e-6)


def test_follow_refuses_a_vertical_route():
    with pytest.raises(ImunavError, match="heading undefined"):
        WaypointMotion([0, 5], [[0, 0, 0], [0, 0, -10]], orientation="follow")


def test_route_simulates_and_navigates_back():
    from imunav import nav_errors, navigate

    wp = WaypointMotion(ROUTE_T, ROUTE_P, orientation="follow")
    sig = simulate_imu(wp, 100.0, kind="increments")
    t0 = np.array([0.0])
    nav = navigate(sig, wp.attitude(t0)[0], wp.velocity(t0)[0], wp.position(t0)[0])
    e = nav_errors(nav, wp)
    assert e.position.max() < 1e-6 and e.attitude.max() < 1e-9


# ----------------------------------------------------------------------------- files and CLI

def _write_poses(path, t, p, q, header="t,x,y,z,qw,qx,qy,qz"):
    cols = [t[:, None], p, q] if "vx" not in header else [t[:, None], p, np.zeros_like(p), q]
    np.savetxt(path, np.hstack(cols), delimiter=",", header=header, comments="", fmt="%.17g")


def test_cli_simulate_pose_csv_matches_the_analytic_rates(tmp_path, capsys):
    t, p, q = _poses(100.0, t0=3.0)
    poses = tmp_path / "poses.csv"
    _write_poses(poses, t, p, q)
    out = tmp_path / "s.csv"
    assert main(["simulate", str(poses), "--rate", "200", "--out", str(out)]) == 0
    assert "t = 3 s in" in capsys.readouterr().out
    sig = read_signals(out)
    inner = (sig.t > 2) & (sig.t < 18)
    # docs/guide_real_logs.md: 5.2e-11 rad/s and 3.0e-10 m/s² measured at these sample times
    # (poses and midpoints)
    assert np.abs(sig.gyro[inner] - TRUE.angular_rate(sig.t[inner])).max() < 2e-10
    assert np.abs(sig.accel[inner] - TRUE.specific_force(sig.t[inner])).max() < 1e-9
    # a truth CSV is accepted as poses (its velocities ignored)
    truth = tmp_path / "truth.csv"
    _write_poses(truth, t, p, q, header="t,x,y,z,vx,vy,vz,qw,qx,qy,qz")
    m, d, _ = load_motion(truth)
    assert isinstance(m, PoseMotion) and d == pytest.approx(20.0)


ROUTE_TOML = """orientation = "follow"
[[waypoint]]
t = 0
x = 0
y = 0
z = 0
[[waypoint]]
t = 10
x = 50
y = 10
z = -2
[[waypoint]]
t = 20
x = 80
y = 60
z = -5
"""


def test_cli_waypoints_simulate_and_assess(tmp_path, capsys):
    route = tmp_path / "route.toml"
    route.write_text(ROUTE_TOML)
    assert main(["simulate", str(route), "--rate", "100", "--out", str(tmp_path / "r.csv"),
                 "--output", "increments"]) == 0
    assert main(["assess", str(route), "--imu", "tactical", "--rate", "50",
                 "--tolerance", "5"]) == 0
    assert "covariance analysis" in capsys.readouterr().out


@pytest.mark.parametrize("name, text, fragment", [
    ("few.csv", "t,x,y,z,qw,qx,qy,qz\n" + "".join(f"{i},0,0,0,1,0,0,0\n" for i in range(3)),
     "at least 6"),
    ("rep.csv", "t,x,y,z,qw,qx,qy,qz\n" + "".join(f"{min(i, 3)},0,0,0,1,0,0,0\n" for i in range(6)),
     "line 6: t = 3 is not after"),
    ("norm.csv", "t,x,y,z,qw,qx,qy,qz\n" + "".join(f"{i},0,0,0,1,{0.1 * (i == 2)},0,0\n"
                                                   for i in range(6)), "line 4: quaternion norm"),
    ("nan.csv", "t,x,y,z,qw,qx,qy,qz\n0,0,0,0,nan,0,0,0\n", "line 2"),
    ("hdr.csv", "t,x,y,z,q0,q1,q2,q3\n0,0,0,0,1,0,0,0\n", "unrecognised header"),
    ("miss.toml", "[[waypoint]]\nt=0\nx=0\ny=0\nz=0\n[[waypoint]]\nx=1\ny=0\nz=0\n",
     "waypoint 2: missing 't'"),
    ("rep.toml", "[[waypoint]]\nt=0\nx=0\ny=0\nz=0\n[[waypoint]]\nt=0\nx=1\ny=0\nz=0\n",
     "waypoint 2: t = 0 is not after"),
    ("one.toml", "[[waypoint]]\nt=0\nx=0\ny=0\nz=0\n", "at least 2"),
    ("str.toml", "[[waypoint]]\nt=0\nx='a'\ny=0\nz=0\n[[waypoint]]\nt=1\nx=1\ny=0\nz=0\n",
     "waypoint 1: x must be a finite number"),
    ("orient.toml", "orientation='up'\n[[waypoint]]\nt=0\nx=0\ny=0\nz=0\n", "orientation must"),
    ("followypr.toml", "orientation='follow'\n[[waypoint]]\nt=0\nx=0\ny=0\nz=0\nyaw=1\n"
     "[[waypoint]]\nt=1\nx=1\ny=0\nz=0\n", "waypoint 1: orientation = \"follow\" derives"),
])
def test_bad_motion_files_exit_2_with_one_line(tmp_path, capsys, name, text, fragment):
    f = tmp_path / name
    f.write_text(text)
    assert main(["simulate", str(f), "--rate", "10", "--out", str(tmp_path / "o.csv")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("imunav: error: ") and fragment in err[0], err


def test_smoothing_flags_only_for_poses(tmp_path, capsys):
    m = tmp_path / "m.toml"
    m.write_text("duration = 2\n")
    assert main(["simulate", str(m), "--rate", "10", "--out", str(tmp_path / "o.csv"),
                 "--smoothing", "0.001"]) == 2
    assert "pose CSV files only" in capsys.readouterr().err


def test_still_motion_unaffected():
    # analytic motions keep the round() interval rule
    assert len(simulate_imu(Motion(duration=1.0), 2.5)) == 3
