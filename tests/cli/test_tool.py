"""exdex.cli.tool: ``exdex tool --quick``: every file written and the rod
study's descent against its closed form."""
import argparse
import csv
import math


def test_cli_quick(tmp_path, capsys):
    from exdex.cli import tool as cli_tool

    parser = argparse.ArgumentParser()
    cli_tool.add_arguments(parser)
    args = parser.parse_args(["--out", str(tmp_path), "--quick", "--no-progress"])
    assert cli_tool.run(args) == 0
    for name in ("theta_star.csv", "theta_curves.png", "box_aspect.csv", "box_aspect.png",
                 "friction.csv", "multi_shape.csv", "rod.csv", "rod.png"):
        assert (tmp_path / name).stat().st_size > 0
    out = capsys.readouterr().out
    assert "theta*" in out and "rod" in out
    # the rod study (a unit-height object, the rod 0.25 m to the side): the largest turn asin(0.25 / 0.5)
    # = 30 deg, and every descent of rod.csv on the geometry's closed form, derived here from the rod
    # staying on the bottom edge: xr sin(psi) + (b - d) cos(psi) = b, b = 0.5 m
    assert "at most 30.00 deg" in out
    with open(tmp_path / "rod.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 51   # 2001 points of the integration, every 40th
    b, xr = 0.5, 0.25
    for r in rows:
        psi = math.radians(float(r["psi_deg"]))
        assert abs(float(r["descent_m"]) - (b - (b - xr * math.sin(psi)) / math.cos(psi))) <= 1e-12
