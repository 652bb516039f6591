"""Every list of aid names derives from the aid registry (issue 35, "Done when"): the literals in
``imunav/`` — lists, tuples, sets, dict keys (``{...}`` or ``dict(...)``) — that name three or
more of gnss/baro/heading/nhc/zupt are at most one. A list written out by hand is how an aid
was silently left out of the analysis before the registry (``performance.SENSOR_ORDER``); the
lists come from :data:`imunav.sensors.aids.AIDS` instead.

Counted on the source (an AST walk over ``imunav/**/*.py``), so no list can hide in a module
that is not imported. Prose (docstrings, help texts) is not a literal of this kind.
"""

from __future__ import annotations

import ast
from pathlib import Path

from imunav.sensors.aids import AIDS

ROOT = Path(__file__).resolve().parents[2] / "imunav"

#: The aids the issue names (the odometer came with the registry).
NAMED = {"gnss", "baro", "heading", "nhc", "zupt"}
#: At most this many literals may name three or more of them.
ALLOWED = 1


def aid_lists(source: str) -> list[tuple[int, list[str]]]:
    """``(line, names)`` of every list, tuple, set, dict (its keys) or ``dict(...)`` (its
    keywords) literal in ``source`` naming three or more aids of :data:`NAMED`."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.List | ast.Tuple | ast.Set):
            items = [e.value for e in node.elts if isinstance(e, ast.Constant)]
        elif isinstance(node, ast.Dict):
            items = [k.value for k in node.keys if isinstance(k, ast.Constant)]
        elif isinstance(node, ast.Call) and getattr(node.func, "id", None) == "dict":
            items = [k.arg for k in node.keywords]
        else:
            continue
        names = sorted(NAMED & {x for x in items if isinstance(x, str)})
        if len(names) >= 3:
            found.append((node.lineno, names))
    return found


def test_at_most_one_literal_lists_the_aids():
    found = [(p.relative_to(ROOT.parent).as_posix(), line, names)
             for p in sorted(ROOT.rglob("*.py"))
             for line, names in aid_lists(p.read_text())]
    assert len(found) <= ALLOWED, ("lists of aid names written out (derive them from "
                                   f"imunav.sensors.aids.AIDS): {found}")


def test_the_registry_holds_the_named_aids():
    # what the lists derive from holds every aid the issue names
    assert NAMED <= set(AIDS)


def test_the_count_sees_planted_lists():
    planted = ('A = ["gnss", "baro", "heading"]\n'
               'B = ("nhc", "zupt", "gnss", "x")\n'
               'C = {"gnss": 1, "baro": 2, "zupt": 3}\n'
               'D = dict(gnss=1, heading=2, nhc=3)\n'
               'E = {"gnss", "baro", "odometer"}\n'               # two of the named: not counted
               'F = "gnss, baro, heading"\n'                       # prose: not a list
               'G = [n for n in AIDS]\n')
    assert [line for line, _ in aid_lists(planted)] == [1, 2, 3, 4]
    assert aid_lists(planted)[0][1] == ["baro", "gnss", "heading"]
