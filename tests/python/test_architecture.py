"""The package's import rules (docs/architecture.md), checked on its import graph.

Every ``import`` and ``from … import`` of every module — at the top or inside a function — is an
edge. The rules: a module imports only from its own unit or from the units :data:`ALLOWED` lists
for it (so formats and inputs know nothing of datasets, fit nothing of ingest, and nothing in
``lanterna.tiler`` imports the server or the CLI); no import circles between modules; no private
(``_name``) name imported from, or reached into, another module. :func:`check` is run on a small
broken package first, so a checker that finds nothing cannot pass.
"""

from __future__ import annotations

import ast
import statistics
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
#: Where each top-level package of the ``lanterna`` namespace lives in the checkout.
ROOTS = {"lanterna": REPO / "lanterna", "lanterna.tiler": REPO / "tiler",
         "lanterna.manifests": REPO / "manifests", "lanterna.server": REPO / "server"}

E = "lanterna.errors"
T = "lanterna.tiler"
BASE = {E, f"{T}.fileio", f"{T}.progress", f"{T}.documents", f"{T}.limits"}
#: unit → the units it may import (besides itself). A unit is the longest matching prefix.
ALLOWED: dict[str, set[str]] = {
    E: set(),
    "lanterna": set(),  # the package's __init__
    f"{T}.fileio": {E},
    f"{T}.documents": {E, f"{T}.fileio"},
    f"{T}.limits": {E},
    f"{T}.progress": set(),
    f"{T}.entry_names": set(),
    T: set(),  # lanterna/tiler/__init__.py
    f"{T}.formats": BASE,
    f"{T}.inputs": BASE | {f"{T}.formats"},
    f"{T}.iiif": BASE,
    f"{T}.render": BASE | {f"{T}.formats", f"{T}.iiif"},
    "lanterna.manifests": {E},
    f"{T}.dataset": BASE | {f"{T}.entry_names", f"{T}.formats", f"{T}.iiif", f"{T}.render",
                            "lanterna.manifests"},
    f"{T}.overlays": BASE | {f"{T}.iiif", f"{T}.dataset"},
    f"{T}.fit": BASE | {f"{T}.formats", f"{T}.inputs", f"{T}.render", f"{T}.dataset"},
    f"{T}.ingest": BASE | {f"{T}.formats", f"{T}.inputs", f"{T}.iiif", f"{T}.dataset",
                           f"{T}.overlays"},
    f"{T}.demo": BASE | {f"{T}.formats", f"{T}.inputs", f"{T}.iiif", f"{T}.render",
                         f"{T}.dataset", f"{T}.overlays", f"{T}.fit"},
    f"{T}.presets": BASE | {f"{T}.render", f"{T}.dataset"},
    "lanterna.server": {E, f"{T}.entry_names", f"{T}.iiif", f"{T}.presets", f"{T}.overlays"},
    "lanterna.commands": {"*"},
    "lanterna.cli": {"*"},
}
#: Lines per source file: the largest allowed, and the largest allowed median of a folder.
MAX_LINES, MAX_MEDIAN = 450, 200


@dataclass(frozen=True)
class Edge:
    source: str
    target: str
    line: int
    names: tuple[str, ...] = ()


def modules(roots: Mapping[str, Path]) -> dict[str, Path]:
    """Every module of the namespace by dotted name."""
    out: dict[str, Path] = {}
    for name, root in roots.items():
        for path in sorted(root.rglob("*.py")):
            rel = path.relative_to(root).with_suffix("").parts
            if any(part.startswith(".") or part == "__pycache__" for part in rel):
                continue
            parts = [*name.split("."), *rel]
            if parts[-1] == "__init__":
                parts.pop()
            out.setdefault(".".join(parts), path)
    return out


def edges(name: str, path: Path, known: Mapping[str, Path]) -> Iterator[Edge]:
    """The imports of one module that name modules of the namespace."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    tree = ast.parse(path.read_text(), str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name in known:
                    yield Edge(name, alias.name, node.lineno)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                module = ".".join(base + ([node.module] if node.module else []))
            else:
                module = node.module or ""
            for alias in node.names:
                sub = f"{module}.{alias.name}"
                if sub in known:
                    yield Edge(name, sub, node.lineno)
                elif module in known:
                    yield Edge(name, module, node.lineno, (alias.name,))


def reached_private(name: str, path: Path, known: Mapping[str, Path]) -> Iterator[str]:
    """``alias._private`` where ``alias`` is another module of the namespace bound by an import."""
    tree = ast.parse(path.read_text(), str(path))
    aliases: dict[str, str] = {}
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            base = package.split(".")[: len(package.split(".")) - node.level + 1] if node.level \
                else []
            module = ".".join(base + ([node.module] if node.module else []))
            for alias in node.names:
                if f"{module}.{alias.name}" in known:
                    aliases[alias.asname or alias.name] = f"{module}.{alias.name}"
        elif isinstance(node, ast.Import):
            for alias in node.names:
                if alias.asname and alias.name in known:
                    aliases[alias.asname] = alias.name
    for node in ast.walk(tree):
        if (isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name)
                and node.value.id in aliases and node.attr.startswith("_")
                and not node.attr.startswith("__")):
            yield f"{name}:{node.lineno} reaches {aliases[node.value.id]}.{node.attr}"


def unit_of(module: str) -> str:
    """The unit of :data:`ALLOWED` a module belongs to (its longest matching prefix)."""
    best = ""
    for unit in ALLOWED:
        if (module == unit or module.startswith(unit + ".")) and len(unit) > len(best):
            best = unit
    if not best:
        raise AssertionError(f"{module} belongs to no unit of ALLOWED: add it")
    return best


def circles(graph: Mapping[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    found: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
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
                found.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def check(roots: Mapping[str, Path]) -> list[str]:
    """Every broken rule, one line each."""
    known = modules(roots)
    problems: list[str] = []
    graph: dict[str, set[str]] = {m: set() for m in known}
    for name, path in known.items():
        unit = unit_of(name)
        for edge in edges(name, path, known):
            graph[name].add(edge.target)
            target_unit = unit_of(edge.target)
            allowed = ALLOWED[unit]
            if target_unit != unit and "*" not in allowed and target_unit not in allowed:
                problems.append(f"{name}:{edge.line} imports {edge.target} ({unit} may not "
                                f"import {target_unit})")
            private = [n for n in edge.names if n.startswith("_") and not n.startswith("__")]
            if private and edge.target != name:
                problems.append(f"{name}:{edge.line} imports private {', '.join(private)} "
                                f"from {edge.target}")
        problems.extend(reached_private(name, path, known))
    problems.extend("import circle: " + " -> ".join(c) for c in circles(graph))
    return problems


def write(root: Path, files: Mapping[str, str]) -> None:
    for rel, text in files.items():
        (root / rel).parent.mkdir(parents=True, exist_ok=True)
        (root / rel).write_text(text)


def test_the_checker_finds_every_kind_of_broken_rule(tmp_path: Path) -> None:
    """A small package that breaks each rule once: each is reported."""
    write(tmp_path / "tiler", {
        "__init__.py": "",
        "formats/__init__.py": "",
        "formats/a.py": "from lanterna.tiler.dataset import b\n",  # formats -> dataset
        "dataset/__init__.py": "",
        "dataset/b.py": "def f():\n    from lanterna.tiler.dataset.c import g\n",
        "dataset/c.py": "from .b import f\nfrom lanterna.tiler.formats.a import _hidden\n",
        "fit/__init__.py": "",
        "fit/d.py": "from lanterna.tiler.formats import a\nx = a._inner\n",
    })
    problems = check({T: tmp_path / "tiler"})
    text = "\n".join(problems)
    assert "lanterna.tiler.formats.a:1 imports lanterna.tiler.dataset.b" in text
    assert "import circle: lanterna.tiler.dataset.b -> lanterna.tiler.dataset.c" in text
    assert "imports private _hidden from lanterna.tiler.formats.a" in text
    assert "reaches lanterna.tiler.formats.a._inner" in text
    assert len(problems) == 4, text


def test_allowed_units_form_no_circle() -> None:
    graph = {unit: {u for u in allowed if u != "*"} for unit, allowed in ALLOWED.items()}
    assert circles(graph) == []


def test_the_package_keeps_its_import_rules() -> None:
    assert check(ROOTS) == []


def test_every_module_is_in_a_unit_and_every_unit_has_modules() -> None:
    known = modules(ROOTS)
    used = {unit_of(m) for m in known}
    assert set(ALLOWED) - used == set(), "units in ALLOWED without modules: remove them"


def source_folders() -> dict[Path, list[int]]:
    """Lines per ``.py`` file, by folder, of the package and the tests."""
    folders: dict[Path, list[int]] = {}
    for root in [*ROOTS.values(), REPO / "tests" / "python"]:
        for path in root.rglob("*.py"):
            if "__pycache__" in path.parts or path.name == "__init__.py":
                continue
            folders.setdefault(path.parent, []).append(len(path.read_text().splitlines()))
    return folders


@pytest.mark.parametrize("folder", sorted(source_folders()), ids=lambda p: str(p.relative_to(REPO)))
def test_files_stay_small(folder: Path) -> None:
    sizes = {p.name: len(p.read_text().splitlines()) for p in folder.glob("*.py")
             if p.name != "__init__.py"}
    too_long = {name: n for name, n in sizes.items() if n > MAX_LINES}
    assert too_long == {}, f"split these files (> {MAX_LINES} lines)"
    assert statistics.median(sizes.values()) <= MAX_MEDIAN
