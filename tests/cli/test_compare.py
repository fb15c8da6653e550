"""exdex.cli.compare: ``exdex compare``: the incline case's closed-form row (the
Coulomb slide a T^2 / 2), a row per engine, the figure colours, --no-progress."""
import math

import numpy as np
import pytest

from exdex import engines
from optional_packages import need_engines


def test_compare_takes_no_progress():
    import argparse

    from exdex.cli import compare as cli_compare

    p = argparse.ArgumentParser()
    cli_compare.add_arguments(p)
    assert p.parse_args(["--no-progress"]).no_progress is True


def test_compare_incline_row(tmp_path):
    # the incline case of `exdex compare`: the closed-form row is the Coulomb
    # slide a T^2 / 2 (a from the scene's numbers, derived above) and every
    # engine (and Drake's corner contact) has a row
    need_engines()
    import argparse

    from exdex.cli import compare as cli_compare

    p = argparse.ArgumentParser()
    cli_compare.add_arguments(p)
    args = p.parse_args(["--cases", "incline", "--out", str(tmp_path), "--no-progress", "--no-variants",
                         "--no-plots"])
    assert cli_compare.run(args) == 0
    lines = (tmp_path / "compare_table.txt").read_text().splitlines()
    # the case column fits "incline": the header's model column starts where the rows' labels do
    assert lines[0].index("model") == len("incline ")
    rows = {line[8:48].strip(): line[48:].split() for line in lines if line.startswith("incline")}
    assert set(rows) == {"exdex (ellipsoid)", "closed form (Coulomb)", "pybullet", "mujoco", "drake",
                         "drake stop corners"}
    g, m = 9.81, 0.1
    a = g * math.sin(0.4) - 0.3 * g * math.cos(0.4) - 0.09 / m
    assert float(rows["closed form (Coulomb)"][0]) == pytest.approx(1e3 * 0.5 * a * 0.6 ** 2, abs=1e-3)


def test_ablation_figure_colours_are_not_shared():
    labels = ["pybullet", "mujoco", "drake", "pybullet point+spin", "pybullet no cone", "mujoco noslip 20",
              "mujoco point+torsion", "drake hydroelastic"]
    from exdex.cli.compare import ablation_colors

    cols = ablation_colors(engines.ABLATION_MODELS, labels)
    assert len(cols) == len(engines.ABLATION_MODELS) + len(labels)
    assert len({tuple(np.round(c, 6)) for c in cols.values()}) == len(cols)
