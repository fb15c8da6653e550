"""Short HTML summaries for Jupyter (``_repr_html_`` of Scene and Result)."""
import html

__all__ = ["summary_table", "quantity"]


def quantity(value, unit="", fmt="{:.6g}"):
    """``value`` formatted with its unit ("1.5 N"); text is kept as given."""
    if isinstance(value, str):
        return value
    text = fmt.format(value)
    return f"{text} {unit}".rstrip()


def summary_table(title, rows):
    """A two-column HTML table under a bold ``title``: ``rows`` are (label, text) pairs, escaped."""
    body = "".join(f'<tr><th style="text-align:left;padding-right:1em">{html.escape(str(k))}</th>'
                   f'<td style="text-align:left">{html.escape(str(v))}</td></tr>' for k, v in rows)
    return f'<div class="exdex-summary"><b>{html.escape(title)}</b><table>{body}</table></div>'
