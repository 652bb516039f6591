"""Sync and execute notebooks in place (``make notebooks``; ``make notebooks NB="00 05"``).

``python notebooks/run.py [NN …]`` — for each notebook whose name starts with one of ``NN`` (all
by default): ``jupytext --update`` its source ``src/NN_*.py`` into the ``.ipynb``, then execute
every cell in a fresh kernel with the inline backend (nbclient, one cell at a time: the next
request is sent only when the previous one has replied) and write it back with its outputs and
figures. Before the first cell the kernel installs the figure check
(:func:`imunav.plotting.install_figure_check`), so a figure with a defect fails the run.

Progress: one line per code cell (its number, time and first line) and per notebook.

A stalled kernel — one that has not started a request it was sent (no ``busy`` status for it
within ``--stall`` seconds while nothing else runs) — is *nudged* with a ``kernel_info`` request,
which makes the kernel read its socket again; the run says so on its own line (``STALL``) and in
the summary (``N stalls``), and fails if the nudge does not help. There is no silent retry.
The last line is ``notebooks: N executed, F failed, S stalls (T s)``; the exit status is 1 if
any notebook failed.
"""

from __future__ import annotations

import argparse
import asyncio
import re
import subprocess
import sys
import time
from pathlib import Path

import nbformat
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError, CellTimeoutError, DeadKernelError
from nbclient.util import run_sync

HERE = Path(__file__).resolve().parent
BIN = Path(sys.executable).parent
KERNEL_SETUP = "from imunav.core.style import install_figure_check as _f; _f({mode!r}); del _f"
_ANSI = re.compile(r"\x1b\[[0-9;]*m")


class Runner(NotebookClient):
    """nbclient, with progress, the figure check and the stall watchdog."""

    stall_s: float = 30.0

    def __init__(self, nb, name: str, **kw):
        super().__init__(nb, **kw)
        self.name = name
        self.stalls = 0
        self.figure_defects = 0
        self.n_code = sum(1 for c in nb.cells if c.cell_type == "code" and c.source.strip())
        self.k = 0
        self._started = False
        self._watch = None
        self._t_cell = time.perf_counter()
        self.on_cell_complete = self._after_send        # runs right after a request is sent

    # the cell's request has been sent: watch for its first message
    async def _after_send(self, cell, cell_index):
        self._started, self._t_cell = False, time.perf_counter()
        self._watch = asyncio.ensure_future(self._watchdog(cell_index))

    async def _watchdog(self, cell_index):
        for nudge in range(2):
            t0 = time.perf_counter()
            while time.perf_counter() - t0 < self.stall_s:
                if self._started:
                    return
                await asyncio.sleep(0.5)
            if nudge == 0:
                self.stalls += 1
                print(f"  STALL {self.name} cell {self.k}/{self.n_code}: no sign of execution "
                      f"{self.stall_s:.0f} s after its request; nudging the kernel with a "
                      "kernel_info request", flush=True)
                self.kc.kernel_info()
        print(f"  STALL {self.name} cell {self.k}/{self.n_code}: the nudge did not wake the "
              "kernel", flush=True)

    def process_message(self, msg, cell, cell_index):
        self._started = True
        return super().process_message(msg, cell, cell_index)

    async def async_execute_cell(self, cell, cell_index, execution_count=None,
                                 store_history=True):
        if cell.cell_type != "code" or not cell.source.strip():
            return cell
        self.k += 1
        try:
            out = await super().async_execute_cell(cell, cell_index, execution_count,
                                                   store_history)
        finally:
            if self._watch is not None:
                self._watch.cancel()
        for o in cell.outputs:
            if o.output_type == "stream" and "figure check:" in o.text:
                for line in o.text.splitlines():
                    if line.startswith("figure check:"):
                        self.figure_defects += 1
                        print(f"  {self.name} [{self.k:2d}] {line}", flush=True)
        first = cell.source.strip().splitlines()[0][:60]
        print(f"  {self.name} [{self.k:2d}/{self.n_code}] {time.perf_counter() - self._t_cell:6.1f} s"
              f"  {first}", flush=True)
        return out

    execute_cell = run_sync(async_execute_cell)


def _install_check(client: Runner, mode: str) -> None:
    reply = client.wait_for_reply(client.kc.execute(KERNEL_SETUP.format(mode=mode),
                                                    store_history=False))
    if reply is None or reply["content"]["status"] != "ok":
        raise RuntimeError(f"figure check not installed: {reply and reply['content'].get('evalue')}")


def run_one(path: Path, timeout: float, stall: float, sync: bool = True, write: bool = True,
            check: str = "raise") -> tuple[bool, int]:
    src = path.parent / "src" / f"{path.stem}.py"
    if sync:
        subprocess.run([str(BIN / "jupytext"), "--quiet", "--update", "--to", "ipynb", "-o",
                        str(path), str(src)], check=True)
    nb = nbformat.read(path, as_version=4)
    client = Runner(nb, path.stem, timeout=timeout, kernel_name="python3",
                    resources={"metadata": {"path": str(path.parent)}})
    client.stall_s = stall
    t0 = time.perf_counter()
    ok = True
    try:
        with client.setup_kernel():
            _install_check(client, check)
            for i, cell in enumerate(nb.cells):
                client.execute_cell(cell, i)
            client.set_widgets_metadata()
    except (CellExecutionError, CellTimeoutError, DeadKernelError) as exc:
        ok = False
        print(f"FAIL {path.stem}: {type(exc).__name__}: "
              f"{_ANSI.sub('', str(exc)).strip()[-1500:]}", flush=True)
    if ok and write:
        nbformat.write(nb, path)
    print(f"{'done' if ok else 'FAILED'} {path.stem}: {client.k} cells in "
          f"{time.perf_counter() - t0:.0f} s" + (f", {client.stalls} stall(s)" if client.stalls
                                                 else ""), flush=True)
    return ok, client.stalls


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("only", nargs="*", help="notebook name prefixes (00 05 …); default all")
    ap.add_argument("--timeout", type=float, default=600, help="seconds per cell (600)")
    ap.add_argument("--stall", type=float, default=30,
                    help="seconds without any sign of a sent request's execution (30)")
    ap.add_argument("--figure-check", choices=("raise", "warn"), default="raise",
                    help="a figure defect fails the cell (raise) or is printed (warn)")
    ap.add_argument("--dir", type=Path, default=HERE, help="the notebooks' folder")
    ap.add_argument("--no-sync", action="store_true", help="do not sync from src/*.py first")
    ap.add_argument("--no-write", action="store_true", help="execute, but leave the files")
    args = ap.parse_args(argv)
    nbs = sorted(args.dir.glob("[0-9][0-9]_*.ipynb"))
    if args.only:
        nbs = [p for p in nbs if any(p.name.startswith(o) for o in args.only)]
        if not nbs:
            print(f"run.py: error: no notebook starts with {' or '.join(args.only)}",
                  file=sys.stderr)
            return 2
    t0 = time.perf_counter()
    failed = stalls = 0
    for p in nbs:
        print(f"{p.stem}: executing", flush=True)
        ok, s = run_one(p, args.timeout, args.stall, not args.no_sync, not args.no_write,
                        args.figure_check)
        failed += not ok
        stalls += s
    print(f"notebooks: {len(nbs) - failed} executed, {failed} failed, {stalls} stalls "
          f"({time.perf_counter() - t0:.0f} s)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
