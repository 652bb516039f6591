"""BLAS threads of imunav's kernels (issue 26): one by default inside the library, whatever
numpy's own setting, the caller's choice otherwise; restored afterwards; Monte Carlo chunks
included."""

from __future__ import annotations

import threading

import numpy as np
import pytest
from threadpoolctl import threadpool_info, threadpool_limits

import imunav
from imunav import ImuModel, ImunavError, Motion, monte_carlo, simulate_imu
from imunav.analysis import montecarlo
from imunav.core import threads
from imunav.core.threads import ENV, blas_env, blas_limit, kernel_threads


def blas_counts() -> list[int]:
    """The thread count of every BLAS library loaded in the process."""
    return [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]


class Spy(Motion):
    """A motion that records the BLAS thread counts each time the simulation evaluates it."""

    seen: list

    def angular_rate(self, t):
        self.seen.append(blas_counts())
        return super().angular_rate(t)


def spy() -> Spy:
    m = Spy(x="sin(t)", roll="0.3*sin(2*t)", duration=3.0)
    m.seen = []
    return m


@pytest.fixture(autouse=True)
def no_process_choice(monkeypatch):
    """Each test starts with no set_blas_threads choice (the environment's, or 1)."""
    monkeypatch.setattr(threads, "_process_choice", threads._UNSET)
    monkeypatch.delenv(ENV, raising=False)


@pytest.fixture
def two_threads():
    """numpy's BLAS at 2 threads (one per core on the 2-core machine; capped where fewer),
    as a user gets by default; the test then checks what imunav does inside it."""
    assert blas_counts(), "numpy has no BLAS threadpool threadpoolctl can see"
    with threadpool_limits(limits=2, user_api="blas"):
        yield blas_counts()


def test_plain_simulate_runs_its_kernel_on_one_blas_thread_and_restores(two_threads):
    m = spy()
    sig = simulate_imu(m, 50.0, kind="increments")
    assert len(sig) == 150 and m.seen
    assert all(c == [1] * len(c) for c in m.seen)                 # inside: one thread each
    assert blas_counts() == two_threads                            # after: as it was


def test_the_caller_chooses(two_threads):
    m = spy()
    with imunav.blas_threads(None):                                # leave BLAS as configured
        simulate_imu(m, 50.0, kind="increments")
    assert m.seen and all(c == two_threads for c in m.seen)
    m.seen = []
    with imunav.blas_threads(2):
        simulate_imu(m, 50.0, kind="increments")
    assert m.seen and all(c == two_threads for c in m.seen)        # 2 (or the cap)
    assert kernel_threads() == 1                                   # the block's choice ended
    previous = imunav.set_blas_threads(None)
    try:
        assert previous == 1 and kernel_threads() is None
        m.seen = []
        simulate_imu(m, 50.0, kind="increments")
        assert all(c == two_threads for c in m.seen)
        with imunav.blas_threads(1):                               # a block beats the process
            assert kernel_threads() == 1
    finally:
        imunav.set_blas_threads(previous)
    assert kernel_threads() == 1


def test_environment_variable(monkeypatch):
    monkeypatch.setenv(ENV, "none")
    assert kernel_threads() is None
    monkeypatch.setenv(ENV, " 3 ")
    assert kernel_threads() == 3
    monkeypatch.setenv(ENV, "")
    assert kernel_threads() == 1
    with imunav.blas_threads(2):                                   # a choice in code wins
        assert kernel_threads() == 2
    monkeypatch.setenv(ENV, "two")
    with pytest.raises(ImunavError, match=f"{ENV} must be a whole number ≥ 1 or 'none', got 'two'"):
        kernel_threads()
    monkeypatch.setenv(ENV, "0")
    with pytest.raises(ImunavError, match=ENV):
        simulate_imu(spy(), 50.0, kind="increments")


def test_cli_names_a_bad_environment_variable(monkeypatch, tmp_path, capsys):
    from imunav.cli import main

    motion = tmp_path / "m.toml"
    motion.write_text('duration = 2\n[attitude]\nroll = "0.3*sin(t)"\n')
    monkeypatch.setenv(ENV, "-1")
    assert main(["simulate", str(motion), "--rate", "50", "--output", "increments", "--out",
                 str(tmp_path / "s.csv")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and ENV in err and "'-1'" in err


@pytest.mark.parametrize("bad", [0, -2, 1.5, True, "1"])
def test_bad_choices_are_refused(bad):
    with pytest.raises(ImunavError, match="whole number ≥ 1 or None"):
        imunav.set_blas_threads(bad)
    with pytest.raises(ImunavError, match=r"blas_threads\(n\)"):
        with imunav.blas_threads(bad):
            pass
    assert kernel_threads() == 1


def test_monte_carlo_chunks_run_one_blas_thread(two_threads, monkeypatch):
    seen = []
    real = montecarlo.navigate_batch

    def recording(*args, **kwargs):
        seen.append(blas_counts())
        return real(*args, **kwargs)

    monkeypatch.setattr(montecarlo, "navigate_batch", recording)
    monte_carlo(Motion(roll="0.2*sin(t)", duration=2.0), ImuModel.load("BMI088"), 50.0, runs=4,
                chunk=2, progress=False)
    assert len(seen) == 2 and all(c == [1] * len(c) for c in seen)
    assert blas_counts() == two_threads


def test_concurrent_kernels_share_the_limit_until_the_last_leaves(two_threads):
    """The main thread enters, a worker thread enters and leaves: the main thread still runs
    limited; the limit is lifted when it leaves. (OpenBLAS honours a change of its thread count
    only from the thread that made the last change, or once that thread has ended: the main
    thread, which set the limit, lifts it here.)"""
    w_done = threading.Event()
    seen = {}

    def worker():
        with blas_limit():
            seen["worker"] = blas_counts()
        seen["after_worker"] = blas_counts()
        w_done.set()

    with blas_limit():
        t = threading.Thread(target=worker)
        t.start()
        assert w_done.wait(5)
        t.join(5)
        assert threads._active == 1 and blas_counts() == [1] * len(two_threads)
    assert seen == {"worker": [1] * len(two_threads), "after_worker": [1] * len(two_threads)}
    assert blas_counts() == two_threads and threads._active == 0 and threads._limiter is None


def test_nested_limits_and_none(two_threads):
    with blas_limit(None):
        assert blas_counts() == two_threads
        with blas_limit(1):
            assert blas_counts() == [1] * len(two_threads)
            with blas_limit():                                     # nested: the limit stays
                assert blas_counts() == [1] * len(two_threads)
            assert blas_counts() == [1] * len(two_threads)
        assert blas_counts() == two_threads


def test_blas_env_for_child_processes():
    env = blas_env(env={"PATH": "/bin"})
    assert env == {"PATH": "/bin", ENV: "1", "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1",
                   "MKL_NUM_THREADS": "1"}
    assert blas_env(None, env={}) == {ENV: "none"}
    with imunav.blas_threads(2):
        assert blas_env(env={})["OPENBLAS_NUM_THREADS"] == "2"
    with pytest.raises(ImunavError, match="blas_env"):
        blas_env(0)


def test_limit_changes_no_result():
    """The kernels give the same bits with one BLAS thread as with numpy's default."""
    m = Motion(x="sin(t)", y="t**2/10", yaw="0.3*sin(t)", roll="0.3*sin(2*t)", duration=30.0)
    one = simulate_imu(m, 200.0, kind="increments")
    with imunav.blas_threads(None):
        default = simulate_imu(m, 200.0, kind="increments")
    assert np.array_equal(one.gyro, default.gyro) and np.array_equal(one.accel, default.accel)


def test_earth_navigation_runs_its_gravity_products_on_one_blas_thread(two_threads, monkeypatch):
    """The rotating-Earth path multiplies the gravity quadrature through BLAS ((2, 8) weights
    times the node rows): one thread inside, as the flat kernels (with a busy core a
    two-thread product waited for its descheduled thread)."""
    from imunav import navigate
    from imunav.motion import EarthMotion
    from imunav.strapdown.rotating import EarthIntegrator

    seen = []
    real = EarthIntegrator._integrals

    def recording(self, *args, **kwargs):
        seen.append(blas_counts())
        return real(self, *args, **kwargs)

    monkeypatch.setattr(EarthIntegrator, "_integrals", recording)
    m = EarthMotion(Motion(x="2*t", yaw="0.1*t", duration=20.0), (0.8, 0.2, 100.0))
    sig = simulate_imu(m, 50.0, kind="increments")
    navigate(sig, *m.states([0.0]).initial(), earth="wgs84")
    assert seen and all(c == [1] * len(c) for c in seen)
    assert blas_counts() == two_threads
