"""``exdex paper``'s figures and table are print-ready.

Read from the matplotlib Figure objects: the size is the column (3.5 in) or page (7.16 in) width of a
two-column paper, every text is >= 8 pt at that size and lies inside the figure, panel (a) draws the
gripper's motion (its extreme is the paper's X1 = 0.1 m down and back for Fig. 3, its end the
trapezoid's 50 mm for Fig. 4, the Eq. 7 amplitude theta1 = 100 deg for Fig. 6), errors at rounding
level are text, not a band of 1e-15 noise. The files: PNG at 300 dpi (pixel width = 300 x width),
PDF and SVG vector (no raster image, text as text). The table: a stop gap of -1.39e-17 m reads as
rounding, every largest |v| has its unit.
"""
import math
import re

import numpy as np
import pytest

from exdex import paper

plt = pytest.importorskip("matplotlib.pyplot")


@pytest.fixture(scope="module")
def runs():
    return {name: paper.run_case(name, dt=1e-3) for name in ("fig3", "fig4")}


def _texts(fig):
    from matplotlib.text import Text

    return [t for t in fig.findobj(Text) if t.get_visible() and t.get_text().strip()]


@pytest.mark.parametrize("width", ["column", "page"])
@pytest.mark.parametrize("name", ["fig3", "fig4"])
def test_figure_size_fonts_and_layout(runs, name, width):
    fig = paper.plot_case(runs[name], width=width)
    try:
        w, h = fig.get_size_inches()
        assert w == {"column": 3.5, "page": 7.16}[width] and 2.0 < h < 7.0
        fig.canvas.draw()   # tick labels get their text when drawn
        texts = _texts(fig)
        assert len(texts) > 25
        small = [(t.get_text(), t.get_fontsize()) for t in texts if t.get_fontsize() < 8.0]
        assert not small, small
        renderer = fig.canvas.get_renderer()
        box = fig.bbox
        outside = [t.get_text() for t in texts
                   if not (box.x0 - 0.5 <= t.get_window_extent(renderer).x0
                           and t.get_window_extent(renderer).x1 <= box.x1 + 0.5
                           and box.y0 - 0.5 <= t.get_window_extent(renderer).y0
                           and t.get_window_extent(renderer).y1 <= box.y1 + 0.5)]
        assert not outside, outside
        # the titles name the parameters with symbols and units, not "X1 0.1 m"
        title = fig.get_suptitle()
        assert "$X_1$ = " in title and " m" in title and "X1 " not in title
        # "max |v| = 0" carries its unit
        assert any(re.search(r"max \|v\| = 0 m/s", t.get_text()) for t in texts)
    finally:
        plt.close(fig)


@pytest.mark.parametrize("name,extreme", [("fig3", -100.0), ("fig4", -50.0)])
def test_panel_a_draws_the_gripper_motion(runs, name, extreme):
    """Fig. 3: Eq. 7 goes X1 = 0.1 m down and back (paper); Fig. 4: the trapezoid's 50 mm down."""
    fig = paper.plot_case(runs[name])
    try:
        ax = fig.axes[0]
        assert ax.get_title(loc="left") == "(a) gripper motion" and ax.get_ylabel() == "height [mm]"
        (line,) = [ln for ln in ax.get_lines() if len(ln.get_xdata()) > 10]
        y = np.asarray(line.get_ydata())
        assert y[0] == 0.0 and np.min(y) == pytest.approx(extreme, abs=1e-9)
        assert y[-1] == pytest.approx(0.0 if name == "fig3" else extreme, abs=1e-9)
    finally:
        plt.close(fig)


def test_rounding_errors_are_text_not_a_band(runs):
    """Fig. 3 and 4's errors against their closed forms are all below 1e-13 of the slip (rounding):
    panel (c) draws no curve and says so; before, it drew a band at the 1e-16 floor."""
    for name in ("fig3", "fig4"):
        run = runs[name]
        assert np.max(run.error) < 1e-13 * np.max(np.abs(run.x))   # the premise, measured
        fig = paper.plot_case(run)
        try:
            ax = fig.axes[2]
            assert [ln for ln in ax.get_lines() if len(ln.get_xdata())] == []
            notes = [t.get_text() for t in ax.texts]
            assert any("rounding" in n and "at every" in n for n in notes), notes
        finally:
            plt.close(fig)


def test_errors_above_rounding_are_drawn_and_rounding_is_not():
    """A run whose error is partly above the floor: drawn where it is, masked (not clamped) below."""
    run = paper.run_case("fig3", dt=1e-3)
    err = np.array(run.error)
    err[: len(err) // 2] = 1e-6     # made-up error above the floor on the first half
    run.error = err
    fig = paper.plot_case(run)
    try:
        ax = fig.axes[2]
        (line,) = [ln for ln in ax.get_lines() if len(ln.get_xdata())]
        y = np.asarray(line.get_ydata(), dtype=float)
        floor = ax.get_ylim()[0]
        assert np.all(np.isnan(y) | (y >= floor)) and np.isnan(y[-1]) and y[0] == 1e-6
        assert floor <= 1e-13 * np.max(np.abs(run.x)) and math.log10(floor).is_integer()
        assert any("rounding" in t.get_text() for t in ax.get_legend().get_texts())
    finally:
        plt.close(fig)


def test_files_png_300_dpi_and_vector_pdf_svg(runs, tmp_path):
    from PIL import Image

    fig = paper.plot_case(runs["fig3"], width="page")
    paths = paper.save_figure(fig, str(tmp_path / "fig3"), ("png", "pdf", "svg"))
    assert [p[-3:] for p in paths] == ["png", "pdf", "svg"]
    with Image.open(paths[0]) as im:
        assert im.size[0] == round(7.16 * 300)
        assert im.info["dpi"][0] == pytest.approx(300, abs=0.01)
    pdf = open(paths[1], "rb").read()
    assert pdf.startswith(b"%PDF") and b"/Subtype /Image" not in pdf and b"/FontFile2" in pdf
    svg = open(paths[2]).read()
    assert "<image" not in svg and "<text" in svg and "inertial slip" in svg
    with pytest.raises(ValueError, match="formats"):
        paper.save_figure(paper.plot_case(runs["fig3"]), str(tmp_path / "x"), ("jpg",))
    with pytest.raises(ValueError, match="width must be one of"):
        paper.plot_case(runs["fig3"], width="a4")


def test_summary_prints_rounding_and_units():
    rows = [dict(case="Fig. 4", quantity="min stop gap [m]", paper=None, exdex=-1.3877787807814457e-17,
                 difference=None, reference=0.0, max_v_after=0.0, note=""),
            dict(case="Fig. 4", quantity="stop force while sliding, median [N]", paper=None, exdex=2.48,
                 difference=None, reference=2.48, max_v_after=0.0, note=""),
            dict(case="Fig. 6", quantity="final relative rotation [deg]", paper=140.0, exdex=114.3,
                 difference=-25.7, reference=114.3, max_v_after=0.0, note="")]
    lines = paper.format_table(rows).splitlines()
    assert "0 (rounding, |gap| < 1e-15 m)" in lines[2] and "e-17" not in lines[2]
    assert lines[2].endswith("0 m/s") and lines[3].endswith("0 m/s") and lines[4].endswith("0 rad/s")
    # a real penetration is not hidden as rounding
    rows[0]["exdex"] = -1e-12
    assert "-1e-12" in paper.format_table(rows).splitlines()[2]
