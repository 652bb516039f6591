"""Build notebooks/NN_*.ipynb from their reviewable sources notebooks/src/NN_*.py, then execute.

Sources use the percent format: ``# %%`` starts a code cell, ``# %% [markdown]`` a markdown
cell whose lines are commented with ``# ``. Executed notebooks are committed with outputs and
re-run under strict ``pytest --nbval`` by ``make test``.

Usage: ``python tools/build_notebooks.py [NAME ...]`` (default: all).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import nbformat

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT / "notebooks" / "src"


def parse(text: str) -> nbformat.NotebookNode:
    nb = nbformat.v4.new_notebook()
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3",
                                 "language": "python"}
    cells: list[tuple[str, list[str]]] = []
    for line in text.splitlines():
        if line.startswith("# %%"):
            cells.append(("markdown" if "[markdown]" in line else "code", []))
        elif cells:
            cells[-1][1].append(line)
    for kind, lines in cells:
        while lines and not lines[-1].strip():
            lines.pop()
        while lines and not lines[0].strip():
            lines.pop(0)
        if kind == "markdown":
            src = "\n".join(ln[2:] if ln.startswith("# ") else ln.lstrip("#") for ln in lines)
            nb.cells.append(nbformat.v4.new_markdown_cell(src))
        else:
            nb.cells.append(nbformat.v4.new_code_cell("\n".join(lines)))
    return nb


def build(src: Path) -> Path:
    out = ROOT / "notebooks" / (src.stem + ".ipynb")
    nbformat.write(parse(src.read_text()), out)
    subprocess.run([sys.executable, "-m", "jupyter", "nbconvert", "--to", "notebook", "--execute",
                    "--inplace", "--ExecutePreprocessor.timeout=600", str(out)], check=True,
                   env={**__import__("os").environ, "MPLBACKEND": "Agg"})
    return out


if __name__ == "__main__":
    names = sys.argv[1:]
    for src in sorted(SRC.glob("*.py")):
        if not names or any(n in src.stem for n in names):
            print("building", build(src).relative_to(ROOT))
