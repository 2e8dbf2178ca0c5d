"""The package's layers (docs/explanation/architecture.md): each layer imports only the layers below it, and
the heavy third-party libraries stay in the one layer that needs them.

Every ``import`` statement of every module is read with :mod:`ast` (function-level imports
included, since lazy imports are imports too), so the test needs no import side effects.
"""

import ast
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "selfalign"

#: layer -> the layers it may import (besides itself).  docs/explanation/architecture.md draws the same.
ALLOWED = {
    "model": set(),
    "solvers": {"model"},
    "analysis": {"model", "solvers"},
    "io": {"model", "solvers"},
    "plots": {"model", "solvers", "analysis", "io"},
    "stages": {"model", "solvers", "analysis", "io", "plots"},
    "cli": {"model", "solvers", "analysis", "io"},
}
#: Third-party library -> the layers that may import it.
THIRD_PARTY = {
    "numba": {"solvers"},
    "matplotlib": {"plots"},
    "h5py": {"io"},
    "rerun": {"io"},
    "snakemake": set(),
    "scipy": {"solvers", "analysis"},
    "click": {"cli"},
}
#: Modules at the package's top level below every layer: any layer may import them, and they
#: import nothing of the package and no third-party library (progress reporting of long loops).
FOUNDATION = {"selfalign.progress"}


def imports(source: str, package: str) -> list[tuple[str, int]]:
    """(imported name as an absolute dotted path, line) for every import in ``source``, a module of
    the dotted ``package``."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            found += [(alias.name, node.lineno) for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                name = ".".join(base + ([node.module] if node.module else []))
            else:
                name = node.module
            found += [(f"{name}.{alias.name}" if node.module is None else name, node.lineno)
                      for alias in node.names]
    return found


def layer_of(path: Path) -> str | None:
    parts = path.relative_to(PACKAGE).parts
    return parts[0] if len(parts) > 1 else None


def violations(layer: str, found: list[tuple[str, int]]) -> list[str]:
    """The imports in ``found`` that ``layer`` may not make."""
    bad = []
    for name, line in found:
        top = name.split(".")
        if name == "selfalign.__version__" or any(name == m or name.startswith(m + ".") for m in FOUNDATION):
            continue
        if top[0] == "selfalign":
            if len(top) == 1 or top[1] not in ALLOWED:
                bad.append(f"line {line}: {name} (the package's top level; import from the layer itself)")
            elif top[1] != layer and top[1] not in ALLOWED[layer]:
                bad.append(f"line {line}: {name} ({top[1]} is not below {layer})")
        elif top[0] in THIRD_PARTY and layer not in THIRD_PARTY[top[0]]:
            bad.append(f"line {line}: {name} ({top[0]} belongs to {sorted(THIRD_PARTY[top[0]]) or 'no layer'})")
    return bad


MODULES = sorted(p for p in PACKAGE.rglob("*.py") if layer_of(p) is not None)


def test_every_subpackage_is_a_known_layer():
    """A new subpackage must take its place in the layer table (and in the drawing of
    docs/explanation/architecture.md)."""
    assert {layer_of(p) for p in MODULES} == set(ALLOWED)


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(PACKAGE)))
def test_layer_imports_only_layers_below(path):
    """The model imports no solver or analysis, solvers no analysis, and so on up
    (docs/explanation/architecture.md); third-party heavyweights only where their layer needs
    them."""
    package = ".".join(path.relative_to(PACKAGE.parent).parent.parts)
    bad = violations(layer_of(path), imports(path.read_text(), package))
    assert not bad, f"{path.relative_to(PACKAGE)} imports across layers:\n" + "\n".join(bad)


@pytest.mark.parametrize("module", sorted(FOUNDATION))
def test_foundation_modules_import_only_the_standard_library(module):
    """A module every layer may import stays below all of them: it imports no part of the package
    and no third-party library (not even numpy), so importing it never drags a layer in."""
    path = PACKAGE.parent.joinpath(*module.split(".")).with_suffix(".py")
    found = [name for name, _ in imports(path.read_text(), "selfalign")]
    assert found, f"{module} imports nothing, so this test would not see a bad import"
    bad = [name for name in found if name.split(".")[0] not in sys.stdlib_module_names | {"__future__"}]
    assert not bad, f"{module} imports beyond the standard library: {bad}"


def test_the_check_can_fail():
    """A relative, a lazy (function-level) and an absolute import upward are all caught, and a
    third-party library outside its layer too."""
    source = ("from ..solvers import driver\n\n\ndef f():\n    from selfalign.analysis import floquet\n"
              "    import matplotlib\n")
    found = imports(source, "selfalign.model")
    assert [name for name, _ in found] == ["selfalign.solvers", "selfalign.analysis", "matplotlib"]
    assert len(violations("model", found)) == 3
    assert violations("stages", found[:2]) == []
    assert violations("model", imports("from ..progress import Progress\n", "selfalign.model")) == []


def module_of(name: str) -> str | None:
    """The package module an imported dotted name lives in (``pkg.mod.attr`` -> ``pkg.mod``), or None
    outside the package."""
    parts = name.split(".")
    while parts and parts[0] == "selfalign":
        path = PACKAGE.parent.joinpath(*parts)
        if path.with_suffix(".py").is_file() or (path / "__init__.py").is_file():
            return ".".join(parts)
        parts = parts[:-1]
    return None


def import_graph() -> dict[str, set[str]]:
    """Module -> the package modules it imports (lazy imports included), for every module of every
    layer (package ``__init__`` modules excluded: they only gather names for the user)."""
    graph = {}
    for path in MODULES:
        if path.name == "__init__.py":
            continue
        name = ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        package = name.rsplit(".", 1)[0]
        found = {module_of(n) for n, _ in imports(path.read_text(), package)}
        graph[name] = {m for m in found if m and m != name and not m.endswith(".__init__")
                       and not (PACKAGE.parent.joinpath(*m.split(".")) / "__init__.py").is_file()}
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan), each sorted."""
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
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
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_no_import_circles():
    """No two modules import each other, directly or through others, inside a layer too (lazy imports
    count): a circle means one of them holds what belongs below both (docs/explanation/architecture.md)."""
    graph = import_graph()
    assert len(graph) > 50 and graph["selfalign.solvers.driver"], "the import graph was not read"
    found = cycles(graph)
    assert not found, "import circles:\n" + "\n".join(" -> ".join(c) for c in found)


def test_the_circle_check_can_fail():
    """A two-module circle and a three-module one are found; a chain is not a circle."""
    assert cycles({"a": {"b"}, "b": {"a"}, "c": {"a"}}) == [["a", "b"]]
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == [["a", "b", "c"]]
    assert cycles({"a": {"b"}, "b": {"c"}, "c": set()}) == []
    assert module_of("selfalign.solvers.driver.simulate") == "selfalign.solvers.driver"
