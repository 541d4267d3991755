"""Rendering of the paper-reproduction report: one document model, two outputs.

A report is a list of blocks (:class:`Heading`, :class:`Para`, :class:`Table`, :class:`Figure`,
:class:`Code`).  :func:`render_html` turns it into one self-contained HTML page (CSS inline,
figures embedded as base64 PNG, no external resource); :func:`render_markdown` into GitHub
Markdown whose figures are PNG files next to it (``figures/NAME.png``).  Both keep the block
order, so the two files carry the same content.

Text in blocks is plain text; the only inline markup understood is ``**bold**`` and
```code```, rendered as ``<b>`` / ``<code>`` in HTML and kept as-is in Markdown.
"""

from __future__ import annotations

import base64
import html
import re
from dataclasses import dataclass, field

from planerel.errors import InputError

__all__ = [
    "Heading",
    "Para",
    "Table",
    "Figure",
    "Code",
    "render_html",
    "render_markdown",
    "slug",
]


def slug(text: str) -> str:
    """``"Table 7: sparse planes"`` -> ``"table-7-sparse-planes"`` (anchors, file names)."""
    s = re.sub(r"[^a-z0-9]+", "-", text.lower()).strip("-")
    return s or "section"


@dataclass(frozen=True)
class Heading:
    """A section heading; ``level`` 1 (title) .. 3."""

    text: str
    level: int = 2

    def __post_init__(self) -> None:
        if self.level not in (1, 2, 3):
            raise InputError(f"heading level must be 1, 2 or 3, got {self.level!r}")


@dataclass(frozen=True)
class Para:
    """A paragraph of plain text (``**bold**`` and ```code``` allowed)."""

    text: str


@dataclass(frozen=True)
class Code:
    """A preformatted block (commands, rules)."""

    text: str


@dataclass(frozen=True)
class Table:
    """A table of already formatted cells.

    Parameters
    ----------
    headers : tuple of str
    rows : tuple of tuple of str
        Every row has ``len(headers)`` cells.
    caption : str
    """

    headers: tuple
    rows: tuple
    caption: str = ""

    def __post_init__(self) -> None:
        headers = tuple(str(h) for h in self.headers)
        rows = tuple(tuple(str(c) for c in r) for r in self.rows)
        for i, r in enumerate(rows):
            if len(r) != len(headers):
                raise InputError(f"table {self.caption!r}: row {i} has {len(r)} cells, "
                                 f"expected {len(headers)}")
        object.__setattr__(self, "headers", headers)
        object.__setattr__(self, "rows", rows)


@dataclass(frozen=True)
class Figure:
    """A PNG figure.

    Parameters
    ----------
    name : str
        File stem (``fig-stairs``); the Markdown output writes ``figures/<name>.png``.
    png : bytes
        The encoded PNG.
    caption : str
    """

    name: str
    png: bytes = field(repr=False)
    caption: str = ""

    def __post_init__(self) -> None:
        if not re.fullmatch(r"[A-Za-z0-9_.-]+", self.name):
            raise InputError(f"figure name must be a plain file stem, got {self.name!r}")
        if not bytes(self.png[:8]) == b"\x89PNG\r\n\x1a\n":
            raise InputError(f"figure {self.name!r} is not a PNG image")


_CSS = """
body{font-family:-apple-system,"Segoe UI",Helvetica,Arial,sans-serif;max-width:1180px;
margin:1.5em auto;padding:0 1em;color:#1b1f24;line-height:1.45}
h1{border-bottom:2px solid #d0d7de;padding-bottom:.3em}
h2{border-bottom:1px solid #d0d7de;padding-bottom:.2em;margin-top:2em}
table{border-collapse:collapse;margin:.6em 0 1.2em 0;font-size:13px}
th,td{border:1px solid #d0d7de;padding:3px 8px;text-align:right;white-space:nowrap}
th{background:#f3f5f7} td:first-child,th:first-child{text-align:left}
tr:nth-child(even) td{background:#fafbfc}
caption{caption-side:top;text-align:left;font-weight:600;padding:.3em 0}
figure{margin:1em 0} figure img{max-width:100%;image-rendering:pixelated;border:1px solid #d0d7de}
figcaption{font-size:13px;color:#57606a}
pre{background:#f6f8fa;padding:.7em;overflow-x:auto;font-size:12.5px}
code{background:#f6f8fa;padding:0 .25em}
nav ul{columns:2;font-size:14px}
"""


def _inline_html(text: str) -> str:
    out = html.escape(text, quote=False)
    out = re.sub(r"\*\*(.+?)\*\*", r"<b>\1</b>", out)
    out = re.sub(r"`(.+?)`", r"<code>\1</code>", out)
    return out


def render_html(blocks, title: str) -> str:
    """One self-contained HTML page (UTF-8 text) of ``blocks``.

    Figures are embedded as ``<img src="data:image/png;base64,...">``; a table of contents
    links the level-2 headings.
    """
    toc = [b for b in blocks if isinstance(b, Heading) and b.level == 2]
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>{html.escape(title)}</title>",
        f"<style>{_CSS}</style></head><body>",
    ]
    toc_done = False
    for b in blocks:
        if isinstance(b, Heading):
            if b.level == 2 and not toc_done and toc:
                parts.append("<nav><ul>" + "".join(
                    f'<li><a href="#{slug(h.text)}">{html.escape(h.text)}</a></li>' for h in toc)
                    + "</ul></nav>")
                toc_done = True
            parts.append(f'<h{b.level} id="{slug(b.text)}">{_inline_html(b.text)}</h{b.level}>')
        elif isinstance(b, Para):
            parts.append(f"<p>{_inline_html(b.text)}</p>")
        elif isinstance(b, Code):
            parts.append(f"<pre>{html.escape(b.text, quote=False)}</pre>")
        elif isinstance(b, Table):
            rows = ["<table>"]
            if b.caption:
                rows.append(f"<caption>{_inline_html(b.caption)}</caption>")
            rows.append("<thead><tr>" + "".join(f"<th>{_inline_html(h)}</th>" for h in b.headers)
                        + "</tr></thead><tbody>")
            for r in b.rows:
                rows.append("<tr>" + "".join(f"<td>{_inline_html(c)}</td>" for c in r) + "</tr>")
            rows.append("</tbody></table>")
            parts.append("".join(rows))
        elif isinstance(b, Figure):
            data = base64.b64encode(b.png).decode("ascii")
            parts.append(f'<figure id="{html.escape(b.name)}"><img alt="{html.escape(b.caption)}" '
                         f'src="data:image/png;base64,{data}">'
                         f"<figcaption>{_inline_html(b.caption)}</figcaption></figure>")
        else:
            raise InputError(f"cannot render a {type(b).__name__} block")
    parts.append("</body></html>")
    return "\n".join(parts) + "\n"


def _md_cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def render_markdown(blocks, title: str, figure_dir: str = "figures") -> tuple[str, dict]:
    """GitHub Markdown of ``blocks``.

    Returns
    -------
    text : str
    files : dict
        ``{relative path: PNG bytes}`` of the figures the text links (``figure_dir/NAME.png``).
    """
    out = []
    files = {}
    if not (blocks and isinstance(blocks[0], Heading) and blocks[0].level == 1):
        out.append(f"# {title}\n")
    for b in blocks:
        if isinstance(b, Heading):
            out.append(f"{'#' * b.level} {b.text}\n")
        elif isinstance(b, Para):
            out.append(b.text + "\n")
        elif isinstance(b, Code):
            out.append("```\n" + b.text.rstrip("\n") + "\n```\n")
        elif isinstance(b, Table):
            lines = []
            if b.caption:
                lines.append(f"**{b.caption}**\n")
            lines.append("| " + " | ".join(_md_cell(h) for h in b.headers) + " |")
            lines.append("|" + "|".join(["---"] + ["---:"] * (len(b.headers) - 1)) + "|")
            for r in b.rows:
                lines.append("| " + " | ".join(_md_cell(c) for c in r) + " |")
            out.append("\n".join(lines) + "\n")
        elif isinstance(b, Figure):
            rel = f"{figure_dir}/{b.name}.png"
            files[rel] = b.png
            out.append(f"![{b.caption}]({rel})\n\n*{b.caption}*\n")
        else:
            raise InputError(f"cannot render a {type(b).__name__} block")
    return "\n".join(out), files
