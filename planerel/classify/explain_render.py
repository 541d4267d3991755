"""Readable explanation images: the proof planes of each classified object, with a legend.

The picture is scaled up by a whole factor to at least 640 pixels wide (nearest neighbour, so
every pixel stays one scan point), and a legend under it names, per object, the class, the
rule that fired and which plane each of the rule's variables is bound to, with the plane's
colour swatch.  The colours of the picture and of the legend come from one table.
"""

from __future__ import annotations

import textwrap

import numpy as np

__all__ = ["MIN_WIDTH", "explanation_picture", "binding_colours", "legend_rows", "shown_planes"]

MIN_WIDTH = 640


def shown_planes(obj) -> tuple:
    """The planes the picture colours for a classified object: its proof planes, or, when its
    rule binds no plane (``box(A) :- nhorizontal(A,1), oblique_share(A,B), ...``), all of the
    object's planes, so that the answer is still seen where it is (user89)."""
    return tuple(dict.fromkeys(obj.proof_planes or obj.planes))


def binding_colours(answer) -> dict:
    """``{(object index, plane id): (r, g, b)}`` for the shown planes (:func:`shown_planes`)
    of every classified object (distinct colours in a fixed order)."""
    from planerel.io.writers import label_colours

    keys = [(n, pid) for n, o in enumerate(answer.objects) if o.klass != "other"
            for pid in shown_planes(o)]
    pal = label_colours(max(1, len(keys)))
    return {k: tuple(int(c) for c in pal[i]) for i, k in enumerate(keys)}


def _picture(answer, depth) -> np.ndarray:
    from planerel.io.writers import colour_labels

    lab = np.asarray(answer.labels)
    grey = colour_labels(np.full_like(lab, -1), depth).astype(float)
    out = grey.copy()
    inv = {v: k for k, v in answer.plane_ids.items()}
    colours = binding_colours(answer)
    for n, o in enumerate(answer.objects):
        for lab_id in o.labels:
            m = lab == lab_id
            tint = (120, 120, 160) if o.klass == "other" else (255, 255, 255)
            out[m] = 0.6 * grey[m] + 0.4 * np.array(tint)
        if o.klass == "other":
            continue
        for pid in shown_planes(o):
            if pid not in inv:
                continue
            m = lab == inv[pid]
            out[m] = 0.25 * grey[m] + 0.75 * np.array(colours[(n, pid)])
    return np.clip(np.round(out), 0, 255).astype(np.uint8)


def legend_rows(answer, chars: int = 100) -> list:
    """The legend under the picture: ``[(text, swatch colour or None)]``, per object its
    class, the refusals and the rule in the words of ``planerel classify``'s text output, and
    the variable -> plane bindings with their colours; the objects of class ``other`` that no
    rule proves share one line at the end.  ``chars`` is the line width in characters."""
    colours = binding_colours(answer)
    rows: list[tuple[str, tuple | None]] = []  # (text, swatch colour)
    if not answer.objects:
        rows.append(("no object proposal in this scene", None))
    quiet = []  # `other` objects no rule proves: one line for all of them
    for n, o in enumerate(answer.objects):
        if o.klass == "other" and not o.refused and not o.fired:
            quiet.append(o.object_id)
            continue
        rows.append((f"{o.object_id}: {o.klass}", None))
        # what the text output says of the object, in the same words (user89: the picture
        # said "no rule fires" of an object whose box rule the decision refused)
        for r in o.refused:
            for part in textwrap.wrap(f"refused {r.klass}: {r.reason}", chars - 4) or [""]:
                rows.append(("    " + part, None))
        if o.rule:
            for part in textwrap.wrap(f"rule: {o.rule}", chars - 4) or [""]:
                rows.append(("    " + part, None))
        plane_of = {v: var for var, v in o.bindings.items()}
        for pid in dict.fromkeys(o.proof_planes):
            var = plane_of.get(pid, "?")
            rows.append((f"{var} = {pid}", colours.get((n, pid), (0, 0, 0))))
        if o.klass != "other" and not o.proof_planes:
            first = shown_planes(o)[:1]
            rows.append(("    the rule binds no plane: the object's planes are coloured",
                         colours.get((n, first[0])) if first else None))
        if o.klass == "other":
            if o.fired and not o.refused:
                fired = ", ".join(f"{k} {i}" for k, i in o.fired)
                rows.append((f"    rules fired ({fired}), the decision answers other", None))
            rows.append(("    planes tinted blue-grey", None))
    if quiet:
        for part in textwrap.wrap(", ".join(quiet) + ": other, no rule fires (planes tinted "
                                  "blue-grey)", chars):
            rows.append((part, None))
    return rows


def explanation_picture(answer, depth, *, min_width: int = MIN_WIDTH) -> np.ndarray:
    """``(H', W', 3)`` uint8: the scan with each object's proof planes in colour, scaled to at
    least ``min_width`` pixels wide, over a legend (class, rule, variable -> plane).

    Parameters
    ----------
    answer : SceneAnswer
        From :meth:`planerel.Classifier.classify`.
    depth : ndarray (H, W)
        The scan's depth (shading of the background).
    """
    from PIL import Image, ImageDraw, ImageFont

    pic = _picture(answer, depth)
    h, w = pic.shape[:2]
    k = max(1, -(-min_width // w))
    pic = np.repeat(np.repeat(pic, k, axis=0), k, axis=1)
    W = pic.shape[1]
    size = 15
    font = ImageFont.load_default(size=size)
    line_h = size + 6
    chars = max(20, int(W / (0.6 * size)))
    rows = legend_rows(answer, chars)
    legend_h = 10 + line_h * len(rows)
    img = Image.new("RGB", (W, pic.shape[0] + legend_h), (255, 255, 255))
    img.paste(Image.fromarray(pic), (0, 0))
    draw = ImageDraw.Draw(img)
    y = pic.shape[0] + 5
    for text, swatch in rows:
        x = 8
        if swatch is not None:
            draw.rectangle([x + 28, y + 2, x + 28 + size, y + 2 + size], fill=swatch,
                           outline=(0, 0, 0))
            x += 28 + size + 8
        draw.text((x, y), text, fill=(0, 0, 0), font=font)
        y += line_h
    return np.asarray(img)
