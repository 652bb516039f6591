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


def pytest_collection_modifyitems(config, items):
    """Under ``make mutation`` only (mutmut sets MUTANT_UNDER_TEST): run the fastest tests
    first. mutmut stops at the first failure, so a mutant then dies on the cheapest test that
    sees it instead of after the 10-second Monte Carlo comparisons; the order of an ordinary
    run is untouched. With IMUNAV_MUTATION_TEST_CAP=s (the first, fast pass of
    benchmarks/mutation.py) tests that took longer than s seconds are left out; the survivors
    of that pass are run again with every test."""
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
    slow = [item for item in items if _DURATIONS.get(item.nodeid, 0.0) > cap]
    if slow:
        config.hook.pytest_deselected(items=slow)
        items[:] = [item for item in items if item not in slow]
