"""The package's layering: every room on its floor, arrows only point down, no import cycles,
no import hidden in a function, no private name borrowed from another module, papers imported
only where they may be (issues 13 and 24).

Every ``import`` statement in every module is read from the source (module level and inside
functions alike, so that no function-level import can hide a cycle).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2] / "imunav"

#: The floors, from the ground up; each room of a floor may import its own modules and the
#: rooms of lower floors, never a room of its own floor or above. ``symbolic`` (SymPy
#: derivations) stands on the ground floor beside ``core``: it needs nothing of imunav.
FLOORS = [
    {"imunav.core", "imunav.symbolic"},
    {"imunav.earth"},                      # WGS-84: constants, gravity, frames (on core)
    {"imunav.motion"},
    {"imunav.sensors"},
    {"imunav.io", "imunav.strapdown"},
    {"imunav.estimation"},
    {"imunav.analysis"},
    {"imunav.papers"},
    {"imunav.plotting"},                   # the faces: figures, the reproductions, the CLI
    {"imunav.reproduce"},
    {"imunav.cli"},
    {"imunav._aliases"},                   # deprecated module names (imports on demand)
    {"imunav.__main__", "imunav"},         # the package facade (imunav/__init__.py)
]
#: Room → floor.
LAYERS = {room: floor for floor, rooms in enumerate(FLOORS) for room in rooms}
#: The one upward arrow allowed (issue 35): the papers draw their figures in the book's style,
#: which lives in the plotting room's style module — a module that imports nothing of imunav
#: (held by ``test_the_style_module_stands_alone``), so the arrow can pull nothing else up.
UPWARD_ALLOWED = {("imunav.papers", "imunav.plotting.style")}
#: The only modules outside imunav.papers that may import it.
PAPER_IMPORTERS = {"imunav.reproduce", "imunav.cli"}
#: Modules whose function-level imports of imunav are their purpose (they import on demand).
LAZY_IMPORTERS = {"imunav._aliases"}


def _modules() -> dict[str, Path]:
    out = {}
    for p in ROOT.rglob("*.py"):
        parts = ("imunav",) + p.relative_to(ROOT).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = p
    return out


MODULES = _modules()


def _room(module: str) -> str:
    return max((k for k in LAYERS if module == k or module.startswith(k + ".")), key=len)


def _layer(module: str) -> int:
    return LAYERS[_room(module)]


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


def test_every_module_is_in_a_room():
    assert set(LAYERS) >= {_room(m) for m in MODULES}
    assert all(any(m == r or m.startswith(r + ".") for m in MODULES) for r in LAYERS)


def _allowed_upward(module: str, target: str) -> bool:
    return (_room(module), target) in UPWARD_ALLOWED


@pytest.mark.parametrize("module", sorted(MODULES))
def test_arrows_point_down(module):
    up = sorted(t for t in GRAPH[module]
                if _layer(t) > _layer(module) and not _allowed_upward(module, t))
    assert not up, f"{module} (floor {_layer(module)}) imports higher floors: {up}"
    side = sorted(t for t in GRAPH[module]
                  if _layer(t) == _layer(module) and _room(t) != _room(module))
    assert not side, f"{module} imports another room of its own floor: {side}"


def test_the_style_module_stands_alone():
    """The exception above holds only while the style module imports nothing of imunav; and it
    is exactly that one arrow — the papers may not import the plotting package or another of
    its modules, and no other room may reach up to the style."""
    assert GRAPH["imunav.plotting.style"] == set()
    assert _allowed_upward("imunav.papers.plaksiy", "imunav.plotting.style")
    assert not _allowed_upward("imunav.papers.plaksiy", "imunav.plotting")
    assert not _allowed_upward("imunav.analysis.metrics", "imunav.plotting.style")
    assert not _allowed_upward("imunav.core.units", "imunav.plotting.style")
    users = sorted(m for m in MODULES if "imunav.plotting.style" in GRAPH[m]
                   and _layer(m) < _layer("imunav.plotting.style"))
    assert users and all(_room(m) == "imunav.papers" for m in users), users


def _function_imports(module: str) -> list[tuple[int, str]]:
    """``(line, module)`` of every import of imunav inside a function of ``module``."""
    tree = ast.parse(MODULES[module].read_text())
    found = []
    for fn in ast.walk(tree):
        if not isinstance(fn, ast.FunctionDef | ast.AsyncFunctionDef):
            continue
        for node in ast.walk(fn):
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                names = ["." * node.level + (node.module or "")]
            else:
                continue
            found += [(node.lineno, n) for n in names
                      if n == "imunav" or n.startswith(("imunav.", "."))]
    return found


@pytest.mark.parametrize("module", sorted(MODULES))
def test_no_imunav_import_inside_a_function(module):
    """An import of imunav inside a function is either dodging a cycle (a lower module is
    missing) or hiding a dependency from this test; both are refused."""
    if module in LAZY_IMPORTERS:
        return
    bad = _function_imports(module)
    assert not bad, f"{module} imports imunav inside a function: {bad}"


def _private_imports(path: Path) -> list[tuple[int, str]]:
    """``(line, "module.name")`` of every underscore name imported from an imunav module."""
    found = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and (node.module or "").startswith("imunav"):
            found += [(node.lineno, f"{node.module}.{a.name}") for a in node.names
                      if a.name.startswith("_") and not a.name.startswith("__")
                      and f"{node.module}.{a.name}" not in MODULES]
    return found


SOURCES = sorted(MODULES.values()) + sorted((ROOT.parent / "notebooks" / "src").glob("*.py"))


@pytest.mark.parametrize("path", SOURCES, ids=lambda p: p.name)
def test_no_module_imports_a_private_name_of_another(path):
    """Kernels and helpers that other modules need have public names (issue 24): a module
    never reaches into another's underscore names."""
    bad = _private_imports(path)
    assert not bad, f"{path.name} imports private names: {bad}"


def test_the_import_checks_see_planted_offenders(tmp_path):
    planted = tmp_path / "m.py"
    planted.write_text("from imunav.core.kernels import quat_mul as _mul\n"
                       "from imunav.core.rotations import _secret\n"
                       "def f():\n    from imunav.core import kernels\n    import numpy\n")
    assert _private_imports(planted) == [(2, "imunav.core.rotations._secret")]
    MODULES["imunav.planted"] = planted
    try:
        assert _function_imports("imunav.planted") == [(4, "imunav.core")]
    finally:
        del MODULES["imunav.planted"]


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
    assert _layer("imunav.strapdown.highorder") == 4 and _layer("imunav.io.files") == 4
    assert _layer("imunav.symbolic.trig") == 0 and _layer("imunav.estimation.kalman") == 5
    assert _layer("imunav.earth") == 1 and _layer("imunav.motion.geodetic") == 2
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
    assert "imunav.strapdown.classic" in _imports("imunav.strapdown.algorithms")


def test_old_module_names_still_import_with_a_deprecation_warning():
    import importlib
    import sys

    for old, new in (("imunav.assess", "nav_errors"), ("imunav.benchmarks", "coning"),
                     ("imunav.quickstart", "run"), ("imunav.montecarlo", "plot_envelope"),
                     ("imunav.core.style", "check_figure")):
        sys.modules.pop(old, None)
        with pytest.warns(DeprecationWarning, match=f"{old} is deprecated"):
            mod = importlib.import_module(old)
        assert callable(getattr(mod, new))
