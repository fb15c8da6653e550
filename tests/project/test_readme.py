"""README.md and benchmarks/README.md against fresh runs.

* README.md stays short (at most 300 lines) and speaks about the product, not
  about how it was developed.
* The quick start runs, and every number of its printed output matches the
  README. Tolerance: half a unit in the last digit the README shows (the README
  shows rounded output, nothing more is claimed).
* The `exdex paper` table: each row's exdex and closed-form values against a
  fresh ``exdex.paper.run_case`` (the function behind the command), same
  tolerance rule.
* The other Python blocks of the README run, and the batch shape its comment
  states is the shape returned.
* benchmarks/README.md quotes its headline and stability figures from the
  files ``exdex bench`` wrote to benchmarks/results/: every number in those
  tables must be in the files, and the stability counts must equal the
  summary's.
"""
import contextlib
import io
import math
import os
import re

import numpy as np
import pytest

import exdex
from exdex import paper

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
NUM = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"


def _read(*path):
    with open(os.path.join(ROOT, *path), encoding="utf-8") as f:
        return f.read()


README = _read("README.md")
BENCH = _read("benchmarks", "README.md")


def _section(text, title):
    # sections are "## ..." headings; "# ..." lines inside code blocks are comments
    m = re.search(rf"^##+ {re.escape(title)}.*?$(.*?)(?=^##+ |\Z)", text, re.M | re.S)
    assert m, f"section {title!r} not found"
    return m.group(1)


def _blocks(text, lang):
    return re.findall(rf"```{lang}\n(.*?)```", text, re.S)


def _close(readme_value: str, fresh: float) -> bool:
    """|fresh - shown| <= half a unit in the shown value's last digit."""
    shown = float(readme_value)
    mant = readme_value.lower().split("e")[0]
    decimals = len(mant.split(".")[1]) if "." in mant else 0
    exp = int(readme_value.lower().split("e")[1]) if "e" in readme_value.lower() else 0
    tol = 0.5 * 10.0 ** (exp - decimals)
    return abs(fresh - shown) <= tol * (1 + 1e-12)


def test_readme_is_short_and_about_the_product():
    n = README.count("\n")
    print("README.md lines:", n)
    assert n <= 300
    history = re.compile(r"\b(this session|session|previously|no longer|used to|earlier version|issue \d+|"
                         r"was fixed|we fixed|since this)\b", re.I)
    for name, text in (("README.md", README), ("benchmarks/README.md", BENCH)):
        hits = [m.group(0) for m in history.finditer(text)]
        assert not hits, f"{name} talks about the development history: {hits}"


def test_quick_start_prints_what_the_readme_says():
    sec = _section(README, "Quick start")
    code = _blocks(sec, "python")[0]
    shown = _blocks(sec, "text")[0]
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, "README quick start", "exec"), {})
    fresh = out.getvalue()
    shown_lines, fresh_lines = shown.strip().splitlines(), fresh.strip().splitlines()
    assert len(shown_lines) == len(fresh_lines), fresh
    for s, f in zip(shown_lines, fresh_lines):
        assert re.sub(NUM, "#", s) == re.sub(NUM, "#", f), (s, f)     # same words
        for a, b in zip(re.findall(NUM, s), re.findall(NUM, f)):
            assert _close(a, float(b)), f"README says {a}, a fresh run prints {b}: {f!r}"
    # the worked e_r is the closed form of a 1 x 2 cm rectangle (tests/scenarios/test_sizes.py derives it)
    a, b = 0.005, 0.01
    d = math.hypot(a, b)
    er = (a * b * d / 3 + a**3 / 6 * math.log((b + d) / a) + b**3 / 6 * math.log((a + d) / b)) / (a * b)
    assert _close(re.search(r"e_r of the pad: (" + NUM + ")", shown).group(1), 1e3 * er)


def _paper_rows():
    table = _section(README, "The two commands")
    rows = []
    for line in table.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 5 and cells[0].startswith("Fig."):
            rows.append(cells)
    return rows


def test_paper_table_matches_a_fresh_run():
    rows = _paper_rows()
    assert len(rows) == 4
    fresh = {}
    for case in paper.CASES:
        for r in paper.run_case(case).rows:
            fresh[(r["case"], r["quantity"])] = r
    for case, quantity, paper_value, exdex_value, reference in rows:
        r = fresh[(case, quantity)]
        assert _close(exdex_value, float(r["exdex"])), (case, quantity, exdex_value, r["exdex"])
        assert _close(reference, float(r["reference"])), (case, quantity, reference, r["reference"])
        if paper_value != "-":
            assert _close(paper_value, float(r["paper"])), (case, quantity, paper_value, r["paper"])
    # the Fig. 6 bound quoted under the table: 2 theta1 (2 beta - 1) / beta with Eq. 7's beta 0.7, 100 deg
    bound = re.search(r"2 theta1 \(2 beta - 1\) / beta = (" + NUM + ") deg", README).group(1)
    assert _close(bound, math.degrees(paper.fig6_rotation_bound()))


@pytest.mark.warns_by_design("outline")
def test_other_readme_code_runs():
    blocks = _blocks(README, "python")[1:]
    assert len(blocks) >= 2
    scope = {}
    with contextlib.redirect_stdout(io.StringIO()):
        exec(compile(_blocks(README, "python")[0], "README quick start", "exec"), scope)
    for i, code in enumerate(blocks):
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            exec(compile(code, f"README block {i + 1}", "exec"), scope)
        # a comment quoting what the block prints ("# e.g. "..., ..."") must be in its output
        for quoted in re.findall(r'# e\.g\. "(.*?)(?:, \.\.\.)?"', code):
            assert quoted in out.getvalue(), f"README block {i + 1} says it prints {quoted!r}; it printed " \
                                             f"{out.getvalue()[:300]!r}"
    shape = re.search(r'b\.gridded\("final_displacement"\)\s*# \((\d+), (\d+), (\d+)\)', README)
    assert scope["b"].gridded("final_displacement").shape == tuple(int(x) for x in shape.groups())
    assert np.all(np.isfinite(scope["b"].final_displacement))
    # the runs the batch's warning counts are marked, and the grid has NaN there only
    grid = scope["b"].gridded("final_displacement")
    assert "NaN where b.valid is False" in README and not scope["b"].valid.all()
    np.testing.assert_array_equal(np.isnan(grid[..., 0]).ravel(), ~scope["b"].valid)


def _tables(text):
    return [ln for ln in text.splitlines() if ln.startswith("|") and not re.match(r"\|[-\s|]+\|$", ln)]


def test_benchmark_figures_are_those_the_bench_wrote():
    headline = _read("benchmarks", "results", "headline.txt")
    summary = _read("benchmarks", "results", "stability_summary.txt")
    sec = _section(BENCH, "Headline")
    checked = 0
    for line in _tables(sec)[1:]:
        if line.startswith("| method") or line.startswith("| case"):
            continue
        body = line.split("|", 2)[2]  # skip the row label (method or case name)
        for tok in re.findall(r"\d[\d.]*(?:e[-+]?\d+)?", body):
            assert tok in headline, f"benchmarks/README.md quotes {tok} ({line.strip()}) but headline.txt lacks it"
            checked += 1
    assert checked >= 40
    for m in re.finditer(r"err by (.*?), and the error", sec, re.S):
        for tok in re.findall(r"\d[\d.]*e[-+]\d+", m.group(1)):
            assert tok in headline
            checked += 1

    stab = _section(BENCH, "Stability maps")
    rows = [ln for ln in _tables(stab) if ln.startswith("| Fig.")]
    methods = ["implicit", "event", "explicit", "regularised"]
    assert len(rows) == 2
    for ln in rows:
        cells = [c.strip() for c in ln.strip().strip("|").split("|")]
        case = "fig" + cells[0].split()[-1]
        for method, cell in zip(methods, cells[1:]):
            line = re.search(rf"^{case} {method} over \(dt, ratio\): (.*)$", summary, re.M)
            assert line and line.group(1).strip() == cell, (case, method, cell, line and line.group(1))


def test_analytic_figures_are_those_the_bench_wrote():
    """The analytic-path section quotes results/analytic.txt (python benchmarks/bench_analytic.py)."""
    text = _read("benchmarks", "results", "analytic.txt")
    sec = _section(BENCH, "Analytic path and planning")
    checked = 0
    for line in _tables(sec)[1:]:
        body = line.split("|", 2)[2]  # skip the row label
        for tok in re.findall(r"\d[\d.,]*\d|\d", body):
            assert tok in text, f"benchmarks/README.md quotes {tok} ({line.strip()}) but analytic.txt lacks it"
            checked += 1
    for tok in re.findall(r"(\d+\.\d+) s\b", sec):
        assert tok in text, f"benchmarks/README.md quotes {tok} s but analytic.txt lacks it"
        checked += 1
    assert checked >= 10


def _quoted_from(section, filename, minimum):
    """Every number in the table rows of ``section`` (after the row label) is
    in benchmarks/results/``filename``; returns how many were checked."""
    text = _read("benchmarks", "results", filename)
    sec = _section(BENCH, section)
    checked = 0
    for line in _tables(sec)[1:]:
        body = line.split("|", 2)[2]  # skip the row label
        for tok in re.findall(r"\d[\d.]*", body):
            assert tok in text, f"benchmarks/README.md quotes {tok} ({line.strip()}) but {filename} lacks it"
            checked += 1
    assert checked >= minimum
    return checked


def test_step_cost_figures_are_those_the_bench_wrote():
    """The per-step table quotes results/step.txt (python benchmarks/bench_step.py)."""
    _quoted_from("Per-step cost", "step.txt", 10)


def test_obstacle_figures_are_those_the_bench_wrote():
    """The obstacle table quotes results/obstacles.txt (python benchmarks/bench_obstacles.py)."""
    _quoted_from("Obstacles and methods", "obstacles.txt", 30)


def test_certificate_cost_figures_are_those_the_bench_wrote():
    """The certificate-cost table quotes results/certify.txt (python benchmarks/bench_certify.py)."""
    _quoted_from("Certificate cost", "certify.txt", 40)
