"""How much memory and disk this machine has, and refusals of work that cannot fit.

A run that would need more memory than is available (or write more than the disk holds) is
refused before any work starts, with the estimate, instead of failing late with a traceback.

May import: ``imunav.core.validation``.
"""

from __future__ import annotations

import os
import shutil
import stat
from pathlib import Path

from imunav.core.validation import ImunavError

#: Fraction of the available memory a single run may plan to use.
MEMORY_FRACTION = 0.8


def available_memory() -> int:
    """Bytes of memory available to new allocations (``MemAvailable`` on Linux)."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        return os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return 1 << 62                                     # unknown: do not refuse


def human(nbytes: float) -> str:
    """``2.3 GB``-style size."""
    for unit in ("B", "kB", "MB", "GB", "TB", "PB"):
        if abs(nbytes) < 1000 or unit == "PB":
            return f"{nbytes:.3g} {unit}"
        nbytes /= 1000
    return f"{nbytes:.3g} PB"


def check_memory(nbytes: float, what: str, hint: str = "") -> None:
    """Raise if ``what`` would need more than :data:`MEMORY_FRACTION` of the available memory."""
    avail = available_memory()
    if nbytes > MEMORY_FRACTION * avail:
        raise ImunavError(f"{what} would need about {human(nbytes)} of memory; "
                          f"{human(avail)} is available{'; ' + hint if hint else ''}")


def check_disk(path: str | Path, nbytes: float, what: str) -> None:
    """Raise if writing about ``nbytes`` next to ``path`` would not fit on its disk (a path
    that is not a regular file — a device, a FIFO — has no disk to fill: not checked)."""
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):
            return
    except OSError:
        pass                                               # a new file
    folder = Path(path).resolve().parent
    try:
        free = shutil.disk_usage(folder).free
    except OSError:
        return
    if nbytes > free:
        raise ImunavError(f"{what} would write about {human(nbytes)} to {path}; the disk has "
                          f"{human(free)} free")
