"""nbval policy (after devito), and the figure check in every notebook kernel.

Printed text is compared strictly; renderings that are not meant to be byte-stable are not —
figures (PNG/SVG), LaTeX (its text/plain twin is compared) and widget views (their state lives
in the kernel).

Before a notebook's first cell, its kernel runs :data:`KERNEL_SETUP`: ``plt.show()`` then runs
:func:`imunav.plotting.check_figure` on every figure it shows and raises
:class:`~imunav.plotting.FigureCheckError` on a defect (a hidden labelled line, more than 8
legend entries, two units on one axis, an internal id in a title or label, text under 8 pt, a
figure wider than 7 in or under 150 dpi, …): the cell fails under nbval with the list.
"""

from nbval.plugin import IPyNbFile

SKIP = ("image/png", "image/svg+xml", "image/jpeg", "text/latex",
        "application/vnd.jupyter.widget-view+json")

#: Run in each notebook's kernel before its cells (its output is not compared).
KERNEL_SETUP = "from imunav.plotting.style import install_figure_check as _f; _f(); del _f"


def _install_in_kernel(kernel) -> None:
    msg_id = kernel.kc.execute(KERNEL_SETUP, store_history=False, stop_on_error=False)
    while True:
        reply = kernel.kc.get_shell_msg(timeout=120)
        if reply["parent_header"].get("msg_id") == msg_id:
            break
    kernel.await_idle(msg_id, 120)
    if reply["content"]["status"] != "ok":
        raise RuntimeError("the figure check could not be installed in the kernel: "
                           f"{reply['content'].get('ename')}: {reply['content'].get('evalue')}")


def pytest_collectstart(collector):
    if getattr(collector, "skip_compare", None) is not None:
        collector.skip_compare = tuple(collector.skip_compare) + SKIP
    if isinstance(collector, IPyNbFile):
        setup = collector.setup

        def setup_with_figure_check():
            setup()
            _install_in_kernel(collector.kernel)

        collector.setup = setup_with_figure_check
