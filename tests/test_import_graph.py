"""The package layout (docs/architecture.md): one subpackage per stage, no import cycles, and no
stage imports a later one.

Every module's imports are read with ``ast`` -- at the top of the module and inside functions --
and resolved to the module they name.  The allowed order is stated here, not read from the code:

    base (errors, atomic, children, compile_notice, progress, _version, parameters: the
    --param sections' names; it loads their classes by name, on demand)
      < io < segment < features < batch < ilp < classify < report < commands < api, cli, __main__, planerel

with ``synth`` beside ilp: it may use base, io, segment and features (it builds data-set
folders), and only report and the front ends (commands, api, cli) may use it.
"""

from __future__ import annotations

import ast
from pathlib import Path

PKG = Path(__file__).resolve().parents[1] / "planerel"

#: group -> groups its modules may import (besides their own group).
BASE = {"base"}
ALLOWED = {
    "base": set(),
    "io": BASE,
    "segment": BASE | {"io"},
    "features": BASE | {"io", "segment"},
    "synth": BASE | {"io", "segment", "features"},
    "batch": BASE | {"io", "segment", "features"},
    "ilp": BASE | {"io", "segment", "features", "batch"},
    "classify": BASE | {"io", "segment", "features", "batch", "ilp"},
    "report": BASE | {"io", "segment", "features", "batch", "ilp", "classify", "synth"},
    "commands": BASE | {"io", "segment", "features", "batch", "ilp", "classify", "synth",
                        "report"},
    "top": BASE | {"io", "segment", "features", "batch", "ilp", "classify", "synth", "report",
                   "commands"},
}
#: top-level modules and the group they belong to (subpackages are their own group).
TOP_LEVEL = {"errors": "base", "atomic": "base", "children": "base", "compile_notice": "base", "progress": "base",
             "_version": "base", "parameters": "base",
             "batch": "batch", "api": "top", "cli": "top", "__main__": "top", "__init__": "top"}


def _modules() -> dict[str, Path]:
    out = {}
    for f in PKG.rglob("*.py"):
        parts = ("planerel", *f.relative_to(PKG).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = f
    return out


MODULES = _modules()


def group(mod: str) -> str:
    parts = mod.split(".")
    if len(parts) == 1:
        return TOP_LEVEL["__init__"]
    if (PKG / parts[1]).is_dir():
        return parts[1]
    return TOP_LEVEL[parts[1]]


def _resolve(name: str) -> str:
    """The deepest existing module of a dotted name (a name imported from a module is that
    module)."""
    while name not in MODULES:
        name = name.rsplit(".", 1)[0]
    return name


def imports(mod: str, top_only: bool = False) -> set[str]:
    """Modules of planerel that ``mod`` imports (``top_only``: only those run at import time,
    i.e. not inside a function)."""
    f = MODULES[mod]
    tree = ast.parse(f.read_text(), str(f))
    pkg = mod if f.name == "__init__.py" else mod.rsplit(".", 1)[0]
    nodes = tree.body if top_only else list(ast.walk(tree))
    if top_only:  # imports under if/try at module level run at import time too
        nodes = [n for top in tree.body if not isinstance(top, (ast.FunctionDef,
                 ast.AsyncFunctionDef, ast.ClassDef)) for n in ast.walk(top)]
    out = set()
    for n in nodes:
        if isinstance(n, ast.Import):
            out |= {_resolve(a.name) for a in n.names if a.name.split(".")[0] == "planerel"}
        elif isinstance(n, ast.ImportFrom):
            if n.level:
                base = pkg.split(".")[: len(pkg.split(".")) - (n.level - 1)]
                src = ".".join([*base, *([n.module] if n.module else [])])
            else:
                src = n.module or ""
            if src.split(".")[0] != "planerel":
                continue
            for a in n.names:
                out.add(_resolve(f"{src}.{a.name}"))
    out.discard(mod)
    return out


def _cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one node (Tarjan)."""
    index, low, stack, on, comps = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(edges.get(v, ())):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                comps.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return comps


def test_every_module_belongs_to_a_stated_group():
    for mod in MODULES:
        assert group(mod) in ALLOWED, mod


def test_no_stage_imports_a_later_one():
    bad = []
    for mod in sorted(MODULES):
        g = group(mod)
        for dep in sorted(imports(mod)):
            h = group(dep)
            if h != g and h not in ALLOWED[g]:
                bad.append(f"{mod} ({g}) imports {dep} ({h})")
    assert not bad, "upward imports:\n" + "\n".join(bad)


def test_the_stage_graph_has_no_cycle():
    edges: dict[str, set[str]] = {}
    for mod in MODULES:
        edges.setdefault(group(mod), set()).update(group(d) for d in imports(mod))
    for g in edges:
        edges[g].discard(g)
    assert _cycles(edges) == []


def test_no_import_cycle_between_modules_at_import_time():
    edges = {m: imports(m, top_only=True) for m in MODULES}
    assert _cycles(edges) == []


#: Mutual imports inside functions (deferred, so they load) that are left as they are: each
#: pair lives inside one package.  The list may only shrink.
KNOWN_DEFERRED_CYCLES = [
    ["planerel.synth.generator", "planerel.synth.sensor", "planerel.synth.world"],
]


def test_no_new_import_cycle_counting_imports_inside_functions():
    edges = {m: imports(m) for m in MODULES}
    assert _cycles(edges) == KNOWN_DEFERRED_CYCLES


def test_normals_and_region_growing_do_not_import_each_other():
    n, r = "planerel.segment.normals", "planerel.segment.regiongrow"
    assert r not in imports(n)
    assert n in imports(r)


def test_the_checker_sees_imports_inside_functions_and_flags_an_upward_one(tmp_path):
    src = "def f():\n    from planerel.ilp import pipeline\n"
    tree = ast.parse(src)
    found = [n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)]
    assert found == ["planerel.ilp"]
    assert "ilp" not in ALLOWED["features"]


def test_only_the_prolog_bridge_starts_prolog():
    """Every ``swipl`` command line and the pyswip engine come from :mod:`planerel.ilp.prolog`:
    no other module names pyswip or builds a command from ``find_swipl``'s executable."""
    bridge = "planerel.ilp.prolog"
    for mod, f in MODULES.items():
        if mod == bridge:
            continue
        text = f.read_text()
        assert "pyswip" not in imports_text(f), f"{mod} imports pyswip"
        assert '"-g"' not in text and "'-g'" not in text, f"{mod} builds a swipl command itself"


def imports_text(f: Path) -> str:
    """The names of every module ``f`` imports (top level and inside functions)."""
    names = []
    for n in ast.walk(ast.parse(f.read_text())):
        if isinstance(n, ast.Import):
            names += [a.name for a in n.names]
        elif isinstance(n, ast.ImportFrom) and n.module:
            names.append(n.module)
    return " ".join(names)
