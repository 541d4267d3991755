"""``planerel params``: the names ``--param`` takes, with their values and meaning."""

from __future__ import annotations

__all__ = ["register", "run"]

#: The commands that take each section's ``--param``.
_TAKEN_BY = {"segmentation": "segment, describe, learn, classify",
             "ransac": "segment, describe, learn, classify (with --method sp or snp)",
             "split": "segment, describe, learn, classify",
             "decision": "classify, evaluate-model"}
_DESCRIPTION = "describe, classify"
#: What to read for a parameter its class does not document.
_UNSAID = {"relations": "(docs/predicates.md: the relation it tunes)"}


def register(sub) -> None:
    p = sub.add_parser(
        "params",
        help="list the parameters --param takes: sections, names, values and meaning",
        description="Without SECTION: the sections of --param NAME=VALUE (a bare NAME is a "
                    "segmentation parameter, SECTION.NAME one of another section) and the "
                    "commands that take them. With SECTION (e.g. relations): each of its "
                    "parameters as --param writes it, its default value and the first sentence "
                    "of its documentation. With one parameter (theta, relations.standing_fill): "
                    "its whole documentation.",
    )
    p.add_argument("section", nargs="?", metavar="SECTION[.NAME]",
                   help="a section (segmentation, ransac, split, gravity, planes, relations, "
                        "proposals, curved, decision), or one parameter")
    p.add_argument("--model", metavar="MODEL",
                   help="show the values the model was learned with (its model.json) instead "
                        "of the defaults")
    p.set_defaults(func=run)


def _model_values(model, section: str) -> dict | None:
    """``{name: value}`` of ``section`` in the model's settings (None: no model.json)."""
    from pathlib import Path

    from planerel.errors import InputError
    from planerel.ilp.model_settings import read_settings
    from planerel.parameters import BARE

    rules = Path(model)
    rules = rules / "rules.pl" if rules.is_dir() else rules
    if not rules.is_file():
        raise InputError(f"--model {model}: no such model (give MODEL_DIR or MODEL_DIR/rules.pl)")
    settings = read_settings(rules)
    if settings is None:
        return None
    if section in BARE or section == "split":
        resolved = settings.resolved() or {}
        if section == "split":
            return {k[len("split."):]: v for k, v in resolved.items() if k.startswith("split.")}
        return {k: v for k, v in resolved.items() if not k.startswith("split.")}
    return dict(settings.sections.get(section, {}))


def _find(text: str) -> tuple[str, str | None]:
    """``(section, name or None)`` of ``SECTION``, ``SECTION.NAME`` or a bare ``NAME``."""
    from planerel.errors import InputError, did_you_mean
    from planerel.parameters import SECTIONS, names_of, unknown_parameters, unknown_section

    if text in SECTIONS:
        return text, None
    sec, dot, key = text.partition(".")
    if dot and sec not in SECTIONS:
        raise unknown_section(text)
    if not dot:
        sec, key = "segmentation", text
        if key not in names_of(sec):
            near = did_you_mean(text, SECTIONS)
            if near:
                raise InputError(f"no section or parameter {text!r}{near}; 'planerel params' "
                                 "lists the sections")
    if key not in names_of(sec):
        raise unknown_parameters(sec, [key])
    return sec, key


def run(args) -> int:
    import textwrap

    from planerel.parameters import SECTIONS, names_of, parameter_rows, written

    if args.section is None:
        print("--param NAME=VALUE: a bare NAME is a segmentation parameter, SECTION.NAME a "
              "parameter of another section (repeat --param for more). Sections:")
        for name, (_, _, what) in SECTIONS.items():
            how = written(name, "NAME")
            print(f"  {name:<13} {how:<15} {len(names_of(name)):>3}  {what}")
        print("segment and learn take segmentation (or ransac) and split parameters; describe "
              "every section but\ndecision; classify every section; evaluate-model decision "
              "only. 'planerel params SECTION' lists\na section's parameters with their values "
              "and meaning; --model MODEL shows a model's values.")
        return 0
    section, key = _find(args.section.strip())
    values = _model_values(args.model, section) if args.model else None
    rows = parameter_rows(section, values)
    if key is not None:
        from planerel.parameters import meanings, section_class

        shown, value, _ = next(r for r in rows if r[0] == written(section, key))
        meaning = meanings(section_class(section)).get(key, "")
        print(f"{shown} = {value}" + (" (the model's value)" if values is not None and key in values
                                      else " (default)"))
        if meaning:
            print(textwrap.fill(meaning, 100, initial_indent="    ", subsequent_indent="    "))
        return 0
    what = SECTIONS[section][2]
    source = (f"the values of {args.model}" if values is not None else
              "default values" + (" (the model keeps no settings)" if args.model else ""))
    how = written(section, "NAME")
    print(f"{section}: {what}\n--param {how}=VALUE ({_TAKEN_BY.get(section, _DESCRIPTION)}); "
          f"{source}; 'planerel params {how}' gives one whole:")
    for shown, value, meaning in rows:
        print(f"  {shown} = {value}")
        meaning = meaning or _UNSAID.get(section, "")
        if meaning:
            print(textwrap.fill(meaning, 100, initial_indent="      ",
                                subsequent_indent="      "))
    return 0
