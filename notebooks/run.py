"""Sync and execute notebooks in place (``make notebooks``; ``make notebooks NB="00 05"``).

``python notebooks/run.py [NN …]`` — for each notebook whose name starts with one of ``NN`` (all
by default): ``jupytext --update`` its source ``src/NN_*.py`` into the ``.ipynb``, then execute
every cell in a fresh kernel with the inline backend (nbclient, one cell at a time: the next
request is sent only when the previous one has replied) and write it back with its outputs and
figures. Before the first cell the kernel installs the figure check
(:func:`imunav.plotting.install_figure_check`), so a figure with a defect fails the run.

Progress: one line per code cell (its number, time and first line) and per notebook.

**The stall, and why it cannot happen here.** nbclient waits for a cell's reply with one
``await socket.poll(timeout)`` on the asyncio shell socket (and for its outputs with a poll without
a timeout on the iopub socket). A zmq socket's file descriptor is edge-triggered, and now and then
the wake-up of such a poll is lost although the message has arrived — most often in cells with
ipywidgets, whose Output-widget mimic sends comm messages on the same shell socket while the
reply is awaited (jupyter/nbclient#312). Both processes then sit idle: "an idle kernel with
cells pending", until the poll's timeout (600 s here) finds the message that was there all
along — we measured exactly that on notebook 04's interact cell (600.0 s, then it went on). So
this runner never waits on one long poll: every wait is cut into 1 s slices, each of which
ends with a direct check of the socket, so a lost wake-up costs at most a second. Each one
recovered so (a message seen more than 0.2 s after it was sent while we waited) is counted and
reported (``lost wake-ups``), never hidden; there is no retry.

**Byte-stable output.** Run twice on one machine, a notebook is written back identical to the
byte (so ``make reproduce`` on a fresh clone leaves ``git status`` clean): :func:`normalise`
removes what changes from run to run although the computation does not — each cell's
execution timestamps (``metadata.execution``, not recorded either); where the kernel happened
to cut a printed stream (consecutive stream outputs are joined); the random ids ipywidgets
gives its models, renamed ``sha256(notebook, k)`` by their order of first appearance (the
cells' outputs, then the models they refer to, then the rest by content) the same in the views
and in the stored widget state, so the stored widgets still render; the random element ids of
an HTML or SVG output (matplotlib's jshtml animation, notebook 04), renamed likewise. Printed
timings are a notebook's own business (notebook 05 prints a checked bound, not its seconds).

The last line is ``notebooks: N executed, F failed, W lost wake-ups recovered (T s)``; the exit status is 1 if
any notebook failed.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import re
import subprocess
import sys
import time
from pathlib import Path
from queue import Empty

import nbformat
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError, CellTimeoutError, DeadKernelError
from nbclient.util import run_sync

HERE = Path(__file__).resolve().parent
BIN = Path(sys.executable).parent
KERNEL_SETUP = "from imunav.plotting.style import install_figure_check as _f; _f({mode!r}); del _f"
_ANSI = re.compile(r"\x1b\[[0-9;]*m")


WIDGET_VIEW = "application/vnd.jupyter.widget-view+json"
WIDGET_STATE = "application/vnd.jupyter.widget-state+json"
REF = "IPY_MODEL_"   # how one widget model's state refers to another (@jupyter-widgets/schema)


def _strings(obj):
    """Every string of a JSON value, in a fixed order (dict keys sorted)."""
    if isinstance(obj, str):
        yield obj
    elif isinstance(obj, dict):
        for k in sorted(obj):
            yield from _strings(obj[k])
    elif isinstance(obj, list):
        for v in obj:
            yield from _strings(v)


def _model_id(s: str, known) -> str | None:
    """The model id that string ``s`` names (the id itself or an ``IPY_MODEL_`` reference)."""
    if s in known:
        return s
    if s.startswith(REF) and s[len(REF):] in known:
        return s[len(REF):]
    return None


def _rename(obj, new: dict):
    if isinstance(obj, str):
        if obj in new:
            return new[obj]
        if obj.startswith(REF) and obj[len(REF):] in new:
            return REF + new[obj[len(REF):]]
        return obj
    if isinstance(obj, dict):
        return {k: _rename(v, new) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_rename(v, new) for v in obj]
    return obj


def _new_id(name: str, kind: str, k: int) -> str:
    """The k-th id of its kind in notebook ``name``: 32 hex digits, shaped as a uuid4's."""
    h = hashlib.sha256(f"{name}/{kind}{k}".encode()).hexdigest()[:32]
    return h[:12] + "4" + h[13:16] + "8" + h[17:]


def normalise(nb, name: str):
    """Make executed notebook ``nb`` (named ``name``) byte-stable from run to run, in place.

    Drops every cell's ``metadata.execution`` (kernel timestamps), joins consecutive pieces of
    one stream (:func:`coalesce_streams`: where the kernel cut its stdout depends on timing),
    renames the widget models (:func:`renumber_widgets`) and the random element ids of HTML and
    SVG outputs (:func:`renumber_markup_ids`). Idempotent; everything else is left as it is. Returns ``nb``.
    """
    for cell in nb.cells:
        cell.get("metadata", {}).pop("execution", None)
        if "outputs" in cell:
            cell["outputs"] = coalesce_streams(cell["outputs"])
    for model in (nb.get("metadata", {}).get("widgets", {}).get(WIDGET_STATE, {})
                  .get("state", {}).values()):
        if isinstance(model.get("state", {}).get("outputs"), list):       # an Output widget's
            model["state"]["outputs"] = coalesce_streams(model["state"]["outputs"])
    renumber_widgets(nb, name)
    renumber_markup_ids(nb, name)
    return nb


def coalesce_streams(outputs: list) -> list:
    """Consecutive stream outputs of one name (stdout, stderr) as one: the kernel sends a
    printed line in one piece or two depending on when its output thread flushed (notebook 09
    stored ``27.64 h`` and its newline apart on one run of two); as displayed, nothing changes."""
    merged: list = []
    for out in outputs:
        if (merged and out.get("output_type") == "stream"
                and merged[-1].get("output_type") == "stream"
                and merged[-1].get("name") == out.get("name")):
            prev = merged[-1]
            join = ("".join if isinstance(prev["text"], list) else str)(prev["text"])
            merged[-1] = nbformat.from_dict({**prev, "text": join + (
                "".join(out["text"]) if isinstance(out["text"], list) else out["text"])})
        else:
            merged.append(out)
    return merged


#: a uuid4 in hex (matplotlib's jshtml animation names its elements with one, per call)
UUID4_HEX = re.compile(r"(?<![0-9a-f])[0-9a-f]{12}4[0-9a-f]{3}[89ab][0-9a-f]{15}(?![0-9a-f])")
MARKUP = ("text/html", "image/svg+xml")


def renumber_markup_ids(nb, name: str):
    """Rename every uuid4-shaped token of the HTML and SVG outputs (in the cells, and in the
    Output widgets' stored state) by its order of first appearance, the same token alike
    everywhere, so that an element and the script that finds it by id still agree."""
    new: dict[str, str] = {}

    def sub(text: str) -> str:
        return UUID4_HEX.sub(lambda m: new.setdefault(m.group(0),
                                                      _new_id(name, "markup", len(new))), text)

    def walk(obj):
        if isinstance(obj, dict):
            for k in sorted(obj):
                if k in MARKUP and isinstance(obj[k], str):
                    obj[k] = sub(obj[k])
                elif k in MARKUP and isinstance(obj[k], list):
                    obj[k] = [sub(t) if isinstance(t, str) else t for t in obj[k]]
                else:
                    walk(obj[k])
        elif isinstance(obj, list):
            for v in obj:
                walk(v)

    for cell in nb.cells:
        walk(cell.get("outputs", []))
    walk(nb.get("metadata", {}).get("widgets", {}))
    return nb


def renumber_widgets(nb, name: str):
    """Rename the widget models (ipywidgets gives each a fresh uuid4 per run): the k-th model met
    — in the cells' outputs in order, then through the models' references to other models, then
    the unreferenced rest sorted by a signature of their content — gets :func:`_new_id`
    everywhere: view outputs (``model_id``), the notebook's widget state (keys and
    ``IPY_MODEL_`` references), and widget views nested in an Output widget's state."""
    bundle = nb.get("metadata", {}).get("widgets", {}).get(WIDGET_STATE)
    state = bundle.get("state", {}) if bundle else {}
    known = set(state)
    for cell in nb.cells:
        for out in cell.get("outputs", []):
            view = out.get("data", {}).get(WIDGET_VIEW)
            if isinstance(view, dict) and isinstance(view.get("model_id"), str):
                known.add(view["model_id"])
    if not known:
        return nb
    order: list[str] = []
    seen: set[str] = set()

    def meet(obj) -> None:
        """Number the models ``obj`` names (in its order), then those they name."""
        queue = []
        for s in _strings(obj):
            mid = _model_id(s, known)
            if mid is not None and mid not in seen:
                seen.add(mid)
                order.append(mid)
                queue.append(mid)
        for mid in queue:
            meet(state.get(mid, {}))

    sigs: dict[str, str] = {}

    def signature(mid: str, path=()) -> tuple[str, bool]:
        """A model's content with each reference replaced by the referenced model's signature
        (equal signatures: interchangeable subgraphs, whatever their ids), and whether a cycle
        was cut (then it depends on where the walk began, and is not kept)."""
        if mid in path:
            return "<cycle>", True
        if mid in sigs:
            return sigs[mid], False
        cut = False

        def sub(obj):
            nonlocal cut
            if isinstance(obj, str):
                ref = _model_id(obj, known)
                if ref is None:
                    return obj
                sig, c = signature(ref, path + (mid,))
                cut |= c
                return "<" + sig + ">"
            if isinstance(obj, dict):
                return {k: sub(v) for k, v in obj.items()}
            if isinstance(obj, list):
                return [sub(v) for v in obj]
            return obj
        sig = json.dumps(sub(state.get(mid)), sort_keys=True)
        if not cut:
            sigs[mid] = sig
        return sig, cut

    for cell in nb.cells:
        meet(cell.get("outputs", []))
    for mid in sorted((m for m in state if m not in seen), key=lambda m: signature(m)[0]):
        if mid not in seen:
            meet([mid])
    new = {mid: _new_id(name, "widget", k) for k, mid in enumerate(order)}
    for cell in nb.cells:
        if "outputs" in cell:
            cell["outputs"] = nbformat.from_dict(_rename(cell["outputs"], new))
    if bundle:
        bundle["state"] = nbformat.from_dict({new[mid]: _rename(state[mid], new)
                                              for mid in sorted(state, key=lambda m: new[m])})
    return nb


SLICE_S = 1.0     # longest single wait on a socket
LATE_S = 0.2      # a message seen this long after it was sent, while we waited: a lost wake-up


def sliced(get_msg, counter: list):
    """``get_msg(timeout)`` of an asyncio channel as a loop of :data:`SLICE_S` polls (each ends
    with a direct check of the socket). A message sent while we were already waiting but seen
    more than :data:`LATE_S` later (its header's date) was found by such a check, not by its
    wake-up: counted in ``counter[0]``."""
    async def get(timeout=None):
        deadline = None if timeout is None else time.monotonic() + timeout
        waiting_since = time.time()
        while True:
            left = SLICE_S if deadline is None else max(0.0, min(SLICE_S, deadline - time.monotonic()))
            try:
                msg = await get_msg(timeout=left)
            except Empty:
                if deadline is not None and time.monotonic() >= deadline:
                    raise
                continue
            sent = msg["header"].get("date")
            if sent is not None:
                sent = sent.timestamp()
                if sent > waiting_since and time.time() - sent > LATE_S:
                    counter[0] += 1
            return msg
    return get


class Runner(NotebookClient):
    """nbclient with progress, the figure check, and no single long wait on a socket."""

    def __init__(self, nb, name: str, **kw):
        super().__init__(nb, **kw)
        self.name = name
        self.lost = [0]
        self.figure_defects = 0
        self.n_code = sum(1 for c in nb.cells if c.cell_type == "code" and c.source.strip())
        self.k = 0

    def slice_waits(self) -> None:
        for ch in (self.kc.shell_channel, self.kc.iopub_channel):
            ch.get_msg = sliced(ch.get_msg, self.lost)

    async def async_execute_cell(self, cell, cell_index, execution_count=None,
                                 store_history=True):
        if cell.cell_type != "code" or not cell.source.strip():
            return cell
        self.k += 1
        lost, t0 = self.lost[0], time.perf_counter()
        out = await super().async_execute_cell(cell, cell_index, execution_count, store_history)
        for o in cell.outputs:
            if o.output_type == "stream" and "figure check:" in o.text:
                for line in o.text.splitlines():
                    if line.startswith("figure check:"):
                        self.figure_defects += 1
                        print(f"  {self.name} [{self.k:2d}] {line}", flush=True)
        first = cell.source.strip().splitlines()[0][:60]
        note = (f"  ({self.lost[0] - lost} lost wake-up(s) recovered)" if self.lost[0] > lost
                else "")
        print(f"  {self.name} [{self.k:2d}/{self.n_code}] {time.perf_counter() - t0:6.1f} s"
              f"  {first}{note}", flush=True)
        return out

    execute_cell = run_sync(async_execute_cell)


KERNELSPEC = {"display_name": "Python 3", "language": "python", "name": "python3"}


def _install_check(client: Runner, mode: str) -> None:
    reply = client.wait_for_reply(client.kc.execute(KERNEL_SETUP.format(mode=mode),
                                                    store_history=False))
    if reply is None or reply["content"]["status"] != "ok":
        raise RuntimeError(f"figure check not installed: {reply and reply['content'].get('evalue')}")


def run_one(path: Path, timeout: float, sync: bool = True, write: bool = True,
            check: str = "raise") -> tuple[bool, int]:
    src = path.parent / "src" / f"{path.stem}.py"
    if sync:
        subprocess.run([str(BIN / "jupytext"), "--quiet", "--update", "--to", "ipynb", "-o",
                        str(path), str(src)], check=True)
    nb = nbformat.read(path, as_version=4)
    nb.metadata.pop("widgets", None)     # this run's widgets only (nbclient adds them, if any)
    client = Runner(nb, path.stem, timeout=timeout, kernel_name="python3", record_timing=False,
                    resources={"metadata": {"path": str(path.parent)}})
    t0 = time.perf_counter()
    ok = True
    try:
        with client.setup_kernel():
            client.slice_waits()
            _install_check(client, check)
            # what nbclient's own execute() records and this cell-by-cell loop bypasses: the
            # book (myst-nb) needs language_info to highlight the code cells
            info = client.wait_for_reply(client.kc.kernel_info())
            if info is not None and "language_info" in info["content"]:
                nb.metadata["language_info"] = info["content"]["language_info"]
            nb.metadata.setdefault("kernelspec", dict(KERNELSPEC))
            for i, cell in enumerate(nb.cells):
                client.execute_cell(cell, i)
            client.set_widgets_metadata()
    except (CellExecutionError, CellTimeoutError, DeadKernelError) as exc:
        ok = False
        print(f"FAIL {path.stem}: {type(exc).__name__}: "
              f"{_ANSI.sub('', str(exc)).strip()[-1500:]}", flush=True)
    if ok and write:
        nbformat.write(normalise(nb, path.stem), path)
    lost = client.lost[0]
    print(f"{'done' if ok else 'FAILED'} {path.stem}: {client.k} cells in "
          f"{time.perf_counter() - t0:.0f} s" + (f", {lost} lost wake-up(s) recovered" if lost
                                                 else ""), flush=True)
    return ok, lost


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("only", nargs="*", help="notebook name prefixes (00 05 …); default all")
    ap.add_argument("--timeout", type=float, default=600, help="seconds per cell (600)")
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
        ok, s = run_one(p, args.timeout, not args.no_sync, not args.no_write, args.figure_check)
        failed += not ok
        stalls += s
    print(f"notebooks: {len(nbs) - failed} executed, {failed} failed, {stalls} lost wake-ups "
          f"recovered ({time.perf_counter() - t0:.0f} s)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
