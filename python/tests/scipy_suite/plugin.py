"""pytest plugin of the SciPy-suite runner (run_scipy_suite.py), loaded with `-p plugin` in
the folder the runner prepares. It keeps the tests that exercise a name splinegpu.interpolate
overrides, arms a per-test timeout, skips the tests an earlier, crashed session already
answered, and writes one JSON line per event to the log the runner reads, flushed as it goes,
so that a session that dies (a crash, a timeout's exit) still says where it stopped."""

from __future__ import annotations

import faulthandler
import json
import os
import types

import pytest

_LOG = None


def pytest_addoption(parser):
    parser.addoption("--suite-log", help="file the runner reads (JSON lines)")
    parser.addoption("--suite-names", default="", help="names splinegpu overrides, by commas")
    parser.addoption("--suite-done", help="file of test ids already answered, one a line")
    parser.addoption("--suite-timeout", type=float, default=120.0, help="seconds per test")


def _write(record: dict) -> None:
    _LOG.write(json.dumps(record) + "\n")
    _LOG.flush()
    os.fsync(_LOG.fileno())


def pytest_configure(config):
    global _LOG
    _LOG = open(config.getoption("--suite-log"), "a", encoding="utf-8")


def _loaded_names(obj, module, seen: set) -> set:
    """Every global or attribute name a function's code (its nested code too) loads, followed
    into the test module's own functions and classes and the test class's own methods."""
    if id(obj) in seen:
        return set()
    seen.add(id(obj))
    names: set = set()
    if isinstance(obj, type):
        for value in vars(obj).values():
            value = getattr(value, "__func__", value)
            if isinstance(value, types.FunctionType | type):
                names |= _loaded_names(value, module, seen)
        return names
    code = getattr(obj, "__code__", None)
    if code is None:
        return names
    stack = [code]
    while stack:
        c = stack.pop()
        names.update(c.co_names)
        stack.extend(k for k in c.co_consts if isinstance(k, types.CodeType))
    for name in list(names):
        value = getattr(module, name, None)
        if (isinstance(value, types.FunctionType | type)
                and getattr(value, "__module__", None) == module.__name__):
            names |= _loaded_names(value, module, seen)
    return names


def _mentions(value, overridden: set) -> bool:
    if isinstance(value, list | tuple | set):
        return any(_mentions(v, overridden) for v in value)
    return getattr(value, "__name__", None) in overridden and callable(value)


def _exercises(item, overridden: set) -> bool:
    module = item.module
    seen: set = set()
    names = _loaded_names(item.function, module, seen)
    if item.cls is not None:
        # A test's helpers are its class's methods and fixtures (self.helper loads "helper").
        for attribute in list(names):
            value = getattr(item.cls, attribute, None)
            value = getattr(value, "__func__", value)
            if isinstance(value, types.FunctionType):
                names |= _loaded_names(value, module, seen)
    for fixture in item.fixturenames:
        value = getattr(module, fixture, None) or getattr(item.cls, fixture, None)
        value = getattr(value, "__wrapped__", value)
        if isinstance(value, types.FunctionType):
            names |= _loaded_names(value, module, seen)
    if names & overridden:
        return True
    callspec = getattr(item, "callspec", None)
    return callspec is not None and any(_mentions(v, overridden)
                                        for v in callspec.params.values())


def pytest_collection_modifyitems(config, items):
    overridden = set(filter(None, config.getoption("--suite-names").split(",")))
    done_file = config.getoption("--suite-done")
    done = set()
    if done_file and os.path.exists(done_file):
        with open(done_file, encoding="utf-8") as f:
            done = {line.rstrip("\n") for line in f}
    keep, drop = [], []
    for item in items:
        (keep if _exercises(item, overridden) and item.nodeid not in done else drop).append(item)
    if drop:
        config.hook.pytest_deselected(items=drop)
    items[:] = keep
    _write({"event": "collected", "ids": [item.nodeid for item in keep]})


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    _write({"event": "start", "id": item.nodeid})
    faulthandler.dump_traceback_later(item.config.getoption("--suite-timeout"), exit=True)
    item.suite_outcome = "passed"
    item.suite_message = ""
    yield
    faulthandler.cancel_dump_traceback_later()
    _write({"event": "end", "id": item.nodeid, "outcome": item.suite_outcome,
            "message": item.suite_message[:500]})


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    report = outcome.get_result()
    if hasattr(report, "wasxfail"):
        # xfail and xpass count as SciPy's run counts them: neither is a pass.
        item.suite_outcome = "xfailed" if report.skipped else "xpassed"
    elif report.failed:
        item.suite_outcome = "failed"
        crash = getattr(report.longrepr, "reprcrash", None)
        item.suite_message = crash.message if crash is not None else str(report.longrepr)
    elif report.skipped and item.suite_outcome == "passed":
        item.suite_outcome = "skipped"


def pytest_sessionfinish(session, exitstatus):
    _write({"event": "finished"})
