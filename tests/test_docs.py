"""The README and the book's generated pages (issue 35, item 6).

The README is the front door: at most 150 lines, the two commands first, and its Python and
command-line examples run and print what it shows (the output blocks under them are compared
with a fresh run, so a change of the library's numbers or wording fails here, not silently on
the page). The command-line reference (``docs/cli.md``) is rendered at build time from the
parser by ``docs/clidoc.py``: checked here against argparse's own ``imunav <command> --help``
(every option, its help, the usage line), with a directive for every command and a page note
for every option whose parser help is empty.
"""

import os
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from imunav.cli import main

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
CLI_PAGE = ROOT / "docs" / "cli.md"

sys.path.insert(0, str(ROOT / "docs"))
clidoc = pytest.importorskip("clidoc")   # needs Sphinx (numpydoc's dependency, in dev)


def _blocks(text: str) -> list[tuple[str, str, int]]:
    """Fenced code blocks: (info string, body, line number of the opening fence)."""
    out, lines, i = [], text.splitlines(), 0
    while i < len(lines):
        m = re.match(r"^```(.*)$", lines[i])
        if m:
            start, body = i, []
            i += 1
            while not lines[i].startswith("```"):
                body.append(lines[i])
                i += 1
            out.append((m.group(1).strip(), "\n".join(body) + "\n", start + 1))
        i += 1
    return out


def _section(text: str, title: str) -> str:
    """The text of the level-2 section ``## title`` (up to the next level-2 heading)."""
    m = re.search(rf"^## {re.escape(title)}\n(.*?)(?=^## |\Z)", text, flags=re.M | re.S)
    assert m, f"README has no section '## {title}'"
    return m.group(1)


# ------------------------------------------------------------------------------------ README

def test_readme_is_a_front_door():
    text = README.read_text(encoding="utf-8")
    lines = text.splitlines()
    assert len(lines) <= 150, f"README.md has {len(lines)} lines (at most 150)"
    # the first lines stay the two commands that do everything on a fresh clone (CI and users
    # run them from there), make test-browser among them
    assert lines[0] == "# imunav" and lines[2] == "```sh"
    info, first, line = _blocks(text)[0]
    assert line == 3
    commands = [c.split("#")[0].strip() for c in first.splitlines()]
    assert commands == ["make reproduce", "make test && make test-browser"], commands


def test_readme_links_resolve():
    text = README.read_text(encoding="utf-8")
    targets = re.findall(r"\]\(([^)#\s]+)(?:#[^)]*)?\)", text)
    local = [t for t in targets if not t.startswith(("http://", "https://"))]
    assert local, "the README links to the book pages and notebooks"
    missing = [t for t in local if not (ROOT / t).exists()]
    assert not missing, missing
    for page in ("docs/cli.md", "docs/formats.md", "docs/guide_assessment.md",
                 "docs/guide_earth.md", "docs/guide_aided.md", "docs/guide_real_logs.md",
                 "docs/performance.md", "docs/contributing.md"):
        assert page in local, f"the README's 'Read on' should link {page}"


def test_readme_python_example_prints_what_it_shows():
    blocks = _blocks(_section(README.read_text(encoding="utf-8"), "Python"))
    (lang, code, _), (_, shown, _) = blocks[0], blocks[1]
    assert lang == "python"
    env = {k: v for k, v in os.environ.items() if k != "PYTHONWARNINGS"}
    run = subprocess.run([sys.executable, "-W", "error::DeprecationWarning", "-c", code],
                         cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert run.stdout == shown


def test_readme_cli_example_prints_what_it_shows(capsys, monkeypatch):
    monkeypatch.chdir(ROOT)
    blocks = _blocks(_section(README.read_text(encoding="utf-8"), "Command line"))
    (lang, command, _), (_, shown, _) = blocks[0], blocks[1]
    assert lang == "sh" and command.count("\n") == 1
    argv = shlex.split(command)
    assert argv[0] == "imunav"
    assert main(argv[1:]) == 0
    assert capsys.readouterr().out == shown


# ------------------------------------------------------------------------ the CLI reference

def _page_directives() -> dict[str, str]:
    """``{imunav-cli} NAME`` directives of docs/cli.md → their content (the page notes)."""
    text = CLI_PAGE.read_text(encoding="utf-8")
    found = re.findall(r"^```\{imunav-cli\} (\S+)\n(.*?)^```", text, flags=re.M | re.S)
    names = [n for n, _ in found]
    assert len(names) == len(set(names)), names
    return dict(found)


def _help(command: str, capsys, monkeypatch) -> str:
    monkeypatch.setenv("COLUMNS", str(clidoc.WIDTH + 2))      # argparse wraps at COLUMNS − 2
    assert main(["--help"] if command == "imunav" else [command, "--help"]) == 0
    return capsys.readouterr().out


def _help_options(text: str) -> set[str]:
    """The option strings and positional names argparse lists in its help (the lines that
    define an argument, not the mentions inside help texts)."""
    out, section = set(), None
    for line in text.splitlines():
        if re.match(r"^\S.*:$", line):
            section = line
            continue
        m = re.match(r"^  (\S.*?)(?:\s{2,}|$)", line)     # the argument, before its help
        if not (m and section):
            continue
        if section.startswith("positional"):
            name = m.group(1)
            if not name.startswith("{"):            # the subcommands of the top level
                out.add(name)
        else:                                       # "-h, --help", "--rate HZ"
            out.update(re.findall(r"(?:^|, )(-[\w-]+)", m.group(1)))
    return out


def test_every_command_has_its_reference():
    assert set(_page_directives()) == set(clidoc.commands())


@pytest.mark.parametrize("command", list(clidoc.commands()))
def test_reference_rows_are_the_help_of_the_parser(command, capsys, monkeypatch):
    parser, summary = clidoc.commands()[command]
    text = _help(command, capsys, monkeypatch)
    rows = clidoc.options(parser)
    flags = {f for r in rows for f in r["flags"]}
    assert flags == _help_options(text), (flags ^ _help_options(text))
    flat = " ".join(text.split())
    for r in rows:                                  # every help text as --help prints it
        assert " ".join(r["help"].replace("%%", "%").split()) in flat, r
    # the usage line, as argparse prints it at the same width
    assert text.startswith(clidoc.usage(parser) + "\n")
    if command != "imunav":
        assert summary, f"imunav {command} has no one-line help"


@pytest.mark.parametrize("command", list(clidoc.commands()))
def test_every_option_without_help_has_a_page_note(command):
    parser, _ = clidoc.commands()[command]
    notes = clidoc.notes(_page_directives()[command].splitlines())
    rows = clidoc.options(parser)
    bare = [r["flags"] for r in rows if not r["help"] and not set(r["flags"]) & set(notes)]
    assert not bare, f"imunav {command}: no parser help and no note on docs/cli.md: {bare}"
    known = {f for r in rows for f in r["flags"]}
    assert set(notes) <= known, set(notes) - known


def test_describe_adds_what_the_help_leaves_unsaid():
    row = {"flags": ["--rate"], "value": "HZ", "required": True, "default": None,
           "choices": None, "help": "sample rate (Hz)"}
    assert clidoc.describe(row) == ("Sample rate (Hz).", ["Required."])
    row = {"flags": ["--kind"], "value": "K", "required": False, "default": "a",
           "choices": ["a", "b"], "help": ""}
    assert clidoc.describe(row) == ("", ["One of a, b.", "Default a."])
    row = {"flags": ["--seed"], "value": "SEED", "required": False, "default": 0,
           "choices": None, "help": "seed (default 0)"}
    assert clidoc.describe(row) == ("Seed (default 0).", [])        # 0 is a default, said once
    assert clidoc.notes(["--a: one", "  two", "", "B: three"]) == {"--a": "one two", "B": "three"}
    with pytest.raises(ValueError):
        clidoc.notes(["no colon here"])
