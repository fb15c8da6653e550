"""Shared pytest fixtures: paths, the C suite build, reference data."""
import contextlib
import os
import pathlib
import subprocess

import matplotlib
import pytest

import expected_warnings

matplotlib.use("Agg")

ROOT = pathlib.Path(__file__).resolve().parent.parent
DATA = ROOT / "tests" / "data" / "reference.dat"


def load_reference(path=DATA):
    """The reference numbers shared with the C suite: {key: value}."""
    refs = {}
    for line in path.read_text().splitlines():
        line = line.split("#", 1)[0].split()
        if len(line) >= 2:
            refs[line[0]] = float(line[1])
    return refs


@pytest.fixture(scope="session")
def ref():
    return load_reference()


@pytest.fixture(scope="session")
def c_suite():
    """Build the C suite and run it once with --values: (returncode, stdout)."""
    env = dict(os.environ)
    build = subprocess.run(["make", "-s", "-C", str(ROOT / "csrc"), "all"], capture_output=True, text=True, env=env)
    assert build.returncode == 0, f"C suite build failed:\n{build.stdout}\n{build.stderr}"
    run = subprocess.run([str(ROOT / "csrc" / "build" / "run_tests"), "--data", str(DATA), "--values"],
                         capture_output=True, text=True, cwd=str(ROOT / "csrc"), timeout=600)
    return run.returncode, run.stdout


# ----------------------------------------------------------------- warnings
# A test's scenes may warn by design (tests/expected_warnings.py); the log
# keeps only warnings nobody declared, and the run fails when more than
# WARNINGS_LIMIT of them are left: each one is news.

WARNINGS_LIMIT = 10
_undeclared = []


def _by_design(item):
    """The item's declared kinds as a context (its fixtures' set-up and the call)."""
    kinds = [k for m in item.iter_markers("warns_by_design") for k in m.args]
    return expected_warnings.by_design(*kinds) if kinds else contextlib.nullcontext()


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_setup(item):
    with _by_design(item):
        yield


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_call(item):
    with _by_design(item):
        yield


def pytest_warning_recorded(warning_message, when, nodeid, location):
    _undeclared.append((nodeid, warning_message))


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    n = len(_undeclared)
    if n > WARNINGS_LIMIT:
        terminalreporter.write_line(
            f"{n} warnings were issued that no test declared (limit {WARNINGS_LIMIT}): a test that is about a "
            "warning asserts it with pytest.warns; scenes that warn by design say so with "
            "@pytest.mark.warns_by_design (tests/expected_warnings.py)", red=True)


def pytest_sessionfinish(session, exitstatus):
    if len(_undeclared) > WARNINGS_LIMIT and exitstatus == 0:
        session.exitstatus = 1
