"""The vectorised fast path against the plain one-sample-at-a-time loops of
imunav.strapdown.reference.

Sizes are chosen to exercise the sequential short path, several cache chunks, padded last
blocks and the recursive scan of block totals (chunk and block sizes are shrunk so that short
inputs reach every branch).
"""

import numpy as np
import pytest

from imunav.core.kernels import quat_exp, quat_mul
from imunav.core.rotations import quat_normalize
from imunav.core.validation import ImunavError
from imunav.sensors.signals import ImuSignals
from imunav.strapdown import cumulative_product, exp_product, navigate, reference, scan


@pytest.fixture(params=[(1 << 15, 16), (64, 4), (48, 3)], ids=["default", "small", "odd"])
def scan_sizes(request, monkeypatch):
    chunk, leaf = request.param
    monkeypatch.setattr(scan, "_SCAN_CHUNK", chunk)
    monkeypatch.setattr(scan, "_SCAN_LEAF", leaf)
    return request.param


def _plain_chain(q0, dq):
    out = [q0]
    for d in dq:
        out.append(quat_mul(out[-1], d))
    out = np.array(out)
    return out / np.linalg.norm(out, axis=-1, keepdims=True)


def _smooth_case(n):
    """Smooth increments at 100 Hz and state arrays holding an arbitrary initial state."""
    h, g = 0.01, 9.80665
    t = np.arange(1, n + 1) * h
    dth = h * np.stack([np.sin(t), 0.5 * np.cos(0.7 * t), 0.3 * np.sin(1.3 * t)], axis=1)
    dv = h * np.stack([np.sin(t), np.cos(t), -g + 0.1 * np.sin(2 * t)], axis=1)
    q0 = quat_normalize([1.0, 0.1, -0.2, 0.3])
    q, v, p = np.zeros((n + 1, 4)), np.zeros((n + 1, 3)), np.zeros((n + 1, 3))
    q[0], v[0], p[0] = q0, [1.0, 2.0, 0.0], [3.0, 0.0, -1.0]
    return h, g, dth, dv, q, v, p


def _navigate(dth, dv, h, g, q, v, p, algorithm):
    t = np.arange(1, dth.shape[0] + 1) * h
    return navigate(ImuSignals(t, dth, dv, "increments", 1 / h, g), q[0], v[0], p[0],
                    algorithm=algorithm)


def _assert_matches(nav, q, v, p):
    np.testing.assert_allclose(nav.quaternion, q, rtol=0, atol=1e-12)
    np.testing.assert_allclose(nav.velocity, v, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(nav.position, p, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("n", [0, 1, 5, 64, 65, 1001, 4099])
def test_cumulative_product_matches_plain_loop(rng, scan_sizes, n):
    dq = quat_normalize(np.concatenate([np.ones((n, 1)), 0.05 * rng.normal(size=(n, 3))], axis=1))
    q0 = quat_normalize(rng.normal(size=4))
    ref = _plain_chain(q0, dq)
    np.testing.assert_allclose(cumulative_product(q0, dq), ref, rtol=0, atol=1e-12)
    # unnormalised chains keep their norm drift exactly as the loop does
    raw = dq * 1.001
    loop = [q0]
    for d in raw:
        loop.append(quat_mul(loop[-1], d))
    np.testing.assert_allclose(cumulative_product(q0, raw, normalize=False), np.array(loop),
                               rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("scale", [0.02, 2.0])  # small angles (√(1−sin²) branch) and large
@pytest.mark.parametrize("n", [3, 700, 5000])
def test_exp_product_matches_reference_loop(rng, scan_sizes, n, scale):
    phi = scale * rng.normal(size=(n, 3))
    phi[n // 2] = 0.0                              # an exactly zero rotation takes the 1/2 limit
    q0 = quat_normalize(rng.normal(size=4))
    q = np.zeros((n + 1, 4))
    q[0] = q0
    reference.exp_attitude(phi, q)
    np.testing.assert_allclose(exp_product(q0, phi), q, rtol=0, atol=1e-12)


def test_batched_chains_equal_single_chains(rng, scan_sizes):
    n, R = 777, 5
    phi = 0.03 * rng.normal(size=(n, R, 3))
    q0 = quat_normalize(rng.normal(size=(R, 4)))
    qb = exp_product(q0, phi)
    assert qb.shape == (n + 1, R, 4)
    for r in range(R):
        np.testing.assert_allclose(qb[:, r], _plain_chain(q0[r], quat_exp(phi[:, r])), atol=1e-12)


def test_exact_exponential_navigation_matches_reference_loop(rng, scan_sizes):
    h, g, dth, dv, q, v, p = _smooth_case(3000)
    reference.exp_navigation(dth, dv, h, g, q, v, p)
    _assert_matches(_navigate(dth, dv, h, g, q, v, p, "exact_exponential"), q, v, p)


def test_chain_shapes_are_checked():
    with pytest.raises(ImunavError, match="dq must have shape"):
        cumulative_product([1.0, 0, 0, 0], np.zeros((5, 2, 4)))
    with pytest.raises(ImunavError, match="phi must have shape"):
        exp_product(np.tile([1.0, 0, 0, 0], (3, 1)), np.zeros((5, 2, 3)))


@pytest.fixture(scope="module")
def sympy_tables():
    """The reference loop's stencils and tap weights, derived with SymPy (no fast-path code)."""
    return reference.poly_tables(1500, 0.01, 8)


@pytest.mark.parametrize("chunk", [1 << 15, 100, 7])
def test_default_poly_navigation_matches_reference_loop(sympy_tables, monkeypatch, chunk):
    from imunav.strapdown import highorder, stream

    monkeypatch.setattr(highorder, "_POLY_CHUNK", chunk)
    monkeypatch.setattr(stream, "CHUNK", max(chunk, 64))
    h, g, dth, dv, q, v, p = _smooth_case(1500)
    reference.poly_navigation(dth, dv, h, g, *sympy_tables, q, v, p)
    _assert_matches(_navigate(dth, dv, h, g, q, v, p, "poly8_m6"), q, v, p)
