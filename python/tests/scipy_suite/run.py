"""SciPy's own interpolate tests run against `splinegpu.interpolate`.

    python python/tests/scipy_suite/run.py [--check] [--update] [--failures]

Takes the installed SciPy's test files (scipy/interpolate/tests: test_bsplines.py,
test_polyint.py, test_interpolate.py, test_rgi.py, test_fitpack2.py, test_fitpack.py), keeps the
tests that exercise a name `splinegpu.interpolate` exports (their code, their helpers' code or
their parameters name it; plugin.py decides), and runs them twice in pytest: once as SciPy ships
them, once with those names imported from `splinegpu.interpolate` (every other name stays
SciPy's).
Each session runs in its own interpreter with a per-test timeout; one that dies (a crash, a
hang's timeout) is started again past the test it died in, which counts as failed. Prints, per
file, the tests splinegpu passes against those SciPy passes.

--check fails (exit 1) when a file's count falls below ratchet.json's, a test SciPy passes
fails here without an entry in expected_failures.txt (each entry: the test's id, " | ", and
the difference python/README.md's coverage table states), or the installed SciPy is not the
one the ratchet was made against (python/pyproject.toml pins it). --update raises
ratchet.json to the counts reached. --failures lists each failing test with its first error.
"""

from __future__ import annotations

import argparse
import ast
import json
import os
import shutil
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

HERE = Path(__file__).resolve().parent
FILES = ("test_bsplines.py", "test_polyint.py", "test_interpolate.py", "test_rgi.py",
         "test_fitpack2.py", "test_fitpack.py")
# Where the test files import the names from.
MODULES = ("scipy.interpolate", "scipy.interpolate._fitpack2", "scipy.interpolate._rgi",
           "scipy.interpolate._ndbspline", "scipy.interpolate._fitpack_py")
RATCHET = HERE / "ratchet.json"
EXPECTED = HERE / "expected_failures.txt"


def scipy_tests() -> Path:
    import scipy.interpolate

    return Path(scipy.interpolate.__file__).parent / "tests"


def overridden_names(source: str) -> list:
    """The names a test file imports from scipy.interpolate (or the private module that
    defines them) that splinegpu.interpolate exports."""
    import splinegpu.interpolate as ours

    imported = set()
    for node in ast.parse(source).body:
        if isinstance(node, ast.ImportFrom) and node.module in MODULES:
            imported |= {alias.asname or alias.name for alias in node.names
                         if alias.name == (alias.asname or alias.name)}
    return sorted(imported & set(ours.__all__))


def with_our_names(source: str, names: list) -> str:
    """The file with an import of `names` from splinegpu.interpolate after its last import that
    precedes the first definition (so that parametrize lists built at import see them)."""
    lines = source.splitlines(keepends=True)
    after = 0
    for node in ast.parse(source).body:
        if isinstance(node, ast.FunctionDef | ast.ClassDef):
            break
        if isinstance(node, ast.Import | ast.ImportFrom):
            after = node.end_lineno
    line = f"from splinegpu.interpolate import {', '.join(names)}  # the suite runner\n"
    return "".join([*lines[:after], line, *lines[after:]])


# SciPy's fixtures (xp and its marks), and its array-API table answering for our classes as it
# does for SciPy's of the same name (make_xp_test_case looks them up while a file imports).
CONFTEST = """\
from scipy.conftest import *  # noqa: F403
import scipy.interpolate
import splinegpu.interpolate
from scipy._lib._array_api import xp_capabilities_table

for name in splinegpu.interpolate.__all__:
    theirs = getattr(scipy.interpolate, name, None)
    if theirs in xp_capabilities_table:
        xp_capabilities_table[getattr(splinegpu.interpolate, name)] = xp_capabilities_table[theirs]
"""


def prepare(folder: Path, ours: bool) -> dict:
    """The test files (rewritten for splinegpu when `ours`), SciPy's conftest and data, and the
    plugin, in `folder`; returns each file's overridden names."""
    tests = scipy_tests()
    folder.mkdir(parents=True)
    names = {}
    for name in FILES:
        source = (tests / name).read_text(encoding="utf-8")
        names[name] = overridden_names(source)
        (folder / name).write_text(with_our_names(source, names[name]) if ours else source,
                                   encoding="utf-8")
    (folder / "data").symlink_to(tests / "data")
    (folder / "conftest.py").write_text(CONFTEST, encoding="utf-8")
    shutil.copy(HERE / "plugin.py", folder / "suite_plugin.py")
    return names


def run_session(folder: Path, names: dict, timeout: float, files=FILES) -> dict:
    """Every selected test's outcome and first error, by id, of the test `files` in `folder`;
    sessions restarted past a test whose interpreter died."""
    log, done = folder / "log.jsonl", folder / "done.txt"
    outcomes: dict = {}
    every = sorted({n for file_names in names.values() for n in file_names})
    while True:
        done.write_text("".join(f"{i}\n" for i in outcomes), encoding="utf-8")
        log.write_text("", encoding="utf-8")
        command = [sys.executable, "-m", "pytest", "-q", "-p", "suite_plugin",
                   "-p", "no:cacheprovider", "-W", "ignore", "--tb=line",
                   f"--suite-log={log}", f"--suite-names={','.join(every)}",
                   f"--suite-done={done}", f"--suite-timeout={timeout}", *files]
        env = dict(os.environ, PYTHONPATH=str(folder), PYTHONFAULTHANDLER="1")
        subprocess.run(command, cwd=folder, env=env, stdout=subprocess.DEVNULL,
                       stderr=subprocess.DEVNULL, check=False)
        started, finished = None, False
        for line in log.read_text(encoding="utf-8").splitlines():
            record = json.loads(line)
            if record["event"] == "start":
                started = record["id"]
            elif record["event"] == "end":
                outcomes[record["id"]] = (record["outcome"], record["message"])
                started = None
            elif record["event"] == "finished":
                finished = True
        if finished or started is None:
            return outcomes
        outcomes[started] = ("failed", "the interpreter died (a crash or the timeout)")


def run(timeout: float) -> tuple:
    with tempfile.TemporaryDirectory(prefix="scipy-suite-") as tmp:
        folders = {"scipy": Path(tmp) / "scipy", "ours": Path(tmp) / "splinegpu"}
        names = {key: prepare(folder, key == "ours") for key, folder in folders.items()}
        with ThreadPoolExecutor(2) as pool:
            futures = {key: pool.submit(run_session, folders[key], names[key], timeout)
                       for key in folders}
            return futures["scipy"].result(), futures["ours"].result()


def expected_failures() -> dict:
    entries = {}
    for line in EXPECTED.read_text(encoding="utf-8").splitlines():
        if line.strip() and not line.startswith("#"):
            test, _, reason = line.partition(" | ")
            entries[test.strip()] = reason.strip()
    return entries


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true")
    parser.add_argument("--update", action="store_true")
    parser.add_argument("--failures", action="store_true")
    parser.add_argument("--timeout", type=float, default=120.0)
    parser.add_argument("--json", help="write every test's outcomes here")
    args = parser.parse_args()
    scipy, ours = run(args.timeout)
    if args.json:
        Path(args.json).write_text(json.dumps({"scipy": scipy, "splinegpu": ours}, indent=1),
                                   encoding="utf-8")
    expected = expected_failures()
    ratchet = json.loads(RATCHET.read_text(encoding="utf-8"))
    from scipy import __version__ as version

    if ratchet.get("scipy") != version:
        # Another release's test files: the counts and the ids do not compare.
        print(f"the ratchet was made against SciPy {ratchet.get('scipy')}, this is SciPy "
              f"{version} (python/pyproject.toml pins the tests' SciPy)",
              file=sys.stderr)
        if args.check and not args.update:
            return 1
    counts, problems = {}, []
    print(f"{'file':<22}{'splinegpu':>10}{'SciPy':>8}{'ratchet':>9}")
    for name in FILES:
        scipy_passes = [i for i, (o, _) in scipy.items() if i.startswith(name) and o == "passed"]
        ours_passes = [i for i in scipy_passes if ours.get(i, ("missing",))[0] == "passed"]
        counts[name] = len(ours_passes)
        print(f"{name:<22}{len(ours_passes):>10}{len(scipy_passes):>8}{ratchet.get(name, 0):>9}")
        if len(ours_passes) < ratchet.get(name, 0):
            problems.append(f"{name}: {len(ours_passes)} pass, below the ratchet's "
                            f"{ratchet[name]}")
        for test in sorted(set(scipy_passes) - set(ours_passes)):
            outcome, message = ours.get(test, ("missing", ""))
            message = (message.strip().splitlines() or [""])[0]
            known = test in expected
            if args.failures or not known:
                print(f"  {'expected' if known else 'FAILS'}: {test}: {outcome}: {message}")
            if not known:
                problems.append(f"{test} fails without an entry in {EXPECTED.name}")
    total_ours, total_scipy = sum(counts.values()), sum(
        1 for o, _ in scipy.values() if o == "passed")
    print(f"{'total':<22}{total_ours:>10}{total_scipy:>8} "
          f"({100 * total_ours / max(total_scipy, 1):.1f}%)")
    stale = [t for t in expected if ours.get(t, ("passed",))[0] == "passed"]
    for test in stale:
        problems.append(f"{test} is listed in {EXPECTED.name} but passes (or is not selected)")
    if args.update:
        raised = {k: max(v, ratchet.get(k, 0)) for k, v in counts.items()}
        raised["scipy"] = version
        RATCHET.write_text(json.dumps(raised, indent=1) + "\n", encoding="utf-8")
    if args.check and problems:
        print("\n".join(problems), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
