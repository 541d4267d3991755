"""How many training examples each literal of a learned rule rests on (support76).

A learned clause keeps a literal when the clause without it proves more negatives (or the
search happened to find it first: a tie).  This tool scores every clause of a model's
``rules.pl`` on its training tasks, whole and with each literal dropped, by the builtin
learner's own coverage test (:func:`planerel.ilp.learn.theory_coverage`), and prints the
positives and negatives each version proves.  A literal whose removal proves no more
negatives rests on nothing in training: the world the model was learned from does not
justify it, and a change to that world may drop it; one that keeps out a handful rests on
those few (docs/segmentation.md "A small top over a large plane": the lying clause's
``oblique_share`` bound, 2 base and 4 product-part negatives).

A literal can be dropped when no other literal uses a variable it introduces, except
comparisons (``lteq``, ``gteq``), which are dropped with it: in ``box(A) :- has_plane(A,B),
oblique_share(A,C), lying(B), lteq(C,0.02)`` the versions are without ``oblique_share(A,C),
lteq(C,0.02)``, without ``lying(B)`` and without ``lteq(C,0.02)``; ``has_plane(A,B)`` links
``lying(B)`` and stays.

Usage::

    python benchmarks/clause_support.py out/model/rules.pl out/model_base/aleph out/model/aleph [--names]

``--names`` also names the negatives each literal keeps out (the learner's ``@@covered``
lines: :func:`~planerel.ilp.learn.theory_coverage`).

Each STAGE folder holds the Aleph task ``CLASS.b/.f/.n`` of every class the rules name (the
``aleph/`` folder a model is written with; ``make demo`` learns in two stages, the base world
in ``out/model_base`` and the product part in ``out/model``).  Scoring loads the task's
background once per version, about 1-2 s each.
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

#: Comparison literals: dropped with the literal that binds their variable.
COMPARISONS = frozenset({"lteq", "gteq", "lt", "gt", "<", ">", "=<", ">="})

_VAR = re.compile(r"\b[A-Z_][A-Za-z0-9_]*\b")


def split_top(text: str) -> list[str]:
    """``text`` split at its top-level commas (outside brackets and quotes)."""
    out, depth, quote, cur = [], 0, None, []
    for ch in text:
        if quote:
            cur.append(ch)
            if ch == quote:
                quote = None
            continue
        if ch in "'\"":
            quote = ch
        elif ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        elif ch == "," and depth == 0:
            out.append("".join(cur).strip())
            cur = []
            continue
        cur.append(ch)
    if "".join(cur).strip():
        out.append("".join(cur).strip())
    return out


def parse_clause(text: str) -> tuple[str, list[str]]:
    """``(head, body literals)`` of a clause ``head :- l1, l2, ... .``"""
    text = text.strip().rstrip(".").strip()
    head, _, body = text.partition(":-")
    return head.strip(), split_top(body) if body.strip() else []


def _name(lit: str) -> str:
    return lit.split("(", 1)[0].strip()


def _vars(lit: str) -> set:
    # quoted atoms hold no variables
    return set(_VAR.findall(re.sub(r"'[^']*'", "", lit)))


def variants(head: str, body: list[str]) -> list[tuple[str, list[str]]]:
    """``(what was dropped, kept body)`` for each literal that can be dropped (see the module
    docstring), in body order."""
    out = []
    for i, lit in enumerate(body):
        seen = set(_vars(head))
        for prev in body[:i]:
            seen |= _vars(prev)
        new = _vars(lit) - seen
        users = [j for j, other in enumerate(body) if j != i and _vars(other) & new]
        if any(_name(body[j]) not in COMPARISONS for j in users):
            continue  # it links a later literal (has_plane(A,B) before lying(B))
        drop = {i, *users}
        out.append((", ".join(body[j] for j in sorted(drop)),
                    [b for j, b in enumerate(body) if j not in drop]))
    return out


def read_rules(path) -> list[str]:
    """The class clauses of a ``rules.pl`` (one per line; directives and facts of the
    model's statistics left out)."""
    out = []
    for line in Path(path).read_text().splitlines():
        s = line.strip()
        if s and not s.startswith(("%", ":-")) and ":-" in s and not s.startswith("planerel_"):
            out.append(s)
    return out


def clause_text(head: str, body: list[str]) -> str:
    return f"{head} :- {', '.join(body)}." if body else f"{head}."


def support(rules_file, stages, *, timeout: float = 600.0, names: bool = False) -> list[dict]:
    """Rows ``{stage, class, clause, dropped, tp, fp}`` (``dropped`` None: the whole clause),
    each clause scored alone on each stage's task of its class; with ``names`` also ``neg``,
    the negative examples the version proves (atoms, e.g. ``box(s0089_o2)``)."""
    from planerel.ilp.learn import theory_coverage

    rows = []
    for clause in read_rules(rules_file):
        head, body = parse_clause(clause)
        cls = _name(head)
        versions = [(None, body), *variants(head, body)]
        for stage in stages:
            stem = Path(stage) / cls
            if not stem.with_suffix(".b").exists():
                continue
            for dropped, kept in versions:
                c, _, neg = theory_coverage(stem, [clause_text(head, kept)], timeout=timeout)
                row = {"stage": str(stage), "class": cls, "clause": clause,
                       "dropped": dropped, "tp": c.tp, "fp": c.fp}
                if names:
                    row["neg"] = neg
                rows.append(row)
    return rows


#: Names of kept-out negatives printed per row at most (``--names``).
MAX_NAMES = 12


def _kept_out(row, whole) -> str:
    """The negatives ``row``'s version proves and the whole clause does not, by object."""
    if "neg" not in row:
        return ""
    out = sorted(set(row["neg"]) - set(whole["neg"]))
    ids = [re.sub(r"^\w+\((.*)\)$", r"\1", a) for a in out]
    more = f" (+{len(ids) - MAX_NAMES} more)" if len(ids) > MAX_NAMES else ""
    return ": " + ", ".join(ids[:MAX_NAMES]) + more if ids else ""


def table(rows) -> str:
    """Markdown: each clause's proofs whole and, per dropped literal, the positives and
    negatives it adds (``+fp`` is what the literal keeps out; with ``neg`` in the rows, which
    ones)."""
    lines = ["| stage | clause | without | positives | negatives | the literal keeps out |",
             "|---|---|---|---|---|---|"]
    whole = {}
    for r in rows:
        key = (r["stage"], r["clause"])
        if r["dropped"] is None:
            whole[key] = r
            lines.append(f"| {Path(r['stage']).parent.name}/{Path(r['stage']).name} | "
                         f"`{r['clause']}` | (whole) | {r['tp']} | {r['fp']} | |")
        else:
            w = whole[key]
            lines.append(f"| | | `{r['dropped']}` | {r['tp']} ({r['tp'] - w['tp']:+d}) | "
                         f"{r['fp']} ({r['fp'] - w['fp']:+d}) | {r['fp'] - w['fp']} negatives"
                         f"{_kept_out(r, w)} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("rules", help="a model's rules.pl")
    ap.add_argument("stages", nargs="+", help="folders of Aleph tasks CLASS.b/.f/.n")
    ap.add_argument("--timeout", type=float, default=600.0, help="seconds per scoring run")
    ap.add_argument("--names", action="store_true",
                    help=f"name the negatives each literal keeps out (at most {MAX_NAMES} a row)")
    args = ap.parse_args(argv)
    if not Path(args.rules).is_file():
        ap.error(f"no such rules file: {args.rules}")
    for s in args.stages:
        if not Path(s).is_dir():
            ap.error(f"no such folder: {s}")
    from planerel.errors import PlanerelError

    try:
        rows = support(args.rules, args.stages, timeout=args.timeout, names=args.names)
    except PlanerelError as e:  # a task that does not load, a learner over its time
        print(f"clause_support: {e}", file=sys.stderr)
        return 1
    print(table(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
