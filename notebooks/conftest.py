"""nbval policy (after devito): LaTeX renderings are not compared (their text/plain twin is)."""


def pytest_collectstart(collector):
    if getattr(collector, "skip_compare", None) is not None:
        collector.skip_compare = tuple(collector.skip_compare) + ("text/latex",)
