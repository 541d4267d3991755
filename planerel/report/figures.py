"""Figures of the paper-reproduction report: side-by-side coloured segmentations with a legend.

A figure is a grid of panels, one panel per (scene, method): the label image coloured by
:func:`planerel.io.writers.colour_labels` over a depth shading, enlarged with nearest-neighbour
sampling to a fixed panel width, sparse planes outlined with a black-and-yellow dashed line, and
one or two caption lines under it.  A legend strip closes the figure.  Everything is drawn with
Pillow's built-in font, so the PNG bytes depend only on the inputs and the Pillow version.
"""

from __future__ import annotations

import io
from dataclasses import dataclass

import numpy as np

from planerel.errors import InputError

__all__ = ["Panel", "panel_image", "compose_figure", "png_bytes", "LEGEND_TEXT"]

#: What the colours mean; the same sentence is printed under every figure of the report.
LEGEND_TEXT = ("Each colour is one plane (colours only tell planes apart; the ground truth and "
               "each method number their planes independently). Grey, shaded by depth (lighter = "
               "nearer): points no plane claims. Black: no depth measurement. Black-and-yellow "
               "dashed outline: a sparse plane (two or more separate pieces, Table 7).")

_BG = (255, 255, 255)
_TEXT = (20, 20, 20)
_DIM = (90, 90, 90)


@dataclass(frozen=True)
class Panel:
    """One panel of a figure.

    Parameters
    ----------
    rgb : ndarray, shape (H, W, 3), uint8
        The picture (already coloured).
    title : str
        First caption line (method or "depth" / "ground truth").
    subtitle : str
        Second caption line (counts), may be empty.
    """

    rgb: np.ndarray
    title: str
    subtitle: str = ""

    def __post_init__(self) -> None:
        a = np.asarray(self.rgb)
        if a.ndim != 3 or a.shape[2] != 3 or a.dtype != np.uint8:
            raise InputError(f"panel {self.title!r}: picture must be (H, W, 3) uint8, got "
                             f"{a.dtype} {a.shape}")


def _font(size: int):
    from PIL import ImageFont

    try:
        return ImageFont.load_default(size=size)
    except (TypeError, OSError, ImportError):  # Pillow without FreeType
        return ImageFont.load_default()


def _dashed(mask: np.ndarray) -> np.ndarray:
    """``(H, W, 3)`` uint8 black/yellow dash pattern (for outline pixels)."""
    h, w = mask.shape
    rr, cc = np.mgrid[0:h, 0:w]
    yellow = ((rr + cc) // 3) % 2 == 0
    out = np.zeros((h, w, 3), np.uint8)
    out[yellow] = (255, 220, 0)
    return out


def panel_image(labels, depth=None, *, sparse_ids=(), width: int = 232) -> np.ndarray:
    """A coloured segmentation, enlarged to ``width`` pixels, sparse planes outlined.

    Parameters
    ----------
    labels : ndarray, shape (H, W), int
        -1 = unassigned.  Pass an all ``-1`` image to draw the depth alone.
    depth : ndarray, shape (H, W), optional
        Depth (any unit, NaN / <= 0 invalid) for the shading.
    sparse_ids : iterable of int
        Region ids to outline.
    width : int
        Output width; the height keeps the aspect ratio.

    Returns
    -------
    ndarray, shape (H', width, 3), uint8
    """
    from scipy import ndimage

    from planerel.io.writers import colour_labels

    lab = np.asarray(labels)
    if lab.ndim != 2:
        raise InputError(f"labels must be (H, W), got shape {lab.shape}")
    h, w = lab.shape
    if width < 8:
        raise InputError(f"panel width must be >= 8 pixels, got {width}")
    out_h = max(1, int(round(h * width / w)))
    rows = np.minimum((np.arange(out_h) * h) // out_h, h - 1)
    cols = np.minimum((np.arange(width) * w) // width, w - 1)
    rgb = colour_labels(lab, depth)[rows[:, None], cols[None, :]]
    ids = [int(i) for i in sparse_ids]
    if ids:
        mask = _significant_pieces(lab, ids)[rows[:, None], cols[None, :]]
        inner = ndimage.binary_erosion(mask, structure=np.ones((3, 3), bool), iterations=2,
                                       border_value=0)
        edge = mask & ~inner
        rgb = rgb.copy()
        rgb[edge] = _dashed(edge)[edge]
    return rgb


def _significant_pieces(lab: np.ndarray, ids, fraction: float = 0.1) -> np.ndarray:
    """``(H, W)`` bool: the significant pieces of the regions ``ids`` (as
    :func:`planerel.segment.evaluate.sparse_planes` defines them: 8-connected components after a
    one-pixel closing, each with at least ``fraction`` of the region and 10 pixels at 160x120),
    filled, so the outline shows the separate pieces and not every stray pixel."""
    from scipy import ndimage

    h, w = lab.shape
    min_px = max(3, int(round(10 * h * w / (160 * 120))))
    st = np.ones((3, 3), bool)
    out = np.zeros(lab.shape, bool)
    for rid in ids:
        m = lab == rid
        total = int(m.sum())
        if total == 0:
            continue
        closed = ndimage.binary_closing(m, structure=st) | m
        comp, nc = ndimage.label(closed, structure=st)
        sizes = np.bincount(comp[m], minlength=nc + 1)
        keep = (sizes >= fraction * total) & (sizes >= min_px)
        keep[0] = False
        out |= ndimage.binary_fill_holes(keep[comp])
    return out


def _legend_strip(width: int, font) -> np.ndarray:
    from PIL import Image, ImageDraw

    img = Image.new("RGB", (width, 26), _BG)
    d = ImageDraw.Draw(img)
    x = 6
    items = [("plane (one colour each)", None), ("unassigned", (150, 150, 150)),
             ("no depth", (0, 0, 0)), ("sparse plane outline", "dash")]
    from planerel.io.writers import label_colours

    pal = label_colours(4)
    for text, colour in items:
        if colour is None:
            for k in range(4):
                d.rectangle([x + 5 * k, 7, x + 5 * k + 4, 19], fill=tuple(int(v) for v in pal[k]))
        elif colour == "dash":
            for k in range(4):
                d.rectangle([x + 5 * k, 7, x + 5 * k + 4, 19],
                            fill=(255, 220, 0) if k % 2 == 0 else (0, 0, 0))
        else:
            d.rectangle([x, 7, x + 19, 19], fill=colour, outline=(120, 120, 120))
        x += 25
        d.text((x, 7), text, fill=_TEXT, font=font)
        x += int(d.textlength(text, font=font)) + 18
    return np.asarray(img)


def compose_figure(rows, *, row_titles=None, columns: int = 5, legend: bool = True) -> np.ndarray:
    """Lay panels out in a grid.

    Parameters
    ----------
    rows : list of list of Panel
        One list per scene; a scene with more than ``columns`` panels wraps onto further lines.
        All panels must have the same width.
    row_titles : list of str, optional
        A title line above each scene.
    columns : int
        Panels per line.
    legend : bool
        Append the legend strip.

    Returns
    -------
    ndarray, shape (H, W, 3), uint8
    """
    from PIL import Image, ImageDraw

    if not rows or not any(rows):
        raise InputError("a figure needs at least one panel")
    if columns < 1:
        raise InputError(f"columns must be >= 1, got {columns}")
    panels = [p for r in rows for p in r]
    pw = panels[0].rgb.shape[1]
    if any(p.rgb.shape[1] != pw for p in panels):
        raise InputError("all panels of a figure must have the same width")
    font = _font(12)
    small = _font(11)
    gap, cap_h, title_h = 6, 32, 20
    ncol = min(columns, max(len(r) for r in rows))
    fig_w = ncol * pw + (ncol + 1) * gap
    blocks = []
    for ri, r in enumerate(rows):
        title = row_titles[ri] if row_titles else None
        lines = [r[i:i + columns] for i in range(0, len(r), columns)]
        parts = []
        if title:
            img = Image.new("RGB", (fig_w, title_h), _BG)
            ImageDraw.Draw(img).text((gap, 4), title, fill=_TEXT, font=font)
            parts.append(np.asarray(img))
        for line in lines:
            ph = max(p.rgb.shape[0] for p in line)
            img = Image.new("RGB", (fig_w, ph + cap_h + gap), _BG)
            d = ImageDraw.Draw(img)
            for ci, p in enumerate(line):
                x = gap + ci * (pw + gap)
                img.paste(Image.fromarray(np.ascontiguousarray(p.rgb), "RGB"), (x, 0))
                d.text((x + 2, p.rgb.shape[0] + 2), p.title, fill=_TEXT, font=font)
                if p.subtitle:
                    d.text((x + 2, p.rgb.shape[0] + 17), p.subtitle, fill=_DIM, font=small)
            parts.append(np.asarray(img))
        blocks.append(np.concatenate(parts, axis=0))
        blocks.append(np.full((gap, fig_w, 3), 255, np.uint8))
    if legend:
        strip = _legend_strip(fig_w, small)
        blocks.append(strip)
    return np.ascontiguousarray(np.concatenate(blocks, axis=0))


def png_bytes(rgb, *, palette: bool = True) -> bytes:
    """Encode an ``(H, W, 3)`` uint8 image as PNG (deterministic, optimised).

    With ``palette`` the image is reduced to 256 colours without dithering (octree
    quantisation, about a third of the size; the depth shading gets slightly banded).
    """
    from PIL import Image

    a = np.ascontiguousarray(np.asarray(rgb, dtype=np.uint8))
    if a.ndim != 3 or a.shape[2] != 3:
        raise InputError(f"an RGB image must be (H, W, 3), got shape {a.shape}")
    img = Image.fromarray(a, "RGB")
    if palette:
        img = img.quantize(colors=256, method=Image.Quantize.FASTOCTREE,
                           dither=Image.Dither.NONE)
    buf = io.BytesIO()
    img.save(buf, format="PNG", optimize=True)
    return buf.getvalue()
