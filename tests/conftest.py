"""Shared pytest fixtures: paths, the C suite build, reference data."""
import os
import pathlib
import subprocess

import matplotlib
import pytest

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
