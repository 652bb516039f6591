"""The ``AIDING.toml`` side of an aid: a :class:`Key` per key of its table (unit, default,
physical range; read and checked by :meth:`Key.read`) and the :class:`TableConfig` dataclass an
aid's configuration derives from. Part of the aid contract of :mod:`imunav.sensors.aids.base`,
which re-exports every name.

May import: ``imunav.core``.
"""

from __future__ import annotations

import math
import numbers
import re
from dataclasses import dataclass

from imunav.core import units as U
from imunav.core.validation import ImunavError, show

__all__ = ["ANGLE_UNITS", "Key", "TableConfig", "check_keys"]


#: The units an angle of an ``AIDING.toml`` may be written in: those of
#: :data:`imunav.core.units.ANGLE` less ``%`` (a cross-axis coupling, not an angle of its own).
ANGLE_UNITS = {u: f for u, f in U.ANGLE.items() if u != "%"}


def _angle(text: str, name: str) -> float:
    """An angle written with its unit (``"2 deg"``) in radians, its sign kept."""
    m = re.fullmatch(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*", text)
    if not m:
        raise ImunavError(f"{name} = {text!r}: expected a number or '<number> <unit>' (an "
                          f"angle: {', '.join(ANGLE_UNITS)})")
    unit = U.normalise(m.group(2))
    if unit not in ANGLE_UNITS:
        why = " (% is for scale factors)" if unit == "%" else ""
        got = f"unit {m.group(2)!r} is not an angle unit{why}" if unit else "no unit"
        raise ImunavError(f"{name} = {text!r}: {got}; accepted: {', '.join(ANGLE_UNITS)}")
    return float(m.group(1)) * ANGLE_UNITS[unit]


def _real(x) -> bool:
    return isinstance(x, numbers.Real) and not isinstance(x, bool) and math.isfinite(x)


@dataclass(frozen=True)
class Key:
    """One key of an ``AIDING.toml`` table: its unit, default and physical range.

    Parameters
    ----------
    name : str
    unit : str
        The SI unit it is written in (``""``: a plain number).
    doc : str
        What it is (one line: the file-format page is generated from these).
    kind : {"number", "angle", "integer", "vector", "intervals", "choice", "path", "delay"}
        A finite number; an angle (a number in rad, or a string with its unit, ``"2 deg"``);
        a whole number; a list of three numbers; a list of ``[t0, t1]``; one of ``choices``;
        a file name; a signed number of seconds or ``"auto"``.
    required : bool
    default : object
        When absent (and not required).
    positive : bool
        A number must be > 0 (else ≥ 0; a vector's components may have any sign).
    hi : float, optional
        The largest physical value (a vector: of each component's magnitude).
    choices : tuple of str
    """

    name: str
    unit: str
    doc: str
    kind: str = "number"
    required: bool = False
    default: object = None
    positive: bool = True
    hi: float | None = None
    choices: tuple[str, ...] = ()

    def read(self, table: dict, where: str):
        """The key's value in ``table`` (the ``[where]`` table), checked.

        Parameters
        ----------
        table : dict
        where : str
            The table's name (for messages).

        Returns
        -------
        object
            A float, an int, a tuple, a string, or the default.

        Raises
        ------
        ImunavError
            Naming ``[where] key``, what was expected (its unit and range) and what came.
        """
        name, unit = f"[{where}] {self.name}", self.unit
        in_unit = f" ({unit})" if unit else ""
        if self.name not in table:
            if self.required:
                raise ImunavError(f"{name}{in_unit} is required")
            return self.default
        raw = table[self.name]
        if self.kind == "choice":
            if raw not in self.choices:
                raise ImunavError(f"{name} must be " + " or ".join(f'"{c}"' for c in self.choices)
                                  + f", got {show(raw)}")
            return raw
        if self.kind == "integer":
            top = "" if self.hi is None else f" and ≤ {self.hi:g}"
            if (isinstance(raw, bool) or not isinstance(raw, numbers.Integral) or raw < 1
                    or (self.hi is not None and raw > self.hi)):
                raise ImunavError(f"{name} must be a whole number of {unit} ≥ 1{top}, got "
                                  f"{show(raw)}")
            return int(raw)
        if self.kind == "vector":
            if not isinstance(raw, list) or len(raw) != 3 or not all(_real(x) for x in raw):
                raise ImunavError(f"{name} must be 3 finite numbers{in_unit}, got {show(raw)}")
            if self.hi is not None and max(abs(x) for x in raw) > self.hi:
                raise ImunavError(f"{name} must be 3 numbers within ±{self.hi:g}{in_unit} (a "
                                  f"physical {self.doc}), got {show(raw)}")
            return tuple(float(x) for x in raw)
        if self.kind == "intervals":
            return _intervals(raw, name, self.hi)
        if self.kind == "path":
            if not isinstance(raw, str) or not raw.strip() or "\x00" in raw:
                raise ImunavError(f"{name} must be a file name (a string), got {show(raw)}")
            return raw
        if self.kind == "delay":
            if raw == "auto":
                return raw
            if not _real(raw) or not abs(raw) <= 10.0:
                raise ImunavError(f'{name} must be a number of seconds within ±10 or "auto", '
                                  f"got {show(raw)}")
            return float(raw)
        v = raw
        if self.kind == "angle" and isinstance(v, str):
            v = _angle(v, name)
        if not _real(v):
            raise ImunavError(f"{name} must be a finite number{in_unit}, got {show(raw)}")
        v = float(v)
        if self.positive and not v > 0:
            raise ImunavError(f"{name} must be a positive number{in_unit}, got {show(raw)}")
        if not self.positive and v < 0:
            raise ImunavError(f"{name} must be a non-negative number{in_unit}, got {show(raw)}")
        if self.hi is not None and v > self.hi:
            lo = "(0" if self.positive else "[0"
            raise ImunavError(f"{name} must be in {lo}, {self.hi:g}]{in_unit} (a physical "
                              f"{self.doc}), got {show(raw)}")
        return v


def _intervals(raw, name: str, hi: float | None) -> tuple[tuple[float, float], ...]:
    """A list of ``[t0, t1]`` with ``0 ≤ t0 < t1``, in time order, not overlapping."""
    if not isinstance(raw, list):
        raise ImunavError(f"{name} must be a list of [t0, t1] (s), got {show(raw)}")
    if raw and all(isinstance(o, numbers.Real) for o in raw):
        hint = f": write [{show(raw)}] for one outage" if len(raw) == 2 else ""
        raise ImunavError(f"{name} must be a list of [t0, t1] (s), got {show(raw)}{hint}")
    out: list[tuple[float, float]] = []
    for i, o in enumerate(raw):
        if (not isinstance(o, list) or len(o) != 2 or not all(_real(x) for x in o)
                or not 0 <= o[0] < o[1] or (hi is not None and o[1] > hi)):
            top = "" if hi is None else f" ≤ {hi:g}"
            raise ImunavError(f"{name}[{i}] must be [t0, t1] with 0 ≤ t0 < t1{top} (s), got "
                              f"{show(o)}")
        if out and o[0] <= out[-1][1]:
            raise ImunavError(f"{name}[{i}] = {show(o)} must start after {name.split()[-1]}"
                              f"[{i - 1}] ends ({out[-1][1]:g} s): list them in time order, "
                              "without overlaps")
        out.append((float(o[0]), float(o[1])))
    return tuple(out)


def check_keys(table, where: str, allowed) -> dict:
    """``table`` as a dict holding only ``allowed`` keys.

    Parameters
    ----------
    table : object
    where : str
        The table's name.
    allowed : iterable of str

    Returns
    -------
    dict

    Raises
    ------
    ImunavError
        If it is not a table or holds another key.
    """
    if not isinstance(table, dict):
        raise ImunavError(f"[{where}] must be a table")
    allowed = tuple(allowed)
    bad = sorted(set(table) - set(allowed))
    if bad:
        raise ImunavError(f"unknown key(s) in [{where}]: {', '.join(bad)}; expected "
                          f"{', '.join(allowed)}")
    return table


class TableConfig:
    """A table of ``AIDING.toml`` as a frozen dataclass read from its :class:`Key` list.

    Subclasses are dataclasses whose fields are, in order, the keys of :attr:`FIELDS`, and set
    :attr:`TABLE`; :meth:`from_dict` reads and checks every key, then :meth:`checked` checks
    what involves several keys.
    """

    TABLE = ""
    FIELDS: tuple[Key, ...] = ()
    #: The table's keys, in order (set from :attr:`FIELDS`).
    KEYS: tuple[str, ...] = ()

    def __init_subclass__(cls, **kw):
        super().__init_subclass__(**kw)
        cls.KEYS = tuple(k.name for k in cls.FIELDS)

    @classmethod
    def from_dict(cls, d: dict):
        """Parse the table.

        Parameters
        ----------
        d : dict

        Returns
        -------
        TableConfig

        Raises
        ------
        ImunavError
            For an unknown key, a missing required key, or a value out of its type or range
            (the message names ``[table] key``).
        """
        d = check_keys(d, cls.TABLE, cls.KEYS)
        return cls(*(k.read(d, cls.TABLE) for k in cls.FIELDS)).checked()

    def checked(self):
        """What involves several keys (none by default).

        Returns
        -------
        TableConfig
            Itself (or a normalised copy).
        """
        return self
