"""Browser tests (``make test-browser``): the notebooks in a real JupyterLab, and the book.

Two suites in a headless Chromium (the Debian package, driven by Playwright through
``executable_path``; Playwright's own browser download is not needed):

*JupyterLab* — for every ``notebooks/NN_*.ipynb`` (on a temporary copy: the stored notebooks are
never touched), open it in JupyterLab served on a loopback port, **Run → Run All Cells** through
the menu, wait for the kernel, save, and fail on any ``error`` output; count the figures shown.
Then, in every interactive widget area, drag a slider with the mouse and change a dropdown,
and fail unless the figure under it changes.

*Book* — open every page of ``build/book/`` (served on loopback), fail on a console error or a
failed request (everything must be bundled), on a notebook page with fewer images than the
notebook stores, or on math that MathJax did not render. Every page of ``docs/`` (the guides,
the references, the contributor pages) must be among them, and the command-line reference must
show one generated option table per command.

*A stalled run* — the kernel idle, cells still pending, nothing run for 90 s — is a message whose
wake-up was lost on the way (the same edge-triggered zmq file descriptors whose lost wake-ups
``notebooks/run.py`` measured under nbclient; there the reply had been in the socket all along).
Any new message on the notebook's own kernel connection wakes every hop again, so the suite
*nudges*: it sends a ``kernel_info`` request through the page's own connection (JupyterLab is
started with ``expose_app_in_browser``) and waits again; the server's view of the kernel
(``/api/kernels``) is printed beside it. Only if two nudges do not help is the kernel restarted
and the notebook run again — and that is reported as a retry. Stalls, nudges and retries are
counted on the last lines.

Servers are started and stopped by PID. The output ends ``N passed, 0 failed``; the exit status is
1 if anything failed. Run: ``python tests/browser/run.py [--only NAME] [--skip-lab] [--skip-book]``.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
NOTEBOOKS = sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))
DOCS = sorted(p for p in (ROOT / "docs").iterdir() if p.suffix in (".md", ".rst"))
BOOK = ROOT / "build" / "book"
CHROMIUM = os.environ.get("CHROMIUM", "/usr/lib/chromium/chromium")
RUN_TIMEOUT_S = 600          # one notebook's Run All
WIDGET_TIMEOUT_S = 120       # one widget change to redraw its figure

SHOTS = Path(tempfile.gettempdir()) / "imunav-browser"     # screenshots of failures
SHOTS.mkdir(exist_ok=True)

results: list[tuple[str, bool, str]] = []
stalls = {"stalled": 0, "woken by a nudge": 0, "retried": 0}


def report(name: str, ok: bool, detail: str = "") -> None:
    results.append((name, ok, detail))
    print(f"{'PASS' if ok else 'FAIL'}  {name}" + (f": {detail}" if detail else ""), flush=True)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def wait_http(url: str, timeout: float = 90.0) -> None:
    t0 = time.time()
    while time.time() - t0 < timeout:
        try:
            urllib.request.urlopen(url, timeout=5)
            return
        except Exception:
            time.sleep(0.5)
    raise RuntimeError(f"server at {url} did not answer within {timeout:.0f} s")


def start(cmd: list[str], cwd: Path, env: dict | None = None) -> subprocess.Popen:
    return subprocess.Popen(cmd, cwd=cwd, env=env, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, start_new_session=True)


def stop(proc: subprocess.Popen) -> None:
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGTERM)
        try:
            proc.wait(20)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()


def stored_images(nb: Path) -> int:
    data = json.loads(nb.read_text())
    return sum(1 for c in data["cells"] for o in c.get("outputs", [])
               if {"image/png", "image/svg+xml", "image/jpeg"} & set(o.get("data", {})))


# ------------------------------------------------------------------------------ JupyterLab

STALL_S = 90                 # kernel idle, cells pending, nothing run for this long: stalled


def _wait_idle(page, timeout: float) -> str:
    """Until every code cell has run (no ``[*]``/``[ ]`` prompt, kernel idle, three polls in a
    row): ``"done"``; ``"error"`` if a cell raised (Run All stops there); ``"stalled"`` if the
    kernel sits idle with cells pending for ``STALL_S``
    (a message whose wake-up was lost on the way: see the module docstring); ``"timeout"``."""
    t0 = time.time()
    calm, last_run, last_change = 0, -1, time.time()
    while time.time() - t0 < timeout:
        st = page.evaluate("""() => {
            const prompts = [...document.querySelectorAll('.jp-Notebook .jp-InputPrompt')]
                .map(p => p.textContent.trim());
            const status = document.querySelector('.jp-Notebook-ExecutionIndicator');
            return {busy: status ? status.getAttribute('data-status') === 'busy' : false,
                    running: prompts.filter(p => p.includes('*')).length,
                    pending: prompts.filter(p => p === '[ ]:' || p === '[ ]').length,
                    run: prompts.filter(p => /\\[\\d+\\]/.test(p)).length,
                    error: [...document.querySelectorAll('.jp-Notebook .jp-OutputArea-output')]
                        .some(o => o.textContent.includes('Traceback (most recent call last)'))};
        }""")
        if st["run"] != last_run:
            last_run, last_change = st["run"], time.time()
        if not (st["busy"] or st["running"] or st["pending"]):
            calm += 1
            if calm >= 3:
                return "done"
        else:
            calm = 0
            if not st["busy"] and st["error"] and not st["running"]:
                return "error"   # Run All stops at an exception: the rest stays pending
            if not st["busy"] and time.time() - last_change > STALL_S:
                return "stalled"
        time.sleep(1.0)
    return "timeout"


def _server_view(page) -> str:
    """The Jupyter server's own view of the kernels (execution state, connections)."""
    try:
        ks = page.evaluate("""async () => (await (await fetch('/api/kernels')).json())
            .map(k => k.execution_state + ', ' + k.connections + ' connection(s)')""")
        return "; ".join(ks) or "no kernel"
    except Exception as exc:   # noqa: BLE001 — a diagnosis only
        return f"unknown ({type(exc).__name__})"


def _nudge(page) -> str:
    """A kernel_info request through the notebook's own kernel connection."""
    return page.evaluate("""async () => {
        const w = window.jupyterapp && window.jupyterapp.shell.currentWidget;
        const k = w && w.sessionContext && w.sessionContext.session &&
                  w.sessionContext.session.kernel;
        if (!k) return 'no kernel connection to nudge';
        const r = await Promise.race([k.requestKernelInfo().then(() => 'replied'),
                                      new Promise(res => setTimeout(() => res('no reply'), 20000))]);
        return 'kernel_info ' + r;
    }""")


def _image_srcs(area) -> list[str]:
    return area.evaluate("el => [...el.querySelectorAll('img')].map(i => i.src)")


def _wait_changed(area, before: list[str], timeout: float) -> bool:
    t0 = time.time()
    while time.time() - t0 < timeout:
        now = _image_srcs(area)
        if now and now != before:
            time.sleep(1.0)   # let a continuous update settle
            return True
        time.sleep(0.5)
    return False


def _run_manual(area) -> None:
    """An ``interact_manual`` area redraws only when its button is pressed: press it, as a
    reader would after moving a control (a plain ``interact`` has no such button)."""
    button = area.locator("button", has_text="Run Interact")
    if button.count():
        button.first.click()


def _check_widgets(page, name: str) -> None:
    areas = page.locator(".jp-OutputArea-output .widget-interact, "
                         ".jp-OutputArea-output > .jupyter-widgets.widget-vbox")
    n = areas.count()
    if n == 0:
        report(f"lab {name} widgets", False, "no interactive widget area found")
        return
    for i in range(n):
        area = areas.nth(i)
        area.scroll_into_view_if_needed()
        checked = []
        handles = area.locator(".noUi-handle")
        if handles.count():
            before = _image_srcs(area)
            handle = handles.first
            handle.scroll_into_view_if_needed()
            box = handle.bounding_box()
            track = area.locator(".noUi-target").first.bounding_box()
            x0, y0 = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
            # drag a quarter of the track, towards the side with room
            dx = track["width"] / 4 if x0 < track["x"] + track["width"] / 2 else -track["width"] / 4
            page.mouse.move(x0, y0)
            page.mouse.down()
            for k in range(1, 11):
                page.mouse.move(x0 + dx * k / 10, y0)
                time.sleep(0.05)
            page.mouse.up()
            _run_manual(area)
            ok = _wait_changed(area, before, WIDGET_TIMEOUT_S)
            checked.append(f"slider drag {'redrew' if ok else 'did NOT change'} the figure")
            if not ok:
                report(f"lab {name} widget {i + 1}", False, "; ".join(checked))
                continue
        selects = area.locator(".widget-dropdown select")
        if selects.count():
            before = _image_srcs(area)
            sel = selects.first
            options = sel.evaluate("s => [...s.options].map(o => o.value)")
            current = sel.evaluate("s => s.value")
            target = next(o for o in options if o != current)
            sel.select_option(target)
            _run_manual(area)
            ok = _wait_changed(area, before, WIDGET_TIMEOUT_S)
            checked.append(f"dropdown → {sel.evaluate('s => s.options[s.selectedIndex].text')!r} "
                           f"{'redrew' if ok else 'did NOT change'} the figure")
        ok = bool(checked) and all("NOT" not in c for c in checked)
        report(f"lab {name} widget {i + 1}", ok, "; ".join(checked) or "no slider or dropdown")


def _shutdown_kernels(page) -> None:
    """Stop every kernel of the server (each notebook's run is independent; 2 cores)."""
    try:
        page.evaluate("""async () => {
            const x = (document.cookie.match(/_xsrf=([^;]+)/) || [])[1] || '';
            const h = {'X-XSRFToken': decodeURIComponent(x)};
            const ks = await (await fetch('/api/kernels', {headers: h})).json();
            for (const k of ks) await fetch('/api/kernels/' + k.id, {method: 'DELETE', headers: h});
        }""")
    except Exception:   # noqa: BLE001 — the server stops them at the end anyway
        pass


def run_lab(browser, only: str | None) -> None:
    # notebooks/ beside copies of examples/ and benchmarks/, as in the repository, and the
    # recordings at ../shared if the repository has them: notebook 10 reads
    # ../examples/drive.toml, notebook 11 ../benchmarks/realdata.py and ../../shared/data,
    # as a reader running them from notebooks/ would
    outer = Path(tempfile.mkdtemp(prefix="imunav-lab-"))
    top = outer / "repo"
    work = top / "notebooks"
    work.mkdir(parents=True)
    for folder in ("examples", "benchmarks"):
        shutil.copytree(ROOT / folder, top / folder)
    if (ROOT.parent / "shared").is_dir():
        (outer / "shared").symlink_to(ROOT.parent / "shared")
    for nb in NOTEBOOKS:   # copies without outputs: every figure counted is drawn by this run
        data = json.loads(nb.read_text())
        for c in data["cells"]:
            if c["cell_type"] == "code":
                c["outputs"], c["execution_count"] = [], None
        data["metadata"].pop("widgets", None)
        (work / nb.name).write_text(json.dumps(data))
    settings = work / ".lab-settings"
    for ext, name, value in (("notebook-extension", "tracker", {"windowingMode": "none"}),
                             ("apputils-extension", "notification", {"fetchNews": "false"})):
        f = settings / f"@jupyterlab/{ext}/{name}.jupyterlab-settings"
        f.parent.mkdir(parents=True, exist_ok=True)
        f.write_text(json.dumps(value))
    port = free_port()
    env = {k: v for k, v in os.environ.items() if k != "MPLBACKEND"}   # inline figures
    env["JUPYTERLAB_SETTINGS_DIR"] = str(settings)   # every cell in the DOM, no news pop-up
    lab = start([sys.executable, "-m", "jupyterlab", "--no-browser", "--allow-root",
                 f"--port={port}", "--ip=127.0.0.1", "--IdentityProvider.token=",
                 "--LabApp.expose_app_in_browser=True",
                 "--ServerApp.password=", f"--ServerApp.root_dir={work}",
                 "--LabApp.news_url=None", "--LabApp.check_for_updates_class="
                 "jupyterlab.NeverCheckForUpdate"], cwd=work, env=env)
    nudge_checked = False
    try:
        wait_http(f"http://127.0.0.1:{port}/lab")
        for nb in NOTEBOOKS:
            if only and only not in nb.name:
                continue
            name = nb.stem
            context = browser.new_context(viewport={"width": 1500, "height": 1000})
            page = context.new_page()
            t0 = time.time()
            try:
                # ?reset: a fresh workspace, not the tabs of the previous notebook
                page.goto(f"http://127.0.0.1:{port}/lab/tree/{nb.name}?reset", timeout=120_000)
                page.wait_for_selector(".jp-Notebook .jp-Cell", timeout=120_000)
                # JupyterLab may ask which kernel to start: the notebook's own (Python 3)
                try:
                    page.locator(".jp-Dialog-button.jp-mod-accept").click(timeout=8_000)
                except Exception:   # noqa: BLE001 — no dialog: the kernel started by itself
                    pass
                # the kernel must be up before Run All
                page.wait_for_selector(".jp-Notebook-ExecutionIndicator[data-status='idle']",
                                       timeout=120_000)
                page.locator(".lm-MenuBar-itemLabel", has_text="Run").first.click()
                page.get_by_role("menuitem", name="Run All Cells", exact=True).click()
                state = _wait_idle(page, RUN_TIMEOUT_S)
                notes = []
                for _ in range(2):
                    if state != "stalled":
                        break
                    stalls["stalled"] += 1
                    server = _server_view(page)
                    nudged = _nudge(page)
                    state = _wait_idle(page, RUN_TIMEOUT_S)
                    woke = state != "stalled"
                    stalls["woken by a nudge"] += woke
                    notes.append(f"STALL: idle with cells pending (server: {server}); nudged "
                                 f"({nudged}): {'it ran on' if woke else 'still stalled'}")
                    print(f"      {name}: {notes[-1]}", flush=True)
                retried = state == "stalled"
                if retried:   # two nudges did not help: restart the kernel, run everything again
                    stalls["retried"] += 1
                    page.locator(".lm-MenuBar-itemLabel", has_text="Run").first.click()
                    page.get_by_role("menuitem", name="Restart Kernel and Run All Cells…").click()
                    page.locator(".jp-Dialog-button.jp-mod-accept").click()
                    time.sleep(5.0)
                    state = _wait_idle(page, RUN_TIMEOUT_S)
                finished = state == "done"
                page.keyboard.press("Control+s")
                time.sleep(2.0)
                saved = json.loads((work / nb.name).read_text())
                errors = [o for c in saved["cells"] for o in c.get("outputs", [])
                          if o.get("output_type") == "error"]
                unrun = sum(1 for c in saved["cells"]
                            if c["cell_type"] == "code" and c.get("execution_count") is None)
                shown = page.evaluate("() => document.querySelectorAll("
                                      "'.jp-OutputArea-output img, .jp-OutputArea-output svg.main-svg,"
                                      " .jp-RenderedSVG svg').length")
                ok = finished and not errors and unrun == 0 and shown >= 1
                detail = (f"Run All in {time.time() - t0:.0f} s, {shown} figures shown, "
                          f"{len(errors)} error outputs, {unrun} cells not run")
                if errors:
                    detail += f" (first: {errors[0]['ename']}: {errors[0]['evalue'][:120]})"
                if notes:
                    detail += "; " + "; ".join(notes)
                if retried:
                    detail += "; RETRIED: the kernel was restarted and the notebook run again"
                if not finished:
                    detail += f"; {state} after the {'second' if retried else 'first'} Run All"
                report(f"lab {name} run-all", ok, detail)
                if ok and not nudge_checked:   # the remedy itself works (once per suite)
                    nudge_checked = True
                    r = _nudge(page)
                    report("lab nudge (kernel_info through the page's connection)",
                           r == "kernel_info replied", r)
                if ok:
                    _check_widgets(page, name)
            except Exception as exc:   # noqa: BLE001 — report and go on with the next notebook
                shot = SHOTS / f"lab_{name}.png"
                page.screenshot(path=shot)
                report(f"lab {name}", False,
                       f"{type(exc).__name__}: {str(exc).splitlines()[0]} (screenshot {shot})")
            finally:
                _shutdown_kernels(page)
                context.close()
    finally:
        stop(lab)
        shutil.rmtree(outer, ignore_errors=True)


# ------------------------------------------------------------------------------ book

def run_book(browser, only: str | None) -> None:
    if not (BOOK / "index.html").exists():
        report("book", False, "build/book/index.html missing: run `make book` first")
        return
    port = free_port()
    server = start([sys.executable, "-m", "http.server", str(port), "--bind", "127.0.0.1"],
                   cwd=BOOK)
    try:
        wait_http(f"http://127.0.0.1:{port}/index.html")
        pages = sorted(p.relative_to(BOOK).as_posix() for p in BOOK.glob("*.html")
                       if p.name not in ("genindex.html", "search.html", "py-modindex.html"))
        # every page written in docs/ is built and so visited below (a page left out of the
        # toctree fails `make book` already; this catches a build from a stale docs/)
        missing = sorted(f"{d.stem}.html" for d in DOCS if f"{d.stem}.html" not in pages)
        if not (only and not any(only in f"{d.stem}.html" for d in DOCS)):
            report("book pages of docs/", not missing,
                   f"{len(DOCS)} pages, all built" if not missing else f"not built: {missing}")
        for rel in pages:
            if only and only not in rel:
                continue
            context = browser.new_context()
            page = context.new_page()
            problems: list[str] = []
            page.on("console", lambda m, p=problems: m.type == "error" and p.append(f"console: {m.text}"))
            page.on("pageerror", lambda e, p=problems: p.append(f"page error: {e}"))
            page.on("requestfailed", lambda r, p=problems: p.append(f"request failed: {r.url}"))
            page.on("response", lambda r, p=problems: r.status >= 400 and p.append(
                f"HTTP {r.status}: {r.url}"))
            page.on("request", lambda r, p=problems: not r.url.startswith(
                (f"http://127.0.0.1:{port}/", "data:", "blob:", "about:")) and p.append(
                f"request outside the book: {r.url}"))
            try:
                page.goto(f"http://127.0.0.1:{port}/{rel}", wait_until="networkidle", timeout=60_000)
                # MathJax typesets asynchronously
                page.wait_for_function(
                    "() => !window.MathJax || !MathJax.startup || MathJax.startup.promise"
                    " && (MathJax.startup.promise.then(() => window.__mj = 1), window.__mj === 1)",
                    timeout=60_000)
                math = page.evaluate("""() => {
                    const m = [...document.querySelectorAll('.math')];
                    return [m.length, m.filter(e => !e.querySelector('mjx-container')).length];
                }""")
                raw = page.evaluate("""() => {
                    const t = document.querySelector('article') ?
                        document.querySelector('article').innerText : '';
                    return (t.match(/\\$\\$|\\\\\\(|\\\\\\[|\\\\begin\\{/g) || []).length;
                }""")
                imgs = page.evaluate("() => document.querySelectorAll('article img').length")
                broken = page.evaluate("() => [...document.querySelectorAll('article img')]"
                                       ".filter(i => !i.complete || i.naturalWidth === 0).length")
                nb = ROOT / "notebooks" / rel.replace(".html", ".ipynb")
                need = stored_images(nb) if nb.exists() else 0
                if rel == "cli.html":      # one generated option table per {imunav-cli} command
                    tables = page.evaluate("() => document.querySelectorAll("
                                           "'article table.imunav-cli-options').length")
                    want = (ROOT / "docs" / "cli.md").read_text().count("```{imunav-cli} ")
                    if tables != want:
                        problems.append(f"{tables} option tables, docs/cli.md has {want} commands")
                if math[1]:
                    problems.append(f"{math[1]} of {math[0]} math elements not rendered")
                if raw:
                    problems.append(f"{raw} raw TeX delimiters in the text")
                if imgs < need:
                    problems.append(f"{imgs} images on the page, the notebook stores {need}")
                if broken:
                    problems.append(f"{broken} images failed to load")
                report(f"book {rel}", not problems,
                       f"{imgs} images (notebook {need}), {math[0]} math rendered"
                       if not problems else "; ".join(problems[:4]))
            except Exception as exc:   # noqa: BLE001
                report(f"book {rel}", False, f"{type(exc).__name__}: {str(exc).splitlines()[0]}")
            finally:
                context.close()
    finally:
        stop(server)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", help="only notebooks/pages whose name contains this")
    ap.add_argument("--skip-lab", action="store_true")
    ap.add_argument("--skip-book", action="store_true")
    args = ap.parse_args()
    from playwright.sync_api import sync_playwright

    t0 = time.time()
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox"])
        try:
            if not args.skip_book:
                run_book(browser, args.only)
            if not args.skip_lab:
                run_lab(browser, args.only)
        finally:
            browser.close()
    failed = sum(1 for _, ok, _ in results if not ok)
    print(f"\nbrowser suite: {time.time() - t0:.0f} s")
    print("stalls: " + ", ".join(f"{v} {k}" for k, v in stalls.items()))
    print(f"{len(results) - failed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
