"""No output may be an input: checks made on every command's paths before anything is written.

An output is refused when it is an input file under another name — the same resolved path
(``./a.csv``, ``a.csv``, a symbolic link) or the same file (a hard link: same device and
inode) — including any file inside an input folder (a recording); when two outputs are one
file; when it is a folder; or when its folder does not exist.

May import: ``imunav.core``.
"""

from __future__ import annotations

import os
from pathlib import Path

from imunav.core.validation import ImunavError


def _identity(p: Path) -> tuple[int, int] | None:
    try:
        st = os.stat(p)
    except OSError:
        return None
    return st.st_dev, st.st_ino


def input_files(paths) -> list[Path]:
    """The files behind ``paths`` (None entries skipped): a file itself, a folder's every file."""
    out = []
    for p in paths:
        if p is None:
            continue
        p = Path(p)
        if p.is_dir():
            out.extend(q for q in p.rglob("*") if q.is_file())
        elif p.exists():
            out.append(p)
    return out


def _named(option: str, path: Path) -> str:
    """``"--out a.csv"``: the option and its path, once — an option that already names its
    file (``"--aiding-out q/nhc.csv"``, one file of a folder option) is left as it is."""
    return option if option.endswith(f" {path}") else f"{option} {path}"


def check_outputs(outputs: dict[str, str | Path | None], inputs) -> dict[str, Path]:
    """Check every output path against every input and each other; return them as Paths.

    ``outputs`` maps the option that names an output (``"--out"``) to its path (None: not
    requested); ``inputs`` are the input files and folders. An option may name its file
    itself (``"--aiding-out q/nhc.csv"``: one file of a folder option); messages then name the
    path once.
    """
    ins = [(q.resolve(), _identity(q), q) for q in input_files(inputs)]
    seen: list[tuple[Path, tuple | None, str]] = []
    checked = {}
    for option, out in outputs.items():
        if out is None:
            continue
        out = Path(out)
        name = _named(option, out)
        if out.is_dir():
            raise ImunavError(f"{name} is a folder; give a file name")
        if not out.resolve().parent.is_dir():
            raise ImunavError(f"{name}: the folder {out.resolve().parent} does not exist")
        rp, ident = out.resolve(), _identity(out)
        for ip, iid, orig in ins:
            if rp == ip or (ident is not None and ident == iid):
                what = "" if str(orig) == str(out) else f" {orig}"       # the path once
                raise ImunavError(f"{name} would overwrite the input file{what}; choose another "
                                  "output name")
        for sp, sid, other in seen:
            if rp == sp or (ident is not None and ident == sid):
                raise ImunavError(f"{name} is the same file as {other}; outputs must differ")
        seen.append((rp, ident, option))
        checked[option] = out
    return checked
