"""Old names kept for one release (issue 35): a renamed keyword argument, a renamed module
attribute, a renamed function that a module of the same name now answers for.

Each keeps working and issues a :class:`DeprecationWarning` naming the new spelling; each is
recorded here (:data:`RENAMED_ARGUMENTS`, :data:`RENAMED_NAMES`), so that one test calls every
old name (``tests/package/test_deprecations.py``). Old *module* paths are the other half of the table:
:data:`imunav._aliases.ALIASES`. Remove both in imunav 0.3 (with the alias table).

May import: nothing from imunav (layer 0).
"""

from __future__ import annotations

import functools
import sys
import types
import warnings
from collections.abc import Callable

__all__ = ["RENAMED_ARGUMENTS", "RENAMED_NAMES", "callable_module", "deprecated_names",
           "renamed"]

#: Every function whose keyword arguments were renamed: ``(function, {old: new})``.
RENAMED_ARGUMENTS: list[tuple[Callable, dict[str, str]]] = []
#: Every renamed module attribute: ``"module.old"`` → ``(module, old, dotted path of the new
#: name, the object)``; a module that answers calls for its former function: ``"module()"``.
RENAMED_NAMES: dict[str, tuple[str, str, str, object]] = {}

#: When the old names go.
REMOVAL = "imunav 0.3"


def renamed(**old_to_new: str) -> Callable[[Callable], Callable]:
    """Accept the old keyword names of a function's arguments for one release, with a warning.

    ``@renamed(model="imu", output="kind")`` above ``def f(motion, imu, …, kind=…)``: a call
    ``f(m, model=x)`` runs as ``f(m, imu=x)`` and warns; positional calls are untouched.

    Parameters
    ----------
    **old_to_new : str
        Each old keyword and the argument it is now.

    Returns
    -------
    callable
        The decorator. The wrapped function keeps its name, docstring and signature (the new
        names) and calls its ``__wrapped__``.

    Raises
    ------
    TypeError
        At a call that gives both an old name and its new one.
    """
    def decorate(func: Callable) -> Callable:
        @functools.wraps(func)
        def wrapper(*args, **kwargs):
            for old, new in old_to_new.items():
                if old in kwargs:
                    if new in kwargs:
                        raise TypeError(f"{func.__qualname__}() got both {old!r} (its former "
                                        f"name) and {new!r}: give {new!r} only")
                    warnings.warn(f"{func.__qualname__}(): the argument {old!r} is now {new!r}; "
                                  f"{old!r} will stop working in {REMOVAL}",
                                  DeprecationWarning, stacklevel=2)
                    kwargs[new] = kwargs.pop(old)
            return wrapper.__wrapped__(*args, **kwargs)

        wrapper.__renamed__ = dict(old_to_new)
        RENAMED_ARGUMENTS.append((wrapper, dict(old_to_new)))
        return wrapper

    return decorate


def deprecated_names(module: str, names: dict[str, tuple[object, str]],
                     advice: dict[str, str] | None = None) -> Callable[[str], object]:
    """A module ``__getattr__`` that answers the module's former attribute names with a warning.

    ``__getattr__ = deprecated_names(__name__, {"NavResult": (States, "imunav.States")})``:
    ``module.NavResult`` and ``from module import NavResult`` return ``States`` and warn.

    Parameters
    ----------
    module : str
        The module's ``__name__``.
    names : dict
        ``{old name: (the object it now is, the dotted path of its new name)}``.
    advice : dict, optional
        ``{old name: text}`` added to the warning (another way to the same thing).

    Returns
    -------
    callable
        The module's ``__getattr__`` (it raises AttributeError for any other name).
    """
    advice = advice or {}
    for old, (value, new) in names.items():
        RENAMED_NAMES[f"{module}.{old}"] = (module, old, new, value)

    def __getattr__(name: str):
        if name in names:
            value, new = names[name]
            more = f" ({advice[name]})" if name in advice else ""
            warnings.warn(f"{module}.{name} is deprecated and will be removed in {REMOVAL}; "
                          f"use {new}{more}", DeprecationWarning, stacklevel=2)
            return value
        raise AttributeError(f"module {module!r} has no attribute {name!r}")

    return __getattr__


def callable_module(module: str, old: str, func: Callable, new: str) -> None:
    """Let a module be called as the function of its own name that it used to hold (and that
    hid it from ``import``), with a warning: ``imunav.estimation.error_model(traj)`` runs
    ``frame_model(traj)``.

    The module stays a module (its attributes, ``import``, ``from … import`` are untouched); only
    calling it is new, by the module's ``__class__`` (the one supported way, PEP 549's
    alternative: ``types.ModuleType`` subclass).

    Parameters
    ----------
    module : str
        The module's ``__name__`` (already in ``sys.modules``).
    old : str
        The former function's name, as users spelt the call.
    func : callable
        What it is now.
    new : str
        The dotted path of its new name.
    """
    RENAMED_NAMES[f"{module}()"] = (module, "()", new, func)

    class _Callable(types.ModuleType):
        def __call__(self, *args, **kwargs):
            warnings.warn(f"calling the module {module} (the former function {old}) is "
                          f"deprecated and will stop working in {REMOVAL}; use {new}",
                          DeprecationWarning, stacklevel=2)
            return func(*args, **kwargs)

    sys.modules[module].__class__ = _Callable
