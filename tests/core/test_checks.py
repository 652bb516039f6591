"""Details of the core layer that the first mutation run (issue 19) found unguarded: which
argument a bad-input error names, batched shapes against scipy, the canonical sign of
quaternions, the gimbal-lock warning, the size and unit helpers. Truths: scipy, numpy's cross
product, hand-written strings."""

import os
import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from imunav.core import rotations as R
from imunav.core.resources import human
from imunav.core.units import factor
from imunav.core.validation import ImunavError, show


# ------------------------------------------------------------------------- bad input named
@pytest.mark.parametrize("call, name, want", [
    (lambda b: R.quat_mul(b, [1, 0, 0, 0]), "p", "(..., 4)"),
    (lambda b: R.quat_mul([1, 0, 0, 0], b), "q", "(..., 4)"),
    (lambda b: R.quat_conj(b), "q", "(..., 4)"),
    (lambda b: R.quat_normalize(b), "q", "(..., 4)"),
    (lambda b: R.quat_rotate(b, [1, 0, 0]), "q", "(..., 4)"),
    (lambda b: R.quat_rotate([1, 0, 0, 0], b), "v", "(..., 3)"),
    (lambda b: R.quat_to_dcm(b), "q", "(..., 4)"),
    (lambda b: R.euler_to_quat(b), "ypr", "(..., 3)"),
    (lambda b: R.quat_to_euler(b), "q", "(..., 4)"),
    (lambda b: R.quat_exp(b), "rotvec", "(..., 3)"),
    (lambda b: R.quat_log(b), "q", "(..., 4)"),
    (lambda b: R.quat_angle(b, [1, 0, 0, 0]), "p", "(..., 4)"),
    (lambda b: R.quat_angle([1, 0, 0, 0], b), "q", "(..., 4)"),
    (lambda b: R.skew(b), "v", "(..., 3)"),
])
def test_bad_shape_names_the_argument(call, name, want):
    bad = np.zeros((2, 5))
    with pytest.raises(ImunavError) as e:
        call(bad)
    assert str(e.value) == f"{name} must have shape {want}, got (2, 5)"


def test_quat_from_dcm_names_its_argument_and_checks_orthogonality():
    with pytest.raises(ImunavError, match=r"^c must have at least 2 dimension\(s\)"):
        R.quat_from_dcm([1.0, 0.0, 0.0])
    c = Rotation.from_euler("ZYX", [0.3, -0.2, 0.1]).as_matrix()
    with pytest.raises(ImunavError):
        R.quat_from_dcm(c * (1 + 1e-3))                    # |CᵀC − I| = 2e-3 > 1e-6
    with pytest.raises(ImunavError):
        R.quat_from_dcm(c * [[1], [1], [-1]])              # a reflection: det = −1
    R.quat_from_dcm(c * (1 + 1e-3), atol=3e-3)             # tolerated when asked
    # the check is per matrix in a batch: one bad matrix among good ones is caught
    with pytest.raises(ImunavError):
        R.quat_from_dcm(np.stack([c, c, c * (1 + 1e-3)]))
    # within the tolerance (|CᵀC − I| = 4e-7) the result is still a unit quaternion
    q = R.quat_from_dcm(c * (1 + 2e-7))
    assert abs(np.linalg.norm(q) - 1) < 1e-15


# ------------------------------------------------------------------------ batches vs scipy
def test_batched_functions_against_scipy():
    rot = Rotation.random(12, random_state=3)
    q = rot.as_quat(scalar_first=True).reshape(3, 4, 4)
    v = np.random.default_rng(5).normal(size=(3, 4, 3))
    np.testing.assert_allclose(R.quat_log(q), rot.as_rotvec().reshape(3, 4, 3), atol=1e-12)
    np.testing.assert_allclose(R.quat_to_euler(q), rot.as_euler("ZYX").reshape(3, 4, 3),
                               atol=1e-12)
    np.testing.assert_allclose(R.quat_rotate(q, v),
                               rot.apply(v.reshape(12, 3)).reshape(3, 4, 3), atol=1e-12)
    np.testing.assert_allclose(R.quat_conj(q)[..., 1:], -q[..., 1:], atol=0)
    # skew(v) u = v × u for a batch
    u = v[::-1]
    np.testing.assert_allclose(np.einsum("...ij,...j->...i", R.skew(v), u), np.cross(v, u),
                               atol=1e-15)
    assert R.skew(v).shape == (3, 4, 3, 3)
    assert R.from_scipy(rot).dtype == np.float64
    assert R.from_scipy(Rotation.from_quat(np.float32([0, 0, 0, 1]))).dtype == np.float64


def test_zero_quaternion_named():
    with pytest.raises(ImunavError, match="^p must have non-zero norm"):
        R.quat_angle([0, 0, 0, 0], [1, 0, 0, 0])
    with pytest.raises(ImunavError, match="^q must have non-zero norm"):
        R.quat_normalize(np.zeros((2, 4)))


def test_quat_from_dcm_every_branch_against_scipy():
    # random attitudes plus half-turns about each axis and near them, where the largest
    # diagonal entry picks the branch
    rot = Rotation.concatenate([
        Rotation.random(2000, random_state=11),
        Rotation.from_rotvec(np.pi * np.eye(3)),
        Rotation.from_rotvec((np.pi - 1e-3) * np.eye(3)),
        Rotation.from_rotvec(np.pi / np.sqrt(3) * np.ones((1, 3)))])
    q = R.quat_from_dcm(rot.as_matrix())
    assert np.all(q[..., 0] >= 0)                           # canonical: w ≥ 0
    np.testing.assert_allclose(np.abs(np.einsum("...i,...i", q, rot.as_quat(scalar_first=True))),
                               1.0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(q, axis=-1), 1.0, atol=1e-15)


def test_log_of_a_quaternion_with_negative_scalar_takes_the_short_way():
    q = Rotation.from_rotvec([0.0, 2.5, 0.0]).as_quat(scalar_first=True)
    np.testing.assert_allclose(R.quat_log(-q), [0.0, 2.5, 0.0], atol=1e-14)
    np.testing.assert_allclose(R.quat_log([[1.0, 0, 0, 0], [-1.0, 0, 0, 0]]), np.zeros((2, 3)),
                               atol=0)


def test_gimbal_lock_warns_at_the_callers_line_and_zeroes_roll():
    q = R.euler_to_quat([0.7, np.pi / 2, 0.2])
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        ypr = R.quat_to_euler(q)
    assert len(w) == 1 and issubclass(w[0].category, R.GimbalLockWarning)
    assert str(w[0].message) == ("gimbal lock: pitch is ±90°, yaw and roll are not separable; "
                                 "roll set to 0")
    if "MUTANT_UNDER_TEST" not in os.environ:               # mutmut's trampoline adds a frame
        assert w[0].filename == __file__                    # stacklevel: the caller's line
    # only ψ − φ is defined at θ = +90°: 0.7 − 0.2
    np.testing.assert_allclose(ypr, [0.5, np.pi / 2, 0.0], atol=1e-7)


# ----------------------------------------------------------------------------- small helpers
@pytest.mark.parametrize("nbytes, text", [
    (0, "0 B"), (999, "999 B"), (1000, "1 kB"), (1234567, "1.23 MB"), (2.5e9, "2.5 GB"),
    (3e12, "3 TB"), (4e15, "4 PB"), (5e18, "5e+03 PB"), (-2e6, "-2 MB"),
])
def test_human_sizes(nbytes, text):
    assert human(nbytes) == text


def test_show_plain_numbers():
    assert show(np.float64(1.5)) == "1.5"
    assert show(np.int64(3)) == "3"
    assert show(2.0) == "2"
    assert show(1 / 3) == "0.333333"
    assert show("a") == "'a'"


def test_factor_normalises_strings_and_lists_the_choices():
    assert factor(" deg / s ", "rate", "--gyro-units") == pytest.approx(np.pi / 180, rel=1e-15)
    with pytest.raises(ImunavError) as e:
        factor(None, "frequency", "--rate-units")
    assert str(e.value) == "unknown --rate-units None; expected one of Hz, kHz"


def test_available_memory_from_meminfo_then_sysconf_then_unknown(monkeypatch):
    import builtins

    from imunav.core import resources

    with open("/proc/meminfo") as fh:
        kb = next(int(line.split()[1]) for line in fh if line.startswith("MemAvailable:"))
    assert resources.available_memory() == pytest.approx(kb * 1024, rel=0.05)
    real_open = builtins.open

    def no_proc(path, *a, **k):
        if str(path) == "/proc/meminfo":
            raise OSError("no /proc")
        return real_open(path, *a, **k)

    monkeypatch.setattr(builtins, "open", no_proc)
    want = os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    assert resources.available_memory() == pytest.approx(want, rel=0.05)

    def no_sysconf(name):
        raise ValueError(name)

    monkeypatch.setattr(os, "sysconf", no_sysconf)
    assert resources.available_memory() == 1 << 62


def test_check_memory_refuses_with_sizes(monkeypatch):
    from imunav.core import resources

    monkeypatch.setattr(resources, "available_memory", lambda: 10_000_000_000)
    limit = resources.MEMORY_FRACTION * 10_000_000_000
    resources.check_memory(limit, "a run")                   # exactly at the limit: allowed
    with pytest.raises(ImunavError) as e:
        resources.check_memory(limit * 1.01, "a run")
    assert str(e.value) == (f"a run would need about {human(limit * 1.01)} of memory; "
                            "10 GB is available")
    with pytest.raises(ImunavError, match=r"is available; use fewer runs$"):
        resources.check_memory(2e10, "a run", "use fewer runs")


def test_check_disk_refuses_what_does_not_fit(monkeypatch, tmp_path):
    import shutil
    from collections import namedtuple

    from imunav.core import resources

    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(shutil, "disk_usage", lambda p: usage(0, 0, 5_000_000))
    out = tmp_path / "out.csv"
    resources.check_disk(out, 5_000_000, "the output")           # exactly what is free: fits
    with pytest.raises(ImunavError) as e:
        resources.check_disk(out, 5_000_001, "the output")
    assert str(e.value) == f"the output would write about 5 MB to {out}; the disk has 5 MB free"

    def gone(p):
        raise OSError(p)

    monkeypatch.setattr(shutil, "disk_usage", gone)
    resources.check_disk(out, 1e30, "the output")                 # unknown: not refused


def test_validation_messages_in_full():
    from imunav.core.validation import as_float_array, check_int, check_positive, check_time

    def msg(f, *a, **k):
        with pytest.raises(ImunavError) as e:
            f(*a, **k)
        return str(e.value)

    assert msg(as_float_array, np.zeros((2, 4)), "q0", ndim=1, last=4) == (
        "q0 must have 1 dimension(s), got shape (2, 4)")
    assert msg(as_float_array, np.zeros((5, 2)), "gyro", ndim=2, last=3) == (
        "gyro must have shape (N, 3), got (5, 2)")
    assert msg(as_float_array, np.zeros((2, 2, 2)), "x", ndim=3, last=3) == (
        "x must have shape (N, N, 3), got (2, 2, 2)")
    assert msg(as_float_array, [[1.0, 2.0], [3.0, np.nan]], "x") == (
        "x contains NaN or inf (first at index (1, 1))")
    assert msg(as_float_array, {"a": 1}, "x").startswith("x must be numeric, got dict: ")
    assert msg(check_int, 1.5, "runs") == "runs must be an integer ≥ 0, got 1.5"
    assert msg(check_int, -2, "runs", 1) == "runs must be an integer ≥ 1, got -2"
    assert check_int(0, "seed") == 0                      # the default minimum is 0
    assert msg(check_positive, -3.0, "rate") == "rate must be a positive finite number, got -3"
    # two samples are enough to be out of order
    assert msg(check_time, [2.0, 1.0], "t") == (
        "t must be strictly increasing; t[1] = 1 does not exceed t[0] = 2")
