"""The package's layering: arrows only point down, no import cycles, papers imported only where
they may be (issue 13).

Every ``import`` statement in every module is read from the source (module level and inside
functions alike, so that no function-level import can hide a cycle).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1] / "imunav"

#: Layer of each top-level part, from the bottom. A module may import its own layer or below.
LAYERS = {
    "imunav.core": 0,
    "imunav.motion": 1,
    "imunav.sensors": 2,
    "imunav.strapdown": 3,
    "imunav.analysis": 4,
    "imunav.io": 5,
    "imunav.symbolic": 6,
    "imunav.papers": 6,
    "imunav.plotting": 7,
    "imunav.reproduce": 7,
    "imunav.cli": 7,
    "imunav.__main__": 8,
    "imunav._aliases": 8,
    "imunav": 8,                        # the package facade (imunav/__init__.py)
}
#: The only modules outside imunav.papers that may import it.
PAPER_IMPORTERS = {"imunav.reproduce", "imunav.cli"}


def _modules() -> dict[str, Path]:
    out = {}
    for p in ROOT.rglob("*.py"):
        parts = ("imunav",) + p.relative_to(ROOT).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = p
    return out


MODULES = _modules()


def _layer(module: str) -> int:
    best = max((k for k in LAYERS if module == k or module.startswith(k + ".")), key=len)
    return LAYERS[best]


def _imports(module: str) -> set[str]:
    """The imunav modules ``module`` imports (a name imported from a package resolves to the
    submodule if there is one, else to the package's __init__)."""
    tree = ast.parse(MODULES[module].read_text())
    package = module if MODULES[module].name == "__init__.py" else module.rpartition(".")[0]
    found = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                up = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(up + ([base] if base else []))
            names = [f"{base}.{a.name}" if f"{base}.{a.name}" in MODULES else base
                     for a in node.names]
        else:
            continue
        found |= {n for n in names if n == "imunav" or n.startswith("imunav.")}
    return {n if n in MODULES else n.rpartition(".")[0] for n in found} - {module}


GRAPH = {m: _imports(m) for m in MODULES}


@pytest.mark.parametrize("module", sorted(MODULES))
def test_arrows_point_down(module):
    up = sorted(t for t in GRAPH[module] if _layer(t) > _layer(module))
    assert not up, f"{module} (layer {_layer(module)}) imports higher layers: {up}"


@pytest.mark.parametrize("module", sorted(MODULES))
def test_papers_imported_only_by_papers_reproduce_and_cli(module):
    if module.startswith("imunav.papers") or module in PAPER_IMPORTERS:
        return
    bad = sorted(t for t in GRAPH[module] if t.startswith("imunav.papers"))
    assert not bad, f"{module} imports {bad}"


def test_no_import_cycles():
    state: dict[str, int] = {}
    path: list[str] = []

    def visit(m):
        state[m] = 1
        path.append(m)
        for t in sorted(GRAPH[m]):
            if state.get(t) == 1:
                cycle = path[path.index(t):] + [t]
                raise AssertionError("import cycle: " + " → ".join(cycle))
            if t not in state:
                visit(t)
        path.pop()
        state[m] = 2

    for m in sorted(MODULES):
        if m not in state:
            visit(m)


def test_every_module_says_what_it_owns_and_may_import():
    missing = [m for m, p in MODULES.items()
               if "May import" not in (ast.get_docstring(ast.parse(p.read_text())) or "")]
    assert not missing, missing


def test_the_checker_sees_a_planted_cycle_and_an_upward_import():
    # the test's own machinery, on a graph with a known cycle and a known upward arrow
    assert _layer("imunav.strapdown.highorder") == 3 and _layer("imunav.io.files") == 5
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}}
    with pytest.raises(AssertionError, match="import cycle: a → b → c → a"):
        saved = dict(GRAPH)
        GRAPH.clear()
        GRAPH.update(graph)
        try:
            MODULES_saved = dict(MODULES)
            MODULES.clear()
            MODULES.update(dict.fromkeys(graph))
            test_no_import_cycles()
        finally:
            GRAPH.clear()
            GRAPH.update(saved)
            MODULES.clear()
            MODULES.update(MODULES_saved)
    assert "imunav.core.rotations" in _imports("imunav.strapdown.scan")
    assert "imunav.strapdown.classic" in _imports("imunav.strapdown.registry")


def test_old_module_names_still_import_with_a_deprecation_warning():
    import importlib
    import sys

    for old, new in (("imunav.assess", "nav_errors"), ("imunav.benchmarks", "coning"),
                     ("imunav.quickstart", "run"), ("imunav.montecarlo", "plot_envelope")):
        sys.modules.pop(old, None)
        with pytest.warns(DeprecationWarning, match=f"{old} is deprecated"):
            mod = importlib.import_module(old)
        assert callable(getattr(mod, new))
