import json
import os
from pathlib import Path

import numpy as np
import pytest


@pytest.fixture
def rng():
    """Seeded generator; every random number in the tests comes from here."""
    return np.random.default_rng(20261123)


_DURATIONS: dict | None = None


def pytest_configure(config):
    """Under ``make mutation`` only: at most 6 GB of address space per mutant, so that a mutant
    which breaks a memory guard fails at once with MemoryError instead of running a
    many-gigabyte Monte Carlo until mutmut's timeout."""
    if "__mutmut_" in os.environ.get("MUTANT_UNDER_TEST", ""):
        import resource

        resource.setrlimit(resource.RLIMIT_AS, (6 << 30, resource.getrlimit(resource.RLIMIT_AS)[1]))


def pytest_collection_modifyitems(config, items):
    """Under ``make mutation`` only (mutmut sets MUTANT_UNDER_TEST): run the fastest tests
    first. mutmut stops at the first failure, so a mutant then dies on the cheapest test that
    sees it instead of after the 10-second Monte Carlo comparisons; the order of an ordinary
    run is untouched; the dask cluster test is left out. With IMUNAV_MUTATION_TEST_CAP=s (the
    first, fast pass of benchmarks/mutation.py) tests that took longer than s seconds are left
    out; the survivors of that pass are run again with every test."""
    global _DURATIONS
    name = os.environ.get("MUTANT_UNDER_TEST", "")
    if "__mutmut_" not in name:
        return
    if _DURATIONS is None:
        try:  # mutmut runs the tests inside mutants/, next to its recorded test durations
            _DURATIONS = json.loads(Path("mutmut-stats.json").read_text())["duration_by_test"]
        except (OSError, ValueError, KeyError):
            _DURATIONS = {}
    items.sort(key=lambda item: _DURATIONS.get(item.nodeid, 0.0))
    cap = float(os.environ.get("IMUNAV_MUTATION_TEST_CAP", "inf"))
    # the dask cluster test is left out: a mutant that breaks a worker leaves the client
    # waiting until mutmut's timeout (~15 min per mutant); the same chunk code runs locally
    slow = [item for item in items
            if _DURATIONS.get(item.nodeid, 0.0) > cap or "dask" in item.name]
    if slow:
        config.hook.pytest_deselected(items=slow)
        items[:] = [item for item in items if item not in slow]
