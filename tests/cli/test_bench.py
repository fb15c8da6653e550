"""exdex.cli.bench: ``exdex bench --quick``: every file written and the
work-precision table's content (the reference machinery is tested in
tests/studies/test_bench.py)."""
import csv
import math

import pytest

from exdex import cli
from exdex.studies import bench


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("bench")
    rc = cli.main(["bench", "--quick", "--out", str(out), "--no-progress"])
    return rc, out


def test_quick_run_writes_every_file(quick_run):
    rc, out = quick_run
    assert rc == 0
    for name in ("work_precision.png", "work_precision.csv", "orders.csv", "headline.csv", "headline.txt",
                 "stability.csv", "stability_fig3.png", "stability_summary.txt"):
        assert (out / name).stat().st_size > 0, name
    assert (out / "work_precision.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_quick_run_csv_content(quick_run):
    _, out = quick_run
    rows = list(csv.DictReader(open(out / "work_precision.csv")))
    cases = {r["case"] for r in rows}
    assert cases == set(bench.CASES)
    imp = [r for r in rows if r["method"] == "implicit" and r["line"] == "implicit" and r["status"] == "ok"]
    assert {r["case"] for r in imp} == set(bench.CASES)
    for r in imp:
        assert math.isfinite(float(r["final_error"])) and float(r["final_error"]) >= 0.0
        assert float(r["max_error"]) >= float(r["final_error"])  # the max over the grid includes t_end
    text = (out / "headline.txt").read_text()
    assert "machine:" in text and "Fig. 3 to 1e-6 m" in text
    # every method simulate() refuses is named as left out, on the chart's notes and in the headline
    _, missing = bench.available_methods()
    for m in missing:
        assert m in text.split("left out")[-1]
    maps = list(csv.DictReader(open(out / "stability.csv")))
    assert {r["cls"] for r in maps} <= set(bench.CLASSES)
    assert all(r["cls"] == "missing" for r in maps if r["method"] in missing)
