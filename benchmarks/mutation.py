"""``make mutation``: mutation testing of the core and analysis layers with mutmut 3.

    python benchmarks/mutation.py run [--jobs N]   mutate, run the unit suite per mutant, report
    python benchmarks/mutation.py report           the score from the stored results (mutants/)
    python benchmarks/mutation.py diffs [TEXT]     the diff of every survivor whose name has TEXT

What is mutated and which tests run is configured in ``[tool.mutmut]`` of pyproject.toml
(imunav/core and imunav/analysis; the whole unit suite, mutmut choosing per mutant the tests
that reach the mutated function; tests/conftest.py runs them fastest first). Two passes: the
first leaves out the tests that took over ``--cap`` seconds (default 1), the second runs the
survivors of the first against every test up to ``--cap2`` seconds (default 3: the 10 slower
tests — the two Monte Carlo agreements, the Allan fits, the layering scan, the fuzzers — take
58 s of the suite's 97 s and would cost every surviving mutant that much again).

Score = killed / (all mutants − equivalent ones). A mutant counts as killed when a test fails,
errors or times out; it survives when every test passes or no test reaches it. Every survivor
must be listed in tests/MUTATION.md, under "Equivalent" (no observable change: not counted) or
"Accepted" (a real change no test catches, with the reason: counted as surviving). The report
exits 1 when the score is below 90 % or a survivor is not listed. Survivors, with their diffs,
go to build/mutation/survivors.txt.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import time
from collections import Counter
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LEDGER = ROOT / "tests" / "MUTATION.md"
OUT = ROOT / "build" / "mutation" / "survivors.txt"
TARGET = 0.90
NAME = re.compile(r"imunav\.[\w.ǁ]+__mutmut_\d+")
KILLED = {"killed", "timeout", "segfault", "caught by type check"}


def _results() -> dict[str, str]:
    """Status of every mutant, from mutmut's stored results."""
    from mutmut.mutation.data import SourceFileMutationData
    from mutmut.stats import status_by_exit_code
    from mutmut.utils.file_utils import walk_mutatable_files

    out = {}
    for path in walk_mutatable_files():
        m = SourceFileMutationData(path=path)
        m.load()
        for name, code in m.exit_code_by_key.items():
            out[name] = status_by_exit_code[code]
    return out


def _ledger() -> dict[str, str]:
    """Mutant name → "equivalent" or "accepted", from tests/MUTATION.md's two sections."""
    out, section = {}, None
    for line in LEDGER.read_text(encoding="utf-8").splitlines():
        if line.startswith("## "):
            head = line[3:].strip().lower()
            section = ("equivalent" if head.startswith("equivalent")
                       else "accepted" if head.startswith("accepted") else None)
            continue
        if section:
            for name in NAME.findall(line):
                out[name] = section
    return out


def _diff(name: str) -> str:
    from mutmut.mutation.diff_apply import get_diff_for_mutant

    try:
        return get_diff_for_mutant(name)
    except Exception as exc:  # noqa: BLE001 - a report line, not a failure
        return f"(no diff: {exc})"


def report() -> int:
    os.chdir(ROOT)
    results = _results()
    if not results:
        print("mutation: no results in mutants/ (run `make mutation` first)")
        return 1
    ledger = _ledger()
    status = Counter(results.values())
    killed = sum(n for s, n in status.items() if s in KILLED)
    unchecked = status.get("not checked", 0)
    survivors = sorted(k for k, s in results.items() if s not in KILLED and s != "not checked")
    equivalent = [k for k in survivors if ledger.get(k) == "equivalent"]
    accepted = [k for k in survivors if ledger.get(k) == "accepted"]
    unlisted = [k for k in survivors if k not in ledger]
    stale = sorted(k for k in ledger if results.get(k, "killed") in KILLED)
    counted = len(results) - unchecked - len(equivalent)
    score = killed / counted if counted else 0.0

    OUT.parent.mkdir(parents=True, exist_ok=True)
    with OUT.open("w", encoding="utf-8") as f:
        for k in survivors:
            f.write(f"# {k}: {results[k]} [{ledger.get(k, 'NOT LISTED')}]\n{_diff(k)}\n\n")

    print(f"mutants: {len(results)}  " + "  ".join(f"{s}: {n}" for s, n in sorted(status.items())))
    print(f"survivors: {len(survivors)} (equivalent {len(equivalent)}, accepted {len(accepted)}, "
          f"not listed in tests/MUTATION.md {len(unlisted)}) → {OUT.relative_to(ROOT)}")
    if stale:
        print(f"listed in tests/MUTATION.md but now killed: {len(stale)} (remove them)")
    print(f"mutation score: {killed}/{counted} = {100 * score:.1f} % of non-equivalent mutants "
          f"killed (target {100 * TARGET:.0f} %)")
    if unchecked:
        print(f"not checked yet: {unchecked}")
    ok = score >= TARGET and not unlisted and not unchecked
    return 0 if ok else 1


def diffs(text: str) -> int:
    os.chdir(ROOT)
    ledger = _ledger()
    for k, s in sorted(_results().items()):
        if s not in KILLED and s != "not checked" and text in k and k not in ledger:
            print(f"# {k}: {s}\n{_diff(k)}\n")
    return 0


def run(jobs: int, cap: float, cap2: float) -> int:
    """Pass 1: every mutant, the tests that took ≤ ``cap`` s. Pass 2: the survivors again, the
    tests that took ≤ ``cap2`` s."""
    os.chdir(ROOT)
    env = dict(os.environ, MPLBACKEND="Agg", IMUNAV_MUTATION_TEST_CAP=str(cap))
    mutmut = [sys.executable, "-m", "mutmut", "run", "--max-children", str(jobs)]
    t0 = time.perf_counter()
    rc = subprocess.call(mutmut, env=env)
    t1 = time.perf_counter()
    print(f"\npass 1 (tests ≤ {cap:g} s): exit {rc} in {t1 - t0:.0f} s")
    if rc:
        return rc
    again = sorted(k for k, s in _results().items() if s not in KILLED)
    if again:
        print(f"pass 2: {len(again)} survivors of pass 1 against the tests ≤ {cap2:g} s")
        env["IMUNAV_MUTATION_TEST_CAP"] = str(cap2)
        rc = subprocess.call(mutmut + again, env=env)
        print(f"\npass 2: exit {rc} in {time.perf_counter() - t1:.0f} s")
        if rc:
            return rc
    print(f"mutation run: {time.perf_counter() - t0:.0f} s in all")
    return report()


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run")
    r.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    r.add_argument("--cap", type=float, default=1.0,
                   help="pass 1 leaves out tests that took longer than this (s)")
    r.add_argument("--cap2", type=float, default=3.0,
                   help="pass 2 leaves out tests that took longer than this (s); inf: none")
    sub.add_parser("report")
    d = sub.add_parser("diffs")
    d.add_argument("text", nargs="?", default="")
    a = p.parse_args(argv)
    if a.cmd == "run":
        return run(a.jobs, a.cap, a.cap2)
    if a.cmd == "report":
        return report()
    return diffs(a.text)


if __name__ == "__main__":
    sys.exit(main())
