"""Deprecated module names, kept for one release after the restructuring of 0.2.

``import imunav.assess`` (and the other former flat modules, and ``imunav.core.style``, now
``imunav.plotting.style``) still works: a meta-path finder
builds a module of that name holding the public names of the modules that replaced it, and
issues a :class:`DeprecationWarning` naming them. Remove this file in 0.3. One old path is
also a new public name: the function ``imunav.assess`` keeps its name when the old module
``imunav.assess`` is imported (``import imunav.assess as m`` gives the function; the old module
is ``sys.modules["imunav.assess"]``, or better :mod:`imunav.analysis.metrics`).

Old *names* (a renamed function, argument or attribute) are the other half of the table: each
is declared where it lived, through :mod:`imunav.core.deprecation` (``renamed``,
``deprecated_names``, ``callable_module``), which records them; ``tests/package/test_deprecations.py``
calls every entry of both.

May import: anything in imunav (only when an old name is imported).
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.machinery
import sys
import types
import warnings

from imunav.core.deprecation import REMOVAL

#: old module → (new modules whose names it holds, {old name: "module:new name"}).
ALIASES: dict[str, tuple[tuple[str, ...], dict[str, str]]] = {
    "imunav.errors": (("imunav.core.validation",), {}),
    "imunav.rotations": (("imunav.core.rotations",), {}),
    "imunav.units": (("imunav.core.units",), {}),
    # issue 35: the figure style moved from the ground floor into the plotting room
    "imunav.core.style": (("imunav.plotting.style",),
                          {"style": "imunav.plotting.style:thing_style"}),
    "imunav.simulate": (("imunav.sensors.simulate", "imunav.sensors.signals"),
                        {"TruthStates": "imunav.core.states:States", "G0": "imunav.core.constants:G0"}),
    "imunav.assess": (("imunav.analysis.metrics",), {}),
    "imunav.benchmarks": (("imunav.motion.catalog", "imunav.motion.quaternion_law"), {}),
    "imunav.family": (("imunav.analysis.family", "imunav.plotting"), {}),
    "imunav.montecarlo": (("imunav.analysis.montecarlo", "imunav.analysis.assessment",
                           "imunav.plotting"), {"write_json": "imunav.io.files:write_json"}),
    "imunav.realdata": (("imunav.io.realdata",), {}),
    "imunav.presets": (("imunav.sensors.presets",), {}),
    "imunav.highorder": (("imunav.strapdown.highorder",),
                         {"rotation_vectors": "imunav.strapdown.highorder:interval_quaternions"}),
    "imunav.reference": (("imunav.strapdown.reference",), {}),
    "imunav.quickstart": (("imunav.analysis.roundtrip", "imunav.plotting"),
                          {"run": "imunav.analysis.roundtrip:round_trip",
                           "QuickstartRun": "imunav.analysis.roundtrip:RoundTrip",
                           "quickstart_motion": "imunav.motion.catalog:figure_eight"}),
    # 0.3: the aids' registry (issue 35)
    "imunav.sensors.aiding": (("imunav.sensors.aids",), {}),
    "imunav.strapdown.earth": (("imunav.strapdown.rotating",), {}),
    "imunav.analysis.aided": (("imunav.analysis.aided_montecarlo",), {}),
    "imunav.estimation.performance": (("imunav.analysis.aided_covariance",), {}),
    # issue 35: one module per name (imunav.estimation.alignment is the other "alignment")
    "imunav.strapdown.alignment": (("imunav.strapdown.initial",), {}),
}


class _Loader(importlib.abc.Loader):
    def __init__(self, targets, renamed):
        self.targets, self.renamed = targets, renamed

    def create_module(self, spec):
        return None

    def exec_module(self, module):
        warnings.warn(f"{module.__name__} is deprecated and will be removed in {REMOVAL}; use "
                      f"{', '.join(self.targets)}", DeprecationWarning, stacklevel=2)
        for name in self.targets:
            m = importlib.import_module(name)
            module.__dict__.update({k: v for k, v in vars(m).items() if not k.startswith("__")})
        for old, where in self.renamed.items():
            mod, _, new = where.partition(":")
            module.__dict__[old] = getattr(importlib.import_module(mod), new)


class _Finder(importlib.abc.MetaPathFinder):
    def find_spec(self, fullname, path, target=None):
        if fullname not in ALIASES:
            return None
        return importlib.machinery.ModuleSpec(fullname, _Loader(*ALIASES[fullname]))


class _Package(types.ModuleType):
    """A package whose public names an old module path of the same name cannot shadow.

    Importing a submodule binds it as an attribute of its package; ``import imunav.assess``
    would replace the function ``imunav.assess`` by the deprecated module. Here the function
    stays (``import imunav.assess as m`` still gives the module, from ``sys.modules``)."""

    def __setattr__(self, name, value):
        old = self.__dict__.get(name)
        if (isinstance(value, types.ModuleType) and f"{self.__name__}.{name}" in ALIASES
                and old is not None and not isinstance(old, types.ModuleType)):
            return
        super().__setattr__(name, value)


def install() -> None:
    """Register the finder of the deprecated module names (once; ``import imunav`` calls it)."""
    if not any(isinstance(f, _Finder) for f in sys.meta_path):
        sys.meta_path.append(_Finder())
    for name in {k.rpartition(".")[0] for k in ALIASES}:
        if name in sys.modules and type(sys.modules[name]) is types.ModuleType:
            sys.modules[name].__class__ = _Package
