"""nbval policy (after devito): printed text is compared strictly; renderings that are not
meant to be byte-stable are not — figures (PNG/SVG), LaTeX (its text/plain twin is compared)
and widget views (their state lives in the kernel)."""

SKIP = ("image/png", "image/svg+xml", "image/jpeg", "text/latex",
        "application/vnd.jupyter.widget-view+json")


def pytest_collectstart(collector):
    if getattr(collector, "skip_compare", None) is not None:
        collector.skip_compare = tuple(collector.skip_compare) + SKIP
