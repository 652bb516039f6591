"""The book's command-line reference, generated from imunav's own argument parser.

``docs/cli.md`` writes, for each command, a directive::

    ```{imunav-cli} simulate
    ```

which this Sphinx extension replaces, when the book is built, by the command's one-line
summary, its usage line and a table of every option (flag, value, required or default, choices,
help) read from :func:`imunav.cli.build_parser` — the parser ``imunav`` itself runs, so the
reference cannot drift from the program. ``{imunav-cli} imunav`` gives the top-level options.

The directive's content adds a page note to an option, one per line, ``--flag: text`` (MyST
inline markup; continuation lines indented), shown after the parser's own help — for the
options whose parser help is short or missing. A note for an option the parser does not have
fails the build (``make book`` runs Sphinx with ``-W``). ``tests/package/test_docs.py`` checks
:func:`options` against ``imunav <command> --help``, that ``docs/cli.md`` has a directive for
every command, and that every option without parser help has a note.

The pure functions (:func:`commands`, :func:`usage`, :func:`options`) need only argparse and
imunav; the directive needs docutils and Sphinx (``make book``).
"""

from __future__ import annotations

import argparse
import re

from docutils import nodes
from sphinx.util.docutils import SphinxDirective

from imunav.cli import build_parser

#: Width of the generated usage lines (characters).
WIDTH = 92


def commands(parser: argparse.ArgumentParser | None = None) -> dict[str, tuple[argparse.ArgumentParser, str]]:
    """Every command of ``imunav``: name → (its parser, its one-line summary); ``"imunav"`` is
    the top level (``--version``, ``--help``)."""
    parser = parser or build_parser()
    out = {"imunav": (parser, parser.description or "")}
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            helps = {a.dest: a.help or "" for a in action._choices_actions}
            for name, sub in action.choices.items():
                out[name] = (sub, helps.get(name, ""))
    return out


def usage(parser: argparse.ArgumentParser) -> str:
    """The usage line as ``--help`` prints it, at a fixed width (not the terminal's)."""
    formatter = argparse.HelpFormatter(parser.prog, width=WIDTH)
    formatter.add_usage(parser.usage, parser._actions, parser._mutually_exclusive_groups)
    return formatter.format_help().strip()


def _value(action: argparse.Action) -> str:
    if action.nargs == 0:
        return ""
    if action.metavar is not None:
        return str(action.metavar)
    if action.choices is not None:
        return "{" + ",".join(map(str, action.choices)) + "}"
    return action.dest.upper()


def options(parser: argparse.ArgumentParser) -> list[dict]:
    """One row per argument: ``flags`` (the option strings, or the positional's name),
    ``value`` (what follows the flag), ``required``, ``default``, ``choices``, ``help``."""
    rows = []
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            continue
        positional = not action.option_strings
        default = action.default
        if default is None or default is argparse.SUPPRESS or action.nargs == 0:
            default = None                      # (0 is a default: not `in (None, False)`)
        rows.append({
            "flags": list(action.option_strings) or [_value(action)],
            "value": "" if positional else _value(action),
            "required": positional or action.required,
            "default": default,
            "choices": list(action.choices) if action.choices is not None else None,
            "help": " ".join((action.help or "").split()),
        })
    return rows


def notes(lines: list[str]) -> dict[str, str]:
    """The page notes of a directive's content: ``--flag: text`` lines (continuations indented)
    → {flag: text}."""
    out: dict[str, str] = {}
    key = None
    for line in lines:
        if not line.strip():
            continue
        if line[:1].isspace() and key is not None:
            out[key] += " " + line.strip()
            continue
        key, sep, text = line.partition(": ")
        if not sep:
            raise ValueError(f"a note is '--flag: text', got {line!r}")
        key = key.strip()
        out[key] = text.strip()
    return out


def _para(*parts) -> nodes.paragraph:
    p = nodes.paragraph()
    for part in parts:
        p += part
    return p


#: An option named in running text (``--imu``), set as code so that smart quotes leave it be.
FLAG = re.compile(r"(?<![\w-])(--?[A-Za-z][\w-]*)")


def _text(text: str) -> list[nodes.Node]:
    """Plain text with the options it names as inline literals."""
    out: list[nodes.Node] = []
    for i, part in enumerate(FLAG.split(text)):
        if part:
            out.append(nodes.literal(text=part) if i % 2 else nodes.Text(part))
    return out


def _sentence(text: str) -> str:
    text = text.strip()
    if not text:
        return text
    text = text[0].upper() + text[1:]
    return text if text.endswith((".", "?", "!")) else text + "."


def describe(row: dict) -> tuple[str, list[str]]:
    """The parser's own words on one option: its help as a sentence ("" without help), and
    what the help leaves unsaid (required, the choices, the default) as sentences."""
    out: list[str] = []
    said = row["help"].lower()
    if row["required"] and row["value"]:
        out.append("Required.")
    if row["choices"] and row["value"] and not row["value"].startswith("{"):
        if not all(str(c) in row["help"] for c in row["choices"]):
            out.append("One of " + ", ".join(map(str, row["choices"])) + ".")
    if row["default"] is not None and "default" not in said:
        out.append(f"Default {row['default']}.")
    return _sentence(row["help"]), out


def _table(rows: list[dict], note_nodes: dict) -> nodes.table:
    table = nodes.table(classes=["imunav-cli-options"])
    group = nodes.tgroup(cols=3)
    table += group
    for width in (24, 16, 60):
        group += nodes.colspec(colwidth=width)
    head = nodes.thead()
    group += head
    row = nodes.row()
    for title in ("option", "value", "what it does"):
        row += nodes.entry("", _para(nodes.Text(title)))
    head += row
    body = nodes.tbody()
    group += body
    for r in rows:
        row = nodes.row()
        flags = []
        for i, flag in enumerate(r["flags"]):
            if i:
                flags.append(nodes.Text(", "))
            flags.append(nodes.literal(text=flag))
        row += nodes.entry("", _para(*flags))
        row += nodes.entry("", _para(nodes.literal(text=r["value"])) if r["value"] else _para())
        help_, extras = describe(r)
        cell: list[nodes.Node] = _text(help_)
        for flag in r["flags"]:
            if flag in note_nodes:
                cell += [nodes.Text(" " if cell else ""), *note_nodes[flag]]
        for sentence in extras:
            cell += [nodes.Text(" " if cell else ""), *_text(sentence)]
        row += nodes.entry("", _para(*cell))
        body += row
    return table


class CliDirective(SphinxDirective):
    """``{imunav-cli} COMMAND``: the summary, usage and options of one command."""

    required_arguments = 1
    has_content = True

    def run(self) -> list[nodes.Node]:
        name = self.arguments[0]
        table = commands()
        if name not in table:
            raise self.error(f"imunav-cli: no command {name!r} (known: {', '.join(table)})")
        parser, summary = table[name]
        try:
            page = notes(list(self.content))
        except ValueError as exc:
            raise self.error(f"imunav-cli {name}: {exc}") from None
        known = {f for r in options(parser) for f in r["flags"]}
        unknown = sorted(set(page) - known)
        if unknown:
            raise self.error(f"imunav-cli {name}: notes for options the parser does not have: "
                             f"{', '.join(unknown)}")
        note_nodes = {flag: self.parse_inline(text, lineno=self.lineno)[0]
                      for flag, text in page.items()}
        out: list[nodes.Node] = []
        if summary and name != "imunav":
            out.append(_para(nodes.emphasis("", "", *_text(_sentence(summary)))))
        text = usage(parser)
        out.append(nodes.literal_block(text, text, language="text"))
        out.append(_table(options(parser), note_nodes))
        return out


def setup(app):
    app.add_directive("imunav-cli", CliDirective)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
