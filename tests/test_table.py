"""exdex._table: plain-text tables for the command line, against tables laid
out by hand: numbers right-aligned under their header, text left-aligned, a
missing value (None, NaN) an en dash, never ``nan``."""
from exdex._table import MISSING, format_table


def test_table_is_aligned_with_units_and_no_nan():
    cols = [("case", None), ("model", None), ("final [mm]", "{:.3f}"), ("wall [s]", "{:.2f}")]
    rows = [("fig3", "exdex", 20.0, 0.5), ("fig3", "ablation point", float("nan"), None),
            ("fig6", "mujoco", -123.4567, 12.0)]
    text = format_table(cols, rows)
    lines = text.splitlines()
    assert "nan" not in text and MISSING in lines[3]
    # right-aligned numbers: every numeric cell of a column ends where its header ends
    for head in ("final [mm]", "wall [s]"):
        end = lines[0].index(head) + len(head)
        for ln in lines[2:]:
            assert len(ln) >= end and ln[end - 1] != " " and (len(ln) == end or ln[end] == " ")


def test_table_cells_by_kind_with_an_indent():
    """A bool is text (its column left-aligned), None is the missing mark
    (right-aligned with the numbers), a column is as wide as its header or
    its widest cell, and every line, the rule too, starts with the indent."""
    text = format_table([("name", None), ("x [m]", "{:.2f}")], [("a", 1.0), ("bb", None), (True, 12.5)], indent="  ")
    assert text.splitlines() == ["  name  x [m]",
                                 "  -----------",
                                 "  a      1.00",
                                 "  bb        " + MISSING,
                                 "  True  12.50"]
