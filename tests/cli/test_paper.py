"""exdex.cli.paper: ``exdex paper``: the three cases' figures, CSV files and
summary against the paper's numbers (20 mm, 140 deg) and the closed-form
bound 114.286 deg; one animation per case."""
import argparse
import csv

import pytest

from exdex import paper


def test_exdex_paper_command(tmp_path, capsys):
    from exdex.cli import paper as cli_paper

    parser = argparse.ArgumentParser()
    cli_paper.add_arguments(parser)
    args = parser.parse_args(["--out", str(tmp_path), "--no-progress"])
    assert cli_paper.run(args) == 0
    out = capsys.readouterr().out
    for name in paper.CASES:
        assert (tmp_path / f"{name}.png").stat().st_size > 10_000
        assert (tmp_path / f"{name}.pdf").read_bytes().startswith(b"%PDF")   # the default formats: png pdf
        with open(tmp_path / f"{name}.csv") as f:
            rows = list(csv.reader(f))
        assert rows[0][0] == "t [s]" and len(rows) > 1000
    with open(tmp_path / "summary.csv") as f:
        summary = list(csv.DictReader(f))
    by = {(r["case"], r["quantity"]): r for r in summary}
    fig3 = by[("Fig. 3", "final relative displacement [mm]")]
    assert float(fig3["paper"]) == 20.0 and abs(abs(float(fig3["exdex"])) - 20.0) < 0.5
    fig6 = by[("Fig. 6", "final relative rotation [deg]")]
    assert float(fig6["paper"]) == 140.0
    assert float(fig6["difference"]) == pytest.approx(float(fig6["exdex"]) - 140.0)
    assert "140" in out and "114.286" in out and "difference" in out
    for r in summary:
        assert float(r["max_v_after"]) == 0.0


def test_paper_command_writes_one_animation_per_case(tmp_path, capsys):
    import argparse

    from exdex.cli import paper as cli_paper

    parser = argparse.ArgumentParser()
    cli_paper.add_arguments(parser)
    args = parser.parse_args(["--out", str(tmp_path), "--cases", "fig4", "--dt", "2e-3", "--animate",
                              "--no-progress"])
    assert cli_paper.run(args) == 0
    PIL = pytest.importorskip("PIL.Image")
    with PIL.open(tmp_path / "fig4.gif") as im:
        assert im.n_frames == 26  # 1.0 s at 25 fps, real time
    assert "fig4.gif" in capsys.readouterr().out
