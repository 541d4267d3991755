"""The settings a model was learned with, kept in the model (``MODEL_DIR/model.json``).

Rules are only as good as the planes they were learned on: a rule about "a plane 0.15 m above
another" means something else when ``classify`` segments or measures differently.  ``planerel
learn`` therefore writes next to ``rules.pl`` the segmentation (method, parameters as given
and resolved, including the sensor-adaptive switch ``adapt`` of
:mod:`planerel.segment.adapt`), the gravity estimate's parameters, the plane, relation and
proposal parameters of the description, the rules' measured precision, and the planar
fractions of each class's training positives and the proof scales of each rule's, with the
decision's margins (section ``decision``, ``planar_domain``, ``proof_domain``, ``level_domain``,
``size_domain``, ``slender_domain``, ``range_domain``:
:func:`planerel.ilp.metrics.planar_refusals`, :func:`~planerel.ilp.metrics.proof_refusals`).  ``classify`` reads them back
and runs with the same settings; ``--param`` overrides one, with a warning when it differs from
the training value.

Override names: a bare name is a segmentation parameter (``theta=12``, ``split=false``,
``preset=paper``), and so is ``split.NAME``, a field of the segmentation's post-processing
(:class:`~planerel.segment.split.SplitParams`, e.g. ``split.small_faces=150``); ``gravity.NAME``, ``planes.NAME``, ``relations.NAME`` and
``proposals.NAME`` and ``curved.NAME`` set a field of :class:`~planerel.features.gravity.GravityParams`,
:class:`~planerel.features.planes.PlaneParams`, :class:`~planerel.features.relations.RelationParams`,
:class:`~planerel.features.proposal_params.ProposalParams` and :class:`~planerel.features.curved.CurvedParams`;
``decision.NAME`` one of :class:`~planerel.ilp.metrics.DecisionParams` (``decision.planar_gate``,
``decision.planar_margin``, ``decision.proof_gate``, ``decision.proof_margin``,
``decision.veto_ratio``, ``decision.level_gate``, ``decision.flight_gate``,
``decision.flight_fragments``, ``decision.unsure_gate``, ``decision.unsure_upside``, ``decision.unsure_sparse``, ``decision.size_gate``, ``decision.size_margin``, ``decision.slender_gate``,
``decision.slender_margin``, ``decision.range_gate``, ``decision.range_margin``,
``decision.range_classes``, ``decision.facet_gate``, ``decision.facet_min``,
``decision.facet_max``, ``decision.facet_bridge``, ``decision.pitch_gate``,
``decision.pitch_tol``, ``decision.flight_side_gate``,
``decision.flight_side_thick``, ``decision.flight_side_gap``, ``decision.flight_side_reach``,
``decision.flight_side_rise``, ``decision.flight_side_angle``, ``decision.flight_trim``,
``decision.flight_trim_angle``, ``decision.flight_trim_edge``, ``decision.flight_trim_rise``,
``decision.hang_gate``, ``decision.hang_share``, ``decision.hang_drop``, ``decision.hang_level``,
``decision.hang_lines``, ``decision.long_lying_gate``, ``decision.long_lying_length``,
``decision.slab_gate``, ``decision.slab_width``, ``decision.slab_drop``,
``decision.crowd_gate``, ``decision.crowd_planes``,
``decision.narrow_face_gate``, ``decision.narrow_face_ratio``, ``decision.far_gate``,
``decision.slope_parts_gate``, ``decision.slope_parts_tol``,
``decision.cut_boxes``, ``decision.cut_reach``,
``decision.cut_margin``, ``decision.cut_corner``, ``decision.cut_pieces``).
"""

from __future__ import annotations

import dataclasses
import json
from dataclasses import dataclass, field
from pathlib import Path

from planerel.errors import InputError
from planerel.parameters import SECTIONS as _PARAM_SECTIONS
from planerel.parameters import unknown_parameters, unknown_section

__all__ = ["MODEL_FILE", "FORMAT", "SECTIONS", "ModelSettings", "training_settings",
           "read_settings", "with_overrides"]

MODEL_FILE = "model.json"
FORMAT = "planerel-model/1"
#: Description settings besides the segmentation: section name -> dataclass (import path).
SECTIONS = {name: (module, cls) for name, (module, cls, _) in _PARAM_SECTIONS.items()
            if name not in ("segmentation", "ransac", "split")}
#: Sections that are not settings of the description (:meth:`ModelSettings.describe_kwargs`).
_DECISION_SECTIONS = ("decision",)
#: Segmentation keywords of :func:`planerel.segment.segment` that are not parameter fields.
_SEGMENT_KEYWORDS = ("split",)


def _section_class(name: str):
    import importlib

    module, cls = SECTIONS[name]
    return getattr(importlib.import_module(module), cls)


def _resolved_segmentation(method: str, params: dict) -> dict | None:
    """Every field of the method's parameter dataclass (defaults filled in), or None for
    ``gt`` (ground-truth planes: nothing to resolve)."""
    if method == "gt":
        return None
    from planerel.segment import SPLIT_PREFIX, make_params, split_fields
    from planerel.segment.split import SplitParams

    fields, split_params = split_fields({k: v for k, v in params.items()
                                         if k not in _SEGMENT_KEYWORDS})
    out = dataclasses.asdict(make_params(method, **fields))
    for k in _SEGMENT_KEYWORDS:
        if k in params:
            out[k] = params[k]
    if method == "regiongrow" or split_params is not None:
        # the post-processing's fields (it runs after region growing by default)
        for k, v in dataclasses.asdict(split_params or SplitParams()).items():
            out[SPLIT_PREFIX + k] = v
    return out


@dataclass(frozen=True)
class ModelSettings:
    """Segmentation and description settings of a model.

    Attributes
    ----------
    method : str
        ``regiongrow``, ``sp``, ``snp`` (or ``gt`` for a model learned from ground-truth planes).
    seg_params : dict
        Segmentation parameters as given (the rest are the method's defaults).
    sections : dict
        ``{section: {field: value}}`` for :data:`SECTIONS`.
    planar_domain : tuple
        ``(class, low, high, n)``: planar fractions of each class's training positives
        (empty for a model written before they were kept: no planar gate).
    proof_domain : tuple
        ``(index, class, low, high, n)``: the proof scales of each rule's training positives
        (:func:`planerel.ilp.metrics.proof_domain`; empty for a model written before they
        were kept: no proof gate).
    level_domain : tuple
        ``(class, low, n)``: the fewest horizontal planes of each class's training positives
        (:func:`planerel.ilp.metrics.level_domain`; empty for a model written before they were
        kept: no level gate).
    size_domain : tuple
        ``(class, high, n)``: the longest plane of each class's training proofs
        (:func:`planerel.ilp.metrics.size_domain`; empty for a model written before it was
        kept: no size gate).
    slender_domain : tuple
        ``(class, high, n)``: the most slender top of each class's training proofs
        (:func:`planerel.ilp.metrics.slender_domain`; empty for a model written before it was
        kept: no slenderness gate).
    range_domain : tuple
        ``(class, high, n)``: the farthest plane from the sensor of each class's training
        proofs (:func:`planerel.ilp.metrics.range_domain`; empty for a model written before it
        was kept: no range gate).
    """

    method: str = "regiongrow"
    seg_params: dict = field(default_factory=dict)
    sections: dict = field(default_factory=dict)
    planar_domain: tuple = ()
    proof_domain: tuple = ()
    #: The segmentation parameters ``model.json`` records (its ``resolved`` keys), or None
    #: when unknown: a parameter added after the model was written is not among them, and its
    #: value is today's default, not a training value.
    seg_recorded: frozenset | None = None
    level_domain: tuple = ()
    size_domain: tuple = ()
    slender_domain: tuple = ()
    range_domain: tuple = ()
    #: ``(index, class, tp, fp)`` of each rule, as ``model.json``'s ``rule_precision``
    #: records them (the ``planerel_rule_stats/4`` facts ``rules.pl`` was written with)
    rule_stats: tuple = ()
    #: ``model.json``'s ``background`` entry, ``{"file": ..., "sha256": ...}``: the background
    #: file of the user's own the rules were learned with (:mod:`planerel.ilp.background`);
    #: None for a model without one
    background: dict | None = None

    def describe_kwargs(self) -> dict:
        """Keyword arguments of :func:`planerel.features.facts.describe_scene` for these settings."""
        kw = {}
        names = {"gravity": "gravity_params", "planes": "plane_params",
                 "relations": "relation_params", "proposals": "proposal_params",
                 "curved": "curved_params"}
        for name, values in self.sections.items():
            if name in _DECISION_SECTIONS:
                continue
            cls = _section_class(name)
            known = {f.name for f in dataclasses.fields(cls)}
            kw[names[name]] = cls(**{k: v for k, v in values.items() if k in known})
        return kw

    def decision_params(self):
        """The decision's settings (:class:`~planerel.ilp.metrics.DecisionParams`; its defaults
        when the model keeps none)."""
        cls = _section_class("decision")
        known = {f.name for f in dataclasses.fields(cls)}
        return cls(**{k: v for k, v in self.sections.get("decision", {}).items() if k in known})

    def resolved(self) -> dict | None:
        """The segmentation parameters with defaults filled in."""
        return _resolved_segmentation(self.method, self.seg_params)


def training_settings(method: str, seg_params: dict | None, *, rule_stats=(),
                      planar_domain=(), proof_domain=(), decision: dict | None = None,
                      level_domain=(), size_domain=(), slender_domain=(),
                      range_domain=(), background: dict | None = None) -> dict:
    """The content of ``model.json`` for a model learned with these settings (the description
    parameters are the defaults ``planerel learn`` describes scenes with; ``planar_domain``,
    ``proof_domain``, ``level_domain``, ``size_domain``, ``slender_domain``, ``range_domain``:
    :attr:`planerel.ilp.pipeline.Model.planar_domain`, ``.proof_domain``, ``.level_domain``,
    ``.size_domain``, ``.slender_domain``, ``.range_domain``;
    ``decision``: a recipe's decision settings in place of the defaults; ``background``: the
    entry ``{"file": ..., "sha256": ...}`` of the model's background file of the user's own,
    written only when given)."""
    from planerel.ilp.metrics import laplace

    seg_params = dict(seg_params or {})
    sections = {name: dataclasses.asdict(_section_class(name)()) for name in SECTIONS}
    unknown = sorted(set(decision or {}) - set(sections["decision"]))
    if unknown:
        raise InputError(f"unknown decision setting(s) {', '.join(unknown)}")
    sections["decision"].update(decision or {})
    out = {
        "format": FORMAT,
        "segmentation": {"method": method, "params": seg_params,
                         "resolved": _resolved_segmentation(method, seg_params)},
        **sections,
        "rule_precision": [{"index": i, "class": k, "tp": tp, "fp": fp,
                            "laplace": round(laplace(tp, fp), 6)} for i, k, tp, fp in rule_stats],
        "planar_domain": [{"class": k, "low": lo, "high": hi, "n": n}
                          for k, lo, hi, n in planar_domain],
        "proof_domain": [{"rule": i, "class": k, "low": lo, "high": hi, "n": n}
                         for i, k, lo, hi, n in proof_domain],
        "level_domain": [{"class": k, "low": lo, "n": n} for k, lo, n in level_domain],
        "size_domain": [{"class": k, "high": hi, "n": n} for k, hi, n in size_domain],
        "slender_domain": [{"class": k, "high": hi, "n": n} for k, hi, n in slender_domain],
        "range_domain": [{"class": k, "high": hi, "n": n} for k, hi, n in range_domain],
    }
    if background is not None:
        out["background"] = dict(background)
    return out


def read_settings(rules_path) -> ModelSettings | None:
    """The settings in ``model.json`` next to a model's ``rules.pl`` (None when the model has
    none: a model written before the settings were kept, or rules written by hand).

    Raises
    ------
    InputError
        The file is not valid JSON or not a planerel model's settings.
    """
    path = Path(rules_path).parent / MODEL_FILE
    if not path.is_file():
        return None
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as exc:
        raise InputError(f"{path}: not a readable model settings file ({exc})") from None
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise InputError(f"{path}: not a planerel model settings file (format {FORMAT!r} expected)")
    seg = data.get("segmentation") or {}
    sections = {name: dict(data[name]) for name in SECTIONS if isinstance(data.get(name), dict)}
    domain = []
    for entry in data.get("planar_domain") or ():
        try:
            domain.append((str(entry["class"]), float(entry["low"]), float(entry["high"]),
                           int(entry["n"])))
        except (KeyError, TypeError, ValueError):
            raise InputError(f"{path}: planar_domain entry {entry!r} is not "
                             "{class, low, high, n}") from None
    proofs = []
    for entry in data.get("proof_domain") or ():
        try:
            proofs.append((int(entry["rule"]), str(entry["class"]), float(entry["low"]),
                           float(entry["high"]), int(entry["n"])))
        except (KeyError, TypeError, ValueError):
            raise InputError(f"{path}: proof_domain entry {entry!r} is not "
                             "{rule, class, low, high, n}") from None
    levels = []
    for entry in data.get("level_domain") or ():
        try:
            levels.append((str(entry["class"]), int(entry["low"]), int(entry["n"])))
        except (KeyError, TypeError, ValueError):
            raise InputError(f"{path}: level_domain entry {entry!r} is not "
                             "{class, low, n}") from None
    sizes, slenders, ranges = [], [], []
    for key, out in (("size_domain", sizes), ("slender_domain", slenders),
                     ("range_domain", ranges)):
        for entry in data.get(key) or ():
            try:
                out.append((str(entry["class"]), float(entry["high"]), int(entry["n"])))
            except (KeyError, TypeError, ValueError):
                raise InputError(f"{path}: {key} entry {entry!r} is not "
                                 "{class, high, n}") from None
    stats = []
    for entry in data.get("rule_precision") or ():
        try:
            stats.append((int(entry["index"]), str(entry["class"]), int(entry["tp"]),
                          int(entry["fp"])))
        except (KeyError, TypeError, ValueError):
            raise InputError(f"{path}: rule_precision entry {entry!r} is not "
                             "{index, class, tp, fp}") from None
    resolved = seg.get("resolved")
    background = data.get("background")
    if background is not None and not (isinstance(background, dict)
                                       and isinstance(background.get("file"), str)
                                       and isinstance(background.get("sha256"), str)):
        raise InputError(f"{path}: background entry {background!r} is not {{file, sha256}}")
    return ModelSettings(str(seg.get("method", "regiongrow")), dict(seg.get("params") or {}),
                         sections, tuple(domain), tuple(proofs),
                         frozenset(resolved) if isinstance(resolved, dict) else None,
                         tuple(levels), tuple(sizes), tuple(slenders), tuple(ranges),
                         tuple(stats), background)


def _coerce_like(value, like, name: str):
    """A command-line string as the type of the training value ``like``."""
    if not isinstance(value, str):
        return value
    text = value.strip()
    try:
        if isinstance(like, bool):
            if text.lower() in ("true", "1", "yes"):
                return True
            if text.lower() in ("false", "0", "no"):
                return False
            raise ValueError(text)
        if isinstance(like, int):
            return int(text)
        if isinstance(like, float):
            return float(text)
    except ValueError:
        raise InputError(f"--param {name}={value}: expected a {type(like).__name__}") from None
    return text


def with_overrides(settings: ModelSettings | None, *, method: str | None = None,
                   overrides: dict | None = None) -> tuple[ModelSettings, list[str]]:
    """Settings to classify with: the model's, changed by ``method`` and ``overrides``.

    Returns
    -------
    (ModelSettings, list of str)
        The settings, and one warning per value that differs from the training value (none
        when the model keeps no settings: nothing to compare with).
    """
    from collections.abc import Mapping

    from planerel.segment import METHODS

    if method is not None and method not in METHODS:
        raise InputError(f"unknown segmentation method {method!r}; choose one of "
                         f"{', '.join(METHODS)}")
    if overrides is not None and (not isinstance(overrides, Mapping)
                                  or not all(isinstance(k, str) for k in overrides)):
        raise InputError(f"parameters must be a mapping of names to values, e.g. "
                         f"{{'theta': 20}}; got {overrides!r}")
    base = settings or ModelSettings()
    warnings: list[str] = []
    new_method = base.method
    if base.method == "gt":
        new_method = method or "regiongrow"
        warnings.append(f"the model was learned from ground-truth planes; scans are segmented "
                        f"with {new_method}")
    elif method is not None and method != base.method:
        new_method = method
        if settings is not None:
            warnings.append(f"segmentation method {method} differs from the model's training "
                            f"method {base.method}")
    seg = dict(base.seg_params) if new_method == base.method else {}
    sections = {k: dict(v) for k, v in base.sections.items()}
    section_over: list[tuple[str, str, object]] = []
    for name, value in (overrides or {}).items():
        sec, dot, key = str(name).partition(".")
        if dot and sec != "split":  # split.NAME is a segmentation parameter
            if sec not in SECTIONS:
                raise unknown_section(name)
            fields = {f.name: f for f in dataclasses.fields(_section_class(sec))}
            if key not in fields:
                raise unknown_parameters(sec, [key])
            current = sections.get(sec, {}).get(key, dataclasses.asdict(_section_class(sec)())[key])
            section_over.append((sec, key, _coerce_like(value, current, name)))
        else:
            seg[name] = value
    for sec, key, value in section_over:
        recorded = key in sections.get(sec, {})
        old = sections.setdefault(sec, {}).get(key, dataclasses.asdict(_section_class(sec)())[key])
        sections[sec][key] = value
        if settings is not None and value != old:
            warnings.append(f"{sec}.{key}={value} differs from the model's training value {old}"
                            if recorded else
                            f"{sec}.{key}={value} differs from the default {old} (the model "
                            f"does not record {sec}.{key}: it was written before the setting "
                            f"existed)")
    out = ModelSettings(new_method, seg, sections, base.planar_domain, base.proof_domain,
                        base.seg_recorded, base.level_domain, base.size_domain,
                        base.slender_domain, base.range_domain, base.rule_stats,
                        base.background)
    out.describe_kwargs()  # a bad value fails here, with the dataclass's message
    out.decision_params()
    out.resolved()  # and a bad segmentation name, before any scan (a model with no model.json too)
    if settings is not None and new_method == base.method and seg != base.seg_params:
        before, after = base.resolved() or {}, out.resolved() or {}
        known = base.seg_recorded
        for key in sorted(after):
            if after[key] != before.get(key):
                warnings.append(f"segmentation {key}={after[key]} differs from the model's "
                                f"training value {before.get(key)}"
                                if known is None or key in known else
                                f"segmentation {key}={after[key]} differs from the default "
                                f"{before.get(key)} (the model does not record {key}: it was "
                                f"written before the setting existed)")
    return out, warnings
