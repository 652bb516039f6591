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

ROOT = Path(__file__).resolve().parents[2]
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


# ------------------------------------------------------------ the AIDING.toml key tables

aidkeys = pytest.importorskip("aidkeys")
FORMATS_PAGE = ROOT / "docs" / "formats.md"


def test_formats_page_holds_the_generated_aiding_key_tables():
    text = FORMATS_PAGE.read_text(encoding="utf-8")
    assert text.count(aidkeys.BEGIN) == 1 and text.count(aidkeys.END) == 1
    assert aidkeys.page_block(text) == aidkeys.markdown(), \
        "docs/formats.md is stale: run .venv/bin/python docs/aidkeys.py --write"


def test_every_table_and_key_is_on_the_page():
    from imunav.sensors.aids.config import SECTIONS
    block = aidkeys.page_block(FORMATS_PAGE.read_text(encoding="utf-8"))
    for table, config in SECTIONS.items():
        part = block.split(f"**`[{table}]`**")[1].split("**`[")[0]
        assert [f"`{k}`" for k in config.KEYS] == re.findall(r"^\| (`\w+`) \|", part, re.M), table


def test_value_range_words():
    from imunav.sensors.aids.keys import Key
    assert aidkeys.value_range(Key("x", "m", "d", hi=5.0), "t") == "(0, 5]"
    assert aidkeys.value_range(Key("x", "m", "d", positive=False, hi=1e4), "t") == "[0, 10000]"
    assert aidkeys.value_range(Key("x", "", "d", hi=1 - 1e-12), "t") == "(0, 1)"
    assert aidkeys.value_range(Key("x", "", "d"), "t") == "> 0"
    assert aidkeys.value_range(Key("x", "", "d", kind="integer", hi=6), "t") == \
        "a whole number, 1 … 6"
    assert aidkeys.value_range(Key("x", "", "d", kind="choice", choices=("a", "b")), "t") == \
        '`"a"` or `"b"`'
    assert aidkeys.default(Key("x", "", "d", default=(0.0, 0.0, 0.0))) == "`[0, 0, 0]`"
    assert aidkeys.default(Key("x", "", "d", required=True)) == "required"


def _base(table, config):
    """A table that reads: every required key at a value inside its range (and what several
    keys together need)."""
    d = {}
    for k in config.FIELDS:
        if k.required:
            d[k.name] = min(1.0, k.hi) if k.hi else 1.0
    if table == "gnss":
        d.update(position_sigma=1.0, correlation_time=10.0)
    return d


def _reads(config, table, d):
    from imunav.core.validation import ImunavError
    try:
        config.from_dict(d)
        return True
    except ImunavError as e:
        assert f"[{table}]" in str(e), e           # the one line names the table
        return False


def _probes(key):
    """(value, accepted?) pairs at the bounds the page states for ``key``."""
    hi = key.hi
    if key.kind == "choice":
        return [(c, True) for c in key.choices] + [("nope", False)]
    if key.kind == "integer":
        return [(1, True), (0, False), (1.5, False)] + ([(int(hi), True), (int(hi) + 1, False)]
                                                        if hi else [])
    if key.kind == "vector":
        return [([hi, -hi, 0.0], True), ([hi * 1.01, 0.0, 0.0], False), ([1.0, 2.0], False)]
    if key.kind == "intervals":
        return [([[0.0, 1.0], [2.0, 3.0]], True), ([[2.0, 3.0], [0.0, 1.0]], False),
                ([[1.0, 0.0]], False), ([0.0, 1.0], False)]
    if key.kind == "path":
        return [("x.pos", True), ("", False)]
    if key.kind == "delay":
        return [(10.0, True), (-10.0, True), ("auto", True), (10.01, False)]
    out = [(float("nan"), False), ("1", False) if key.kind != "angle" else ("2 deg", True)]
    if key.positive:
        out += [(0.0, False), ((hi or 1.0) * 1e-3, True)]
    else:
        out += [(0.0, True), (-1e-3, False)]
    if hi is not None:
        shown = aidkeys._number(hi)
        above = float(shown) if shown != "π" and float(shown) > hi else hi * (1 + 1e-6) + 1e-9
        out += [(hi, True), (above, False)]
    return out


@pytest.mark.parametrize("table", ["gnss", "baro", "heading", "nhc", "zupt", "odometer",
                                   "initial", "mounting"])
def test_stated_ranges_are_what_the_reader_enforces(table):
    from imunav.sensors.aids.config import SECTIONS
    config = SECTIONS[table]
    for key in config.FIELDS:
        if (table, key.name) in aidkeys.READ_BY_HAND:
            continue
        for value, ok in _probes(key):
            d = {**_base(table, config), key.name: value}
            assert _reads(config, table, d) is ok, (table, key.name, value, ok)


def test_keys_read_by_hand_are_still_read_by_hand_and_stated_rightly():
    from imunav.core.validation import ImunavError
    from imunav.sensors.aids.config import SECTIONS
    assert aidkeys.READ_BY_HAND == {("mounting", "time_offset"): "any sign, within ±1e6"}
    config = SECTIONS["mounting"]
    key = next(k for k in config.FIELDS if k.name == "time_offset")
    with pytest.raises(ImunavError):        # its Key alone would refuse a negative offset …
        key.read({"time_offset": -0.2}, "mounting")
    for value, ok in ((-0.2, True), (-1e6, True), (1e6, True), (1.1e6, False), (-1.1e6, False)):
        assert _reads(config, "mounting", {"time_offset": value}) is ok, value   # … the table not


def test_the_aiding_files_table_lists_every_aid_file():
    from imunav.sensors.aids import AIDS
    text = FORMATS_PAGE.read_text(encoding="utf-8")
    section = text.split("(aiding-files)=")[1].split("(rtklib-files)=")[0]
    rows = [line for line in section.splitlines() if line.startswith("| `")]
    for spec in AIDS.values():
        mine = " ".join(r for r in rows if r.startswith(f"| `{spec.file}`"))
        assert mine, f"docs/formats.md: no row for {spec.file}"
        for frame, headers in spec.headers.items():
            for h in headers:
                assert f"`{','.join(h)}`" in mine, (spec.file, frame, h)


# ------------------------------------------------- the guide's worked example of an own aid

def test_the_own_aid_example_prints_what_it_shows():
    text = (ROOT / "docs" / "guide_aided.md").read_text(encoding="utf-8")
    section = text.split("(write-your-own-aid)=")[1].split("\n## ")[1]
    blocks = _blocks(section)
    (lang, code, _), (_, shown, _) = blocks[0], blocks[1]
    assert lang == "python" and "class WheelSpeed(Measurement)" in code
    env = {k: v for k, v in os.environ.items() if k != "PYTHONWARNINGS"}
    run = subprocess.run([sys.executable, "-W", "error::DeprecationWarning", "-c", code],
                         cwd=ROOT, env=env, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stderr
    assert run.stdout == shown
