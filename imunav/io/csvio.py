"""Numeric CSV files with an exact header, read and written in chunks, fast and exactly.

Engine: Apache Arrow's C++ CSV reader and writer (``pyarrow.csv``), because it parses and
formats doubles exactly (correctly rounded parsing; the shortest decimal that reads back as the
same double), streams block by block (memory bounded by the block, not the file), and runs
outside the GIL (formatting is done in two threads while the caller computes). pandas would add
a layer over the same engine for no gain here; numpy's ``savetxt``/``loadtxt`` were 5–6 µs a row.

Writing goes to a temporary file in the destination folder, renamed over the destination only
when everything is written (:class:`CsvWriter`): an interrupted run leaves no half file. The
rename is for regular files only (:class:`OutputFile`): a symbolic link is written through to
its target (the link stays), a character device or a FIFO (``/dev/null``, a pipe) is written
directly, anything else is refused — a special file is never replaced.
Reading reports a bad value with its line and column; pyarrow does not give line numbers, so
the file is rescanned with the ``csv`` module on that (error) path only.

May import: ``imunav.core``.
"""

from __future__ import annotations

import csv
import fcntl
import os
import stat
import tempfile
from collections import deque
from collections.abc import Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

from imunav.core.validation import ImunavError

#: Bytes per block of the streaming reader.
BLOCK = 1 << 22
#: Files larger than this (bytes) are read with a progress bar (tqdm, on stderr).
PROGRESS_BYTES = 64 << 20


def read_header(path: Path, what: str) -> tuple[str, ...]:
    """The first line of ``path`` split at commas and stripped (UTF-8, a BOM allowed)."""
    if not path.exists():
        raise ImunavError(f"{what} file not found: {path}")
    if not path.is_file():
        raise ImunavError(f"{what} file {path} is not a file")
    with path.open("rb") as fh:
        first = fh.readline(1 << 16)
    if not first.strip():
        raise ImunavError(f"{what} file {path} is empty or has no header line")
    try:
        text = first.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise ImunavError(f"{path}, line 1: not UTF-8 text (byte {exc.start})") from None
    return tuple(h.strip() for h in text.rstrip("\r\n").split(","))


def _checked_rows(path: Path, header: Sequence[str]) -> Iterator[tuple[int, np.ndarray]]:
    """``(line number, values)`` of each data row of ``path`` (after the header line; blank
    lines skipped), read line by line; the first undecodable line, wrong column count,
    non-number or NaN/inf raises :class:`ImunavError` naming its line and column."""
    with path.open("rb") as fh:
        fh.readline()
        for line_no, raw in enumerate(fh, start=2):
            try:
                text = raw.decode("utf-8")
            except UnicodeDecodeError as exc:
                raise ImunavError(f"{path}, line {line_no}: not UTF-8 text (byte {exc.start})"
                                  ) from None
            if not text.strip():
                continue
            cells = next(csv.reader([text]))
            if len(cells) != len(header):
                raise ImunavError(f"{path}, line {line_no}: expected {len(header)} columns "
                                  f"({','.join(header)}), got {len(cells)}")
            row = np.empty(len(header))
            for j, (name, c) in enumerate(zip(header, cells, strict=True)):
                try:
                    row[j] = float(c)
                except ValueError:
                    raise ImunavError(f"{path}, line {line_no}, column '{name}': {c.strip()!r} "
                                      "is not a number") from None
                if not np.isfinite(row[j]):
                    raise ImunavError(f"{path}, line {line_no}, column '{name}': NaN or inf")
            yield line_no, row


def _locate(path: Path, header: Sequence[str], bad_row: int | None = None) -> str:
    """Error path only: rescan ``path`` to say where the first problem is (line and column),
    or where data row ``bad_row`` (0-based, blank lines skipped) is."""
    try:
        for row, (line_no, _) in enumerate(_checked_rows(path, header)):
            if row == bad_row:
                return f"{path}, line {line_no}: bad value"
    except ImunavError as exc:
        return str(exc)
    return f"{path}: unreadable CSV"


def read_chunks(path: str | Path, header: Sequence[str], what: str,
                max_rows: int | None = None) -> Iterator[np.ndarray]:
    """Data rows of ``path`` (whose first line is ``header``) as float64 arrays (n, columns),
    block by block; every value must be a finite number. ``max_rows`` stops early. A file of
    more than :data:`PROGRESS_BYTES` shows a progress bar in bytes (tqdm, on stderr)."""
    path = Path(path)
    size = path.stat().st_size if path.is_file() else 0
    if size <= PROGRESS_BYTES:
        yield from _chunks(path, header, max_rows, None)
        return
    from tqdm.auto import tqdm

    with tqdm(total=size, desc=f"reading {path.name}", unit="B", unit_scale=True,
              mininterval=1.0, leave=False) as bar:
        yield from _chunks(path, header, max_rows, bar)


def _chunks(path: Path, header: Sequence[str], max_rows: int | None, bar
            ) -> Iterator[np.ndarray]:
    import pyarrow as pa
    import pyarrow.csv as pc

    names = list(header)
    try:
        reader = pc.open_csv(
            path,
            read_options=pc.ReadOptions(skip_rows=1, column_names=names, block_size=BLOCK,
                                        use_threads=True),
            parse_options=pc.ParseOptions(newlines_in_values=False, ignore_empty_lines=True),
            convert_options=pc.ConvertOptions(column_types={c: pa.float64() for c in names},
                                              strings_can_be_null=False))
    except pa.ArrowInvalid:
        raise ImunavError(_locate(path, header)) from None
    seen = 0
    while True:
        try:
            batch = reader.read_next_batch()
        except StopIteration:
            break
        except pa.ArrowInvalid:
            raise ImunavError(_locate(path, header)) from None
        if bar is not None:
            bar.update(min(BLOCK, bar.total - bar.n))   # a batch is one block of the file
        if batch.num_rows == 0:
            continue
        data = np.column_stack([batch.column(i).to_numpy(zero_copy_only=False)
                                for i in range(len(names))]).astype(np.float64, copy=False)
        ok = np.isfinite(data)
        if not ok.all():
            r = int(np.argmin(ok.all(axis=1)))
            raise ImunavError(_locate(path, header, seen + r))
        if max_rows is not None and seen + len(data) >= max_rows:
            yield data[: max_rows - seen]
            return
        seen += len(data)
        yield data


def first_row(path: str | Path, header: Sequence[str], what: str) -> np.ndarray | None:
    """The first data row of ``path`` (after the header line), or None if there is none; the
    rest of the file is not read."""
    for _, row in _checked_rows(Path(path), header):
        return row
    return None


def _format(columns: Sequence[np.ndarray]) -> bytes:
    """Rows of the given columns as CSV text (no header), every double exactly."""
    import io

    import pyarrow as pa
    import pyarrow.csv as pc

    table = pa.table({str(i): np.ascontiguousarray(c, dtype=np.float64)
                      for i, c in enumerate(columns)})
    buf = io.BytesIO()
    pc.write_csv(table, buf, write_options=pc.WriteOptions(include_header=False,
                                                           quoting_style="none"))
    return buf.getvalue()


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def output_kind(path: str | Path) -> str:
    """What an output path is: ``"file"`` (a regular file, possibly behind symbolic links, or
    nothing yet), ``"stream"`` (a character device or a FIFO, written through) or
    ``"other"`` (a block device, a socket: refused).

    Parameters
    ----------
    path : str or Path

    Returns
    -------
    str
    """
    try:
        mode = os.stat(path).st_mode                      # through every link
    except FileNotFoundError:
        return "file"                                      # new (or a dangling link's target)
    if stat.S_ISREG(mode):
        return "file"
    if stat.S_ISCHR(mode) or stat.S_ISFIFO(mode):
        return "stream"
    return "other"


class OutputFile:
    """An output opened for writing bytes, committed only when complete.

    A regular file (new, existing, or the target of symbolic links) is written to a temporary
    file in its folder, renamed over it by :meth:`commit` (with the existing file's permission
    bits, or a new file's); :meth:`abort` removes the temporary file. A character device or a
    FIFO is written through (a FIFO only if a reader has it open); a block device or a socket
    is refused. A special file or a link is never replaced.

    Parameters
    ----------
    path : str or Path
    what : str
        How error messages name it (the option, say).

    Raises
    ------
    ImunavError
        For a path that cannot be written this way.
    """

    def __init__(self, path: str | Path, what: str | None = None):
        self.path = Path(path)
        self.what = f"{what} {self.path}" if what else str(self.path)
        kind = output_kind(self.path)
        self.stream = kind == "stream"
        self.tmp = None
        if kind == "other":
            raise ImunavError(f"{self.what} is a special file (not a regular file, a character "
                              "device or a FIFO); give a file name")
        if self.stream:
            flags = os.O_WRONLY | (os.O_NONBLOCK if stat.S_ISFIFO(os.stat(self.path).st_mode)
                                   else 0)
            try:
                fd = os.open(self.path, flags)
            except OSError as exc:
                why = "a FIFO no process reads" if exc.errno == 6 else (exc.strerror or exc)
                raise ImunavError(f"cannot write {self.what} ({why})") from None
            fcntl.fcntl(fd, fcntl.F_SETFL, fcntl.fcntl(fd, fcntl.F_GETFL) & ~os.O_NONBLOCK)
            self.fh = os.fdopen(fd, "wb")
            return
        self.target = Path(os.path.realpath(self.path))
        try:
            self.mode = stat.S_IMODE(os.stat(self.target).st_mode)
        except FileNotFoundError:
            self.mode = 0o666 & ~_umask()                   # as an ordinary new file would be
        fd, tmp = tempfile.mkstemp(prefix=f".{self.target.name}.", suffix=".imunav-tmp",
                                   dir=self.target.parent)
        self.tmp = Path(tmp)
        self.fh = os.fdopen(fd, "wb")

    def write(self, data: bytes) -> None:
        """Write ``data`` (bytes)."""
        self.fh.write(data)

    def commit(self) -> None:
        """Finish: flush and close; a regular file is renamed into place.

        Raises
        ------
        ImunavError
            If the data could not be written (a full disk or device).
        """
        try:
            self.fh.close()
            if self.tmp is not None:
                os.chmod(self.tmp, self.mode)
                os.replace(self.tmp, self.target)
        except OSError as exc:
            self.abort()
            raise ImunavError(f"could not write {self.what} ({exc.strerror or exc})") from None

    def abort(self) -> None:
        """Give up: close, and remove the temporary file (nothing replaced)."""
        try:
            self.fh.close()
        except OSError:
            pass
        if self.tmp is not None:
            self.tmp.unlink(missing_ok=True)


def atomic_write_text(path: str | Path, text: str) -> None:
    """Write ``text`` to ``path`` as :class:`OutputFile` does (a regular file through a
    temporary file renamed at the end; a device or FIFO directly)."""
    out = OutputFile(path)
    try:
        out.write(text.encode())
    except BaseException:
        out.abort()
        raise
    out.commit()


class CsvWriter:
    """Write a CSV with an exact header, chunk by chunk.

    ``write(columns)`` takes 1-D and 2-D arrays of equal length (2-D arrays give one column per
    component); rows are formatted in two threads while the caller goes on, and written in
    order. The data go to a temporary file next to ``path``, renamed to ``path`` by
    :meth:`close`; :meth:`abort` (or leaving the ``with`` block by an exception) removes it.
    """

    def __init__(self, path: str | Path, header: Sequence[str]):
        self.path = Path(path)
        self.out = OutputFile(self.path)
        self.fh = self.out
        self.fh.write((",".join(header) + "\n").encode())
        self.width = len(header)
        self.pool = ThreadPoolExecutor(2)
        self.pending: deque = deque()
        self.rows = 0

    def write(self, columns: Sequence[np.ndarray]) -> None:
        """Queue the next rows for formatting and writing.

        Parameters
        ----------
        columns : sequence of ndarray
            1-D arrays (one column each) and 2-D arrays (one column per component), all of
            the same length, as many columns as the header in all.

        Raises
        ------
        ValueError
            If the columns do not add up to the header's width.
        """
        cols = []
        for c in columns:
            c = np.asarray(c, dtype=np.float64)
            cols.extend([c] if c.ndim == 1 else [c[:, j] for j in range(c.shape[1])])
        if len(cols) != self.width:
            raise ValueError(f"{len(cols)} columns for a header of {self.width}")
        n = len(cols[0])
        for lo in range(0, n, 1 << 15):                   # pieces the two threads can share
            self.pending.append(self.pool.submit(_format, [c[lo:lo + (1 << 15)] for c in cols]))
        self.rows += n
        while self.pending and (self.pending[0].done() or len(self.pending) > 8):
            self.fh.write(self.pending.popleft().result())

    def close(self) -> None:
        """Write what is pending and rename the temporary file to ``path``.

        Raises
        ------
        OSError
            If the file cannot be written or renamed (the temporary file is removed).
        """
        try:
            while self.pending:
                self.fh.write(self.pending.popleft().result())
            self.pool.shutdown()
            self.out.commit()
        except BaseException:
            self.abort()
            raise

    def abort(self) -> None:
        """Drop the pending rows and remove the temporary file: ``path`` is left untouched."""
        for f in self.pending:
            f.cancel()
        self.pending.clear()
        self.pool.shutdown(wait=True, cancel_futures=True)
        self.out.abort()

    def __enter__(self) -> CsvWriter:
        return self

    def __exit__(self, exc_type, exc, tb) -> bool:
        if exc_type is None:
            self.close()
        else:
            self.abort()
        return False
