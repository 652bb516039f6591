"""Sphinx configuration of the imunav book (``make book``).

The pages are the stored notebooks (never re-executed: ``nb_execution_mode = "off"``), a
landing page, the guides and reference pages of ``docs/`` (the command-line reference rendered
from imunav's own argument parser by ``clidoc.py``; example files and benchmark records
included from the files themselves) and an API reference generated from the numpydoc
docstrings. Code cells that only
draw carry the cell tag ``hide-input`` and exercise solutions ``hide-cell``: myst-nb folds them
behind a "Show code" toggle, so a page reads as words, equations and figures. Figures are shown
at the size stored in their output metadata (``imunav.plotting.use_book_style``), so their text
stays at its size in points. ``make book`` copies
``docs/`` and ``notebooks/*.ipynb`` into ``build/book-src`` and builds it with ``-W``, so a
missing figure or a broken cross-reference fails the build. Nothing is loaded from the
internet: MathJax is bundled (sphinx-mathjax-offline) and the ipywidgets CDN script is off.
"""

import os
import sys

sys.path.insert(0, os.path.abspath("../.."))   # build/book-src → repository root
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))   # clidoc.py beside this file

project = "imunav"
author = "imunav developers"
copyright = "2026, imunav developers (BSD-3-Clause)"

extensions = [
    "myst_nb",
    "sphinx.ext.autodoc",
    "numpydoc",
    "sphinx.ext.mathjax",
    "sphinx-mathjax-offline",
    "clidoc",                 # {imunav-cli} COMMAND: the CLI reference from imunav's own parser
]

# Notebooks: shown as stored (outputs and figures committed by `make notebooks`).
nb_execution_mode = "off"
nb_ipywidgets_js = {}                 # no CDN script: the widgets' first state is a stored figure
nb_merge_streams = True
# Generated Markdown outputs (coverage tables, verdict lines, the numbers under a computation)
# are rendered as MyST, like the markdown cells: CommonMark would show tables as pipes and
# leave $math$ raw.
nb_render_markdown_format = "myst"
myst_enable_extensions = ["dollarmath", "amsmath"]
myst_heading_anchors = 3
nb_mime_priority_overrides = [
    ("html", "application/vnd.jupyter.widget-view+json", None),   # no kernel in a book
    ("html", "application/vnd.jupyter.widget-state+json", None),
]

# API reference
autodoc_member_order = "bysource"
autodoc_typehints = "none"
numpydoc_show_class_members = False
numpydoc_validation_checks = set()
numpydoc_xref_param_type = False

exclude_patterns = ["_build", "**.ipynb_checkpoints"]
suppress_warnings = ["mystnb.unknown_mime_type"]

html_theme = "pydata_sphinx_theme"
html_title = "imunav"
html_favicon = "favicon.svg"   # browsers ask for one; without it a 404 in the console
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "header_links_before_dropdown": 4,
    "footer_start": ["copyright"],
}
html_static_path = []
html_context = {"default_mode": "light"}   # the theme logs a console error without one

# The docstrings write norms as |x| (plain text for help() readers); reStructuredText would read
# |x| as a substitution. Escape bars outside inline literals before numpydoc parses them.
import re  # noqa: E402

_LITERAL = re.compile(r"(``.*?``|`[^`]*`)")


def _escape_bars(app, what, name, obj, options, lines):
    for i, line in enumerate(lines):
        if "|" in line:
            parts = _LITERAL.split(line)
            lines[i] = "".join(p if j % 2 else p.replace("|", r"\|") for j, p in enumerate(parts))


# The contributor page includes the repository's DEVELOPERS.md as it stands (one text, kept where
# the developers read it): its headings one level down, its repository-relative links to docs/
# made relative to the book. MyST's include directive cannot do the latter (the book is built
# from a copy of docs/), so the text is put in place of a marker when the page is read.
DEVELOPERS_MARKER = "<!-- DEVELOPERS.md:"
_REPO = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))


def _developers_md() -> str:
    with open(os.path.join(_REPO, "DEVELOPERS.md"), encoding="utf-8") as fh:
        text = fh.read()
    text = re.sub(r"^(#+) ", r"#\1 ", text, flags=re.M)          # one heading level down
    return re.sub(r"\]\(docs/", "](", text)                        # docs/x.md → x.md


def _include_developers(app, docname, source):
    if docname == "contributing":
        lines = source[0].splitlines(keepends=True)
        source[0] = "".join(_developers_md() + "\n" if line.startswith(DEVELOPERS_MARKER) else line
                            for line in lines)


def setup(app):
    app.connect("autodoc-process-docstring", _escape_bars, priority=100)
    app.connect("source-read", _include_developers)
