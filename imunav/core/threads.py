"""How many BLAS threads imunav's kernels use: one by default, the caller's choice otherwise.

imunav's hot kernels (the Chebyshev blocks of the exact increments, the tap weights of the
high-order navigation, a Monte Carlo chunk) multiply a small matrix into a long one. Two
OpenBLAS threads never made these faster on the 2-core machine we measure on, and when
another process keeps a core busy a 2-thread product waits for its descheduled second thread:
exact increments took 3× as long (issue 26). Several processes each running a BLAS pool
(Monte Carlo chunks on Dask workers) oversubscribe the cores the same way. So every kernel runs
inside :func:`blas_limit`, which sets the BLAS libraries loaded in the process (threadpoolctl)
to the chosen number of threads for the duration of the call and restores them afterwards.

The choice, in order of precedence:

- ``with imunav.blas_threads(n):`` — for the calls inside the block (this thread or task);
- ``imunav.set_blas_threads(n)`` — for the rest of the process;
- the environment variable ``IMUNAV_BLAS_THREADS`` (read on first use; e.g. set it for Dask
  workers, which are other processes);
- else 1.

``n`` is a whole number ≥ 1, or ``None`` (``"none"`` in the environment) to leave the BLAS
libraries as numpy configured them (``OPENBLAS_NUM_THREADS`` and the like, else one thread per
core). Code outside imunav's kernels is never affected. A child process started by a script
(a notebook kernel, a worker) gets the same choice from :func:`blas_env`.

The setting is process-wide in the BLAS library: while any kernel is inside its limit, other
threads' BLAS calls see it too, and the limit is lifted when the last kernel leaves. OpenBLAS
honours a change of its thread count only from the thread that made the last change (or once
that thread has ended), so kernels overlapping on several threads can leave BLAS at the limit
after they finish (a Dask worker's threads: one BLAS thread each is what they should have;
Dask's nanny starts its workers with ``OPENBLAS_NUM_THREADS=1`` anyway). Kernels called from
one thread, as in a script, a notebook or the command line, always restore it.

May import: ``imunav.core.validation``.
"""

from __future__ import annotations

import contextvars
import functools
import os
import sys
import threading
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import TypeVar

from imunav.core.validation import ImunavError

#: The environment variable read when neither ``blas_threads`` nor ``set_blas_threads`` chose.
ENV = "IMUNAV_BLAS_THREADS"
#: BLAS threads of imunav's kernels when nothing else is chosen.
DEFAULT_THREADS = 1

_UNSET = object()
_block_choice: contextvars.ContextVar = contextvars.ContextVar("imunav_blas_threads",
                                                               default=_UNSET)
_process_choice: object = _UNSET

_lock = threading.Lock()
_limiter = None                     # the threadpoolctl limiter in force, if any
_active = 0                         # kernels running inside it (all threads)
_controller = None
_controller_modules = -1            # len(sys.modules) when the controller last looked


def _check(n, what: str) -> int | None:
    if n is None:
        return None
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise ImunavError(f"{what} must be a whole number ≥ 1 or None (leave BLAS as numpy "
                          f"configured it), got {n!r}")
    return n


def _from_env() -> int | None:
    raw = os.environ.get(ENV)
    if raw is None or not raw.strip():
        return DEFAULT_THREADS
    text = raw.strip().lower()
    if text in ("none", "default"):
        return None
    try:
        n = int(text)
    except ValueError:
        n = 0
    if n < 1:
        raise ImunavError(f"the environment variable {ENV} must be a whole number ≥ 1 or "
                          f"'none', got {raw!r}")
    return n


def kernel_threads() -> int | None:
    """The BLAS threads imunav's kernels will use here and now.

    The choice of the innermost :func:`blas_threads` block of this thread or task, else the
    last :func:`set_blas_threads`, else the environment variable ``IMUNAV_BLAS_THREADS``,
    else 1 (:data:`DEFAULT_THREADS`).

    Returns
    -------
    int or None
        Threads ≥ 1, or None: BLAS left as numpy configured it.

    Raises
    ------
    ImunavError
        If the choice comes from ``IMUNAV_BLAS_THREADS`` and it is neither a whole number ≥ 1
        nor ``none``.
    """
    choice = _block_choice.get()
    if choice is _UNSET:
        choice = _process_choice
    if choice is _UNSET:
        choice = _from_env()
    return choice  # type: ignore[return-value]


def set_blas_threads(n: int | None) -> int | None:
    """Choose the BLAS threads of imunav's kernels for the rest of the process.

    Parameters
    ----------
    n : int or None
        Threads (≥ 1) for every kernel from now on; ``None`` leaves BLAS as numpy configured it.

    Returns
    -------
    int or None
        The previous choice.

    Raises
    ------
    ImunavError
        If ``n`` is neither None nor a positive integer.

    Examples
    --------
    >>> import imunav
    >>> previous = imunav.set_blas_threads(2)
    >>> _ = imunav.set_blas_threads(previous)
    """
    global _process_choice
    n = _check(n, "set_blas_threads(n): n")
    previous = kernel_threads()
    _process_choice = n
    return previous


@contextmanager
def blas_threads(n: int | None) -> Iterator[None]:
    """Within the block, imunav's kernels use ``n`` BLAS threads, in this thread or task only;
    the previous choice comes back after.

    Parameters
    ----------
    n : int or None
        Threads (≥ 1) inside the block; ``None``: as numpy configured BLAS.

    Yields
    ------
    None

    Raises
    ------
    ImunavError
        If ``n`` is neither None nor a positive integer.

    Examples
    --------
    >>> import imunav
    >>> with imunav.blas_threads(2):
    ...     pass
    """
    token = _block_choice.set(_check(n, "blas_threads(n): n"))
    try:
        yield
    finally:
        _block_choice.reset(token)


def _threadpool_controller():
    """One threadpoolctl controller, looked at again when modules have been imported since
    (a newly imported extension may have loaded another BLAS)."""
    global _controller, _controller_modules
    if _controller is None or len(sys.modules) != _controller_modules:
        from threadpoolctl import ThreadpoolController

        _controller = ThreadpoolController()
        _controller_modules = len(sys.modules)
    return _controller


@contextmanager
def blas_limit(threads=_UNSET) -> Iterator[None]:
    """Run the block with the BLAS libraries of the process set to ``threads`` threads.

    The limit is restored when the last block inside a limit leaves; nested and concurrent
    blocks share the limit first put in force (see the module's notes on OpenBLAS). Kernels
    use it through :func:`limit_blas`; a block of library calls that should be pinned as a
    whole can use it directly.

    Parameters
    ----------
    threads : int or None, optional
        Threads ≥ 1 inside the block; ``None`` leaves BLAS unchanged. Default: the choice in
        force (:func:`kernel_threads`).

    Yields
    ------
    None

    Raises
    ------
    ImunavError
        If ``threads`` is neither None nor a whole number ≥ 1.

    Examples
    --------
    >>> import numpy as np
    >>> with blas_limit(1):
    ...     _ = np.ones((50, 50)) @ np.ones((50, 50))
    """
    global _limiter, _active
    n = kernel_threads() if threads is _UNSET else _check(threads, "blas_limit(threads)")
    with _lock:
        entered = _limiter is not None or n is not None
        if _limiter is None and n is not None:
            _limiter = _threadpool_controller().limit(limits=n, user_api="blas")
        if entered:
            _active += 1
    try:
        yield
    finally:
        if entered:
            with _lock:
                _active -= 1
                if _active == 0:
                    _limiter.restore_original_limits()
                    _limiter = None


F = TypeVar("F", bound=Callable)


def limit_blas(func: F) -> F:
    """Decorator for a kernel: each call runs inside :func:`blas_limit`.

    The number of threads is the choice in force when the call is made (not when the function
    is decorated). Do not decorate a generator: the limit would be held across each ``yield``.

    Parameters
    ----------
    func : callable
        The kernel.

    Returns
    -------
    callable
        ``func`` wrapped (``functools.wraps``: same name, docstring and signature).
    """

    @functools.wraps(func)
    def kernel(*args, **kwargs):
        with blas_limit():
            return func(*args, **kwargs)

    return kernel  # type: ignore[return-value]


def blas_env(threads: int | None = _UNSET, env: dict | None = None) -> dict[str, str]:
    """An environment for a child process (a notebook kernel, a worker) with this BLAS choice.

    With a number, the BLAS libraries' own variables (``OPENBLAS_NUM_THREADS``,
    ``OMP_NUM_THREADS``, ``MKL_NUM_THREADS``) are set to it too, so that the child's other BLAS
    calls do not start more threads than that either.

    Parameters
    ----------
    threads : int or None, optional
        Threads ≥ 1 for the child's imunav kernels; ``None`` leaves the child's BLAS as numpy
        configures it. Default: the choice in force here (:func:`kernel_threads`).
    env : dict, optional
        The environment to start from (default ``os.environ``); it is copied, not changed.

    Returns
    -------
    dict of str to str
        The copy, with ``IMUNAV_BLAS_THREADS`` set (``"none"`` for None).

    Raises
    ------
    ImunavError
        If ``threads`` is neither None nor a whole number ≥ 1.

    Examples
    --------
    >>> blas_env(2, env={})
    {'IMUNAV_BLAS_THREADS': '2', 'OPENBLAS_NUM_THREADS': '2', 'OMP_NUM_THREADS': '2', 'MKL_NUM_THREADS': '2'}
    """
    n = kernel_threads() if threads is _UNSET else _check(threads, "blas_env(threads)")
    out = dict(os.environ if env is None else env)
    out[ENV] = "none" if n is None else str(n)
    if n is not None:
        for var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
            out[var] = str(n)
    return out
