import numpy as np
import pytest


@pytest.fixture
def rng():
    """Seeded generator; every random number in the tests comes from here."""
    return np.random.default_rng(20261123)
