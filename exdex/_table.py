"""Plain-text tables for the command line: aligned columns, units in the
headers, an en dash for a missing value (None or NaN) instead of ``nan``."""
from __future__ import annotations

import math
import numbers

__all__ = ["format_table", "MISSING"]

#: what a missing value (None, NaN) prints as
MISSING = "\u2013"


def _cell(value, fmt):
    if value is None:
        return MISSING, True
    if isinstance(value, numbers.Real) and not isinstance(value, bool):
        x = float(value)
        if math.isnan(x):
            return MISSING, True
        return (fmt.format(x) if fmt else f"{x:g}"), True
    return str(value), False


def format_table(columns, rows, indent=""):
    """Format ``rows`` (sequences of values) under ``columns``, a sequence of
    ``(header, fmt)`` pairs (``fmt`` a ``str.format`` spec for numbers, or
    None for ``{:g}``). Numbers are right-aligned, text left-aligned; the
    header carries the unit (e.g. ``"final [mm]"``)."""
    heads = [h for h, _ in columns]
    cells = []
    numeric = [True] * len(columns)
    for r in rows:
        line = []
        for j, (v, (_, fmt)) in enumerate(zip(r, columns)):
            text, is_num = _cell(v, fmt)
            if not is_num:
                numeric[j] = False
            line.append(text)
        cells.append(line)
    widths = [max([len(h)] + [len(c[j]) for c in cells]) for j, h in enumerate(heads)]

    def fmt_line(items):
        return indent + "  ".join(s.rjust(w) if numeric[j] else s.ljust(w)
                                  for j, (s, w) in enumerate(zip(items, widths))).rstrip()

    head = fmt_line(heads)
    rule = indent + "-" * (len(head) - len(indent))
    return "\n".join([head, rule] + [fmt_line(c) for c in cells])
