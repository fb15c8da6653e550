"""exdex._html, the short HTML summaries of Jupyter's rich display: quantity
and summary_table against strings written out by hand (units, escaping),
then what a Scene and a Result show with them.

The numbers are the scene's own inputs (mass, sizes, grip, mu) and, for the Result, the final slip of
the paper's Fig. 3 scene, which its closed form fixes at -20 mm (tests/studies/test_paper.py checks the
value itself; here only that the table shows it, in mm)."""
import html
import re

import numpy as np

import exdex
from exdex._html import quantity, summary_table


def test_quantity_formats_a_number_with_its_unit():
    assert quantity(1.5, "N") == "1.5 N"
    assert quantity(1 / 3) == "0.333333"                 # six significant digits, no unit, no trailing space
    assert quantity(1e-7, "m") == "1e-07 m"
    assert quantity(0.02, "s", fmt="{:.3f}") == "0.020 s"
    assert quantity("holds", "N") == "holds"             # text is kept as given, without the unit


def test_summary_table_is_a_two_column_table_with_everything_escaped():
    th = '<th style="text-align:left;padding-right:1em">'
    td = '<td style="text-align:left">'
    assert summary_table("a <b>", [("x < y", "1 & 2"), (3, None)]) == (
        '<div class="exdex-summary"><b>a &lt;b&gt;</b><table>'
        f'<tr>{th}x &lt; y</th>{td}1 &amp; 2</td></tr>'
        f'<tr>{th}3</th>{td}None</td></tr>'
        '</table></div>')
    assert summary_table("empty", []) == '<div class="exdex-summary"><b>empty</b><table></table></div>'


def _cells(text):
    rows = re.findall(r"<tr><th[^>]*>(.*?)</th><td[^>]*>(.*?)</td></tr>", text)
    return {html.unescape(k): html.unescape(v) for k, v in rows}


def test_scene_html_summary_lists_inputs_with_units():
    sc = exdex.Scene(body=exdex.Body.box(0.1, (0.03, 0.06, 0.02)),
                     grasp=exdex.Grasp(mu=0.5, grip_force=1.5, patch=exdex.Patch.rectangle(0.01, 0.02)),
                     motion=exdex.AsymmetricProfile(0.1, 0.5, 0.9, axis=(0, 0, -1)))
    text = sc._repr_html_()
    assert text.startswith('<div class="exdex-summary">') and "exdex.Scene" in text
    cells = _cells(text)
    assert cells["object"] == "0.1 kg, box 30 x 60 x 20 mm"
    assert cells["grip force per finger"] == "1.5 N"
    assert cells["friction capacity"] == "1.5 N"           # 0.5 x 2 fingers x 1.5 N
    assert cells["contact"].startswith("patch on the object, rectangle 10 x 20 mm")
    assert cells["motion"] == "AsymmetricProfile, ends at t = 1 s"   # Eq. 7: down in T, back in T
    assert cells["free coordinates"] == "translation"


def test_scene_html_summary_with_a_schedule_and_a_pad():
    sc = exdex.Scene(body=exdex.Body.box(0.1, (0.04, 0.04, 0.02)),
                     grasp=exdex.Grasp(mu=0.5, grip_force=exdex.GripSchedule([0.0, 0.5], [2.0, 0.0]),
                                       pad=exdex.Pad.disc(0.005)))
    cells = _cells(sc._repr_html_())
    assert cells["grip force per finger"] == "schedule 0 to 2 N (linear, t = 0 to 0.5 s)"
    assert cells["contact"].startswith("pad on the fingers, disc radius 5 mm")


def test_result_html_summary_shows_the_run():
    res = exdex.simulate(exdex.paper.fig3_scene(), t_end=1.5, dt=1e-3)
    cells = _cells(res._repr_html_())
    assert cells["model"] == "translation, method implicit, dt 0.001 s"
    assert cells["samples"] == str(len(res.t)) == "1501"
    assert cells["time"] == "0 to 1.5 s"
    start, end = cells["s: start, end"].split(", ")
    assert start == "0 mm" and end.endswith(" mm") and abs(float(end[:-3]) + 20.0) < 0.1
    assert cells["stick"].endswith("at the end: yes")
    assert cells["1-DoF reduction"] == "holds"
    assert np.isclose(float(end[:-3]), 1e3 * res.displacement[-1, 0], rtol=1e-5)
