"""The stored notebooks: each paired with its source (jupytext), executed, with its figures.

The notebooks are read as stored (on a repository page, in the rendered book) as much as run,
so what is stored is checked here; `make test`'s nbval pass re-runs them.
"""

from pathlib import Path

import jupytext
import nbformat
import pytest

NB = Path(__file__).resolve().parents[1] / "notebooks"
SOURCES = sorted((NB / "src").glob("*.py"))


def test_every_source_has_its_notebook_and_back():
    assert SOURCES, "no notebook sources"
    assert {p.stem for p in SOURCES} == {p.stem for p in NB.glob("[0-9]*.ipynb")}


def _cells(nb):
    return [(c.cell_type, c.source.strip()) for c in nb.cells]


@pytest.mark.parametrize("src", SOURCES, ids=[p.stem for p in SOURCES])
def test_pair_agrees(src):
    """notebooks/src/X.py and notebooks/X.ipynb hold the same cells (run `make notebooks`)."""
    stored = nbformat.read(NB / f"{src.stem}.ipynb", as_version=4)
    assert _cells(jupytext.read(src)) == _cells(stored)


@pytest.mark.parametrize("src", SOURCES, ids=[p.stem for p in SOURCES])
def test_stored_outputs_and_figures(src):
    nb = nbformat.read(NB / f"{src.stem}.ipynb", as_version=4)
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert all(c.execution_count is not None for c in code if c.source.strip()), "not executed"
    errors = [o for c in code for o in c.outputs if o.output_type == "error"]
    assert not errors, errors[0].get("ename")
    for c in code:
        figure_cell = "plt.show()" in c.source and "interact" not in c.source
        images = [o for o in c.outputs if any(k.startswith("image/") for k in o.get("data", {}))]
        assert images or not figure_cell, f"figure cell stored without its figure:\n{c.source[:200]}"


@pytest.mark.parametrize("src", SOURCES, ids=[p.stem for p in SOURCES])
def test_markdown_tables_keep_their_columns(src):
    """A '|' inside a table cell (a norm |x|) splits the row: the coverage tables would show
    values under the wrong heading. Every row must have as many cells as its header."""
    import re

    for cell in jupytext.read(src).cells:
        if cell.cell_type != "markdown":
            continue
        ncol = None
        for line in cell.source.splitlines():
            if not line.startswith("|"):
                ncol = None
                continue
            n = len(re.findall(r"(?<!\\)\|", line))
            ncol = n if ncol is None else ncol
            assert n == ncol, f"{src.name}: row has {n - 1} cells, header {ncol - 1}: {line[:80]}"
