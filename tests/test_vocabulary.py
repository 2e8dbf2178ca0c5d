"""One public vocabulary: enums that read as their text, one exception base, and the names of
``selfalign``'s top level.

Modules are read with :mod:`ast` where a check covers the whole package, so it needs no import
side effects (numba, matplotlib, rerun).
"""

import ast
from enum import StrEnum
from pathlib import Path

import numpy as np

import selfalign as sa

PACKAGE = Path(__file__).resolve().parents[1] / "selfalign"


def text_enums_not_str_enum(source: str) -> list[str]:
    """Classes in ``source`` that derive from ``str`` and an ``Enum`` base rather than ``StrEnum``."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.ClassDef):
            bases = [ast.unparse(base) for base in node.bases]
            if "str" in bases and any(base.split(".")[-1].endswith("Enum") for base in bases):
                found.append(node.name)
    return found


def test_status_reads_as_its_value():
    """Hypothesis: a Status is its value as text wherever it turns into a string: str(), an
    f-string, and a numpy array of statuses, whose entries then equal the members (a ``(str, Enum)``
    gave "Status.REST" and numpy cut that to the longest value's length: "Stat" alone)."""
    assert issubclass(sa.Status, StrEnum)
    assert str(sa.Status.REST) == f"{sa.Status.REST}" == "rest"
    statuses = [sa.Status.REST, sa.Status.ACCUMULATION, sa.Status.NEVER_STOPS]
    array = np.array(statuses)
    assert array.tolist() == ["rest", "accumulation", "never_stops"]
    assert (array == sa.Status.REST).tolist() == [True, False, False]


def test_every_text_enum_is_a_str_enum():
    """Hypothesis: no enum of the package derives from (str, Enum); the check finds one that does."""
    assert text_enums_not_str_enum("from enum import Enum\nclass A(str, Enum):\n    X = 'x'\n") == ["A"]
    assert text_enums_not_str_enum("import enum\nclass B(str, enum.Enum):\n    X = 'x'\n") == ["B"]
    assert text_enums_not_str_enum("from enum import StrEnum\nclass C(StrEnum):\n    X = 'x'\n") == []
    bad = {str(path.relative_to(PACKAGE)): names for path in sorted(PACKAGE.rglob("*.py"))
           if (names := text_enums_not_str_enum(path.read_text()))}
    assert not bad, bad


def subclasses_of_base(source: str) -> dict[str, str]:
    """Classes in ``source`` with ``SelfalignError`` among their bases: name -> "Name(Base, ...)"."""
    return {node.name: f"{node.name}({', '.join(ast.unparse(base).split('.')[-1] for base in node.bases)})"
            for node in ast.walk(ast.parse(source)) if isinstance(node, ast.ClassDef)
            and any(ast.unparse(base).split(".")[-1] == "SelfalignError" for base in node.bases)}


def test_library_errors_share_one_base_and_keep_their_builtin_one():
    """Hypothesis: every exception of the library is a SelfalignError and still the builtin error
    that ``except`` clauses written before the base existed catch (ValueError, RuntimeError)."""
    from selfalign.io.design_spec import DesignSpecError
    from selfalign.model.errors import NonPhysicalProfile, SceneError, SelfalignError
    from selfalign.solvers.jit import KernelError

    for error, builtin in ((NonPhysicalProfile, ValueError), (SceneError, ValueError),
                           (DesignSpecError, ValueError), (KernelError, RuntimeError)):
        assert issubclass(error, SelfalignError) and issubclass(error, builtin), error
    assert not issubclass(SelfalignError, (ValueError, RuntimeError))


def test_design_spec_error_is_not_a_scene_error(tmp_path):
    """Hypothesis: a bad design spec file raises DesignSpecError, which ``except SelfalignError`` and
    ``except ValueError`` catch and ``except SceneError`` does not (a spec is not a scene)."""
    from selfalign.io.design_spec import DesignSpecError, load_design_spec
    from selfalign.model.errors import SceneError, SelfalignError

    path = tmp_path / "spec.yaml"
    path.write_text("machine: [\n")
    try:
        load_design_spec(path)
    except SceneError:
        raise AssertionError("a design spec error was caught as a SceneError") from None
    except SelfalignError as exc:
        assert isinstance(exc, DesignSpecError) and isinstance(exc, ValueError), exc
        assert str(exc).startswith(f"{path}: not valid YAML"), exc
    else:
        raise AssertionError("a spec that is not YAML was read")


def test_errors_module_documents_every_library_error():
    """Hypothesis: the hierarchy drawn in selfalign.model.errors' docstring names every class of the
    package that derives from SelfalignError, with its bases as the source declares them; the scan
    finds such a class."""
    from selfalign.model import errors

    assert subclasses_of_base("class E(errors.SelfalignError, ValueError):\n    pass\n") == {
        "E": "E(SelfalignError, ValueError)"}
    found = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        found.update(subclasses_of_base(path.read_text()))
    assert set(found) >= {"NonPhysicalProfile", "SceneError", "DesignSpecError", "KernelError"}
    missing = [declared for declared in found.values() if declared not in errors.__doc__]
    assert not missing, missing


#: Names a user constructs or catches that the top level must offer.
REQUIRED_EXPORTS = {"SelfalignError", "SceneError", "DesignSpecError", "KernelError", "NonPhysicalProfile",
                    "FiniteJerkProfile", "FrictionLaw", "ThreePhaseProfile", "StopZone", "Scene", "Status"}


def test_every_export_resolves_to_its_definition():
    """Hypothesis: each name of ``selfalign.__all__`` loads from the module ``_EXPORTS`` names for it,
    and is the object defined there (no name points at a missing or re-bound object)."""
    import importlib

    assert REQUIRED_EXPORTS <= set(sa.__all__)
    assert set(sa.__all__) == set(sa._EXPORTS) | {"__version__"}
    for name, module in sa._EXPORTS.items():
        value = getattr(sa, name)
        assert value is getattr(importlib.import_module(f"selfalign.{module}"), name), name
        assert value.__module__.startswith(f"selfalign.{module}"), (name, value.__module__)


def test_examples_use_exported_names(repo):
    """Hypothesis: every ``sa.<name>`` in the Python examples of the README and the documentation
    pages written by hand is a top-level name."""
    import re

    pages = [repo / "README.md", *(p for p in (repo / "docs").rglob("*.md")
                                   if "_build" not in p.parts and "generated" not in p.parts)]
    blocks = [block for page in pages for block in re.findall(r"```python\n(.*?)```", page.read_text(), re.S)]
    used = {name for block in blocks for name in re.findall(r"\bsa\.([A-Za-z_]\w*)", block)}
    assert used, "no Python example uses sa."
    assert used <= set(sa.__all__), sorted(used - set(sa.__all__))


def test_exported_functions_return_exported_classes():
    """Hypothesis: what an exported function returns, when its annotation names a class of the package,
    is a top-level name too, so a user can annotate with ``sa.<Class>``."""
    import inspect

    missing = {}
    for name in sa._EXPORTS:
        value = getattr(sa, name)
        if inspect.isfunction(value):
            returned = inspect.signature(value).return_annotation
            defined = getattr(inspect.getmodule(value), str(returned), None)
            if inspect.isclass(defined) and defined.__module__.startswith("selfalign."):
                if getattr(sa, defined.__name__, None) is not defined:
                    missing[name] = defined.__name__
    assert not missing, missing


STUB = PACKAGE / "__init__.pyi"


def test_stub_declares_exactly_the_exported_names():
    """Hypothesis: selfalign/__init__.pyi re-exports (``from .module import Name as Name``) each name of
    ``selfalign.__all__`` from the module ``_EXPORTS`` loads it from, and declares ``__version__: str``;
    nothing more, nothing less."""
    declared = {}
    for node in ast.parse(STUB.read_text()).body:
        if isinstance(node, ast.ImportFrom):
            for alias in node.names:
                assert alias.asname == alias.name, f"{alias.name} is not re-exported as itself"
                declared[alias.name] = "." * node.level + node.module
        elif isinstance(node, ast.AnnAssign):
            declared[node.target.id] = ast.unparse(node.annotation)
    assert set(declared) == set(sa.__all__), set(declared) ^ set(sa.__all__)
    assert declared.pop("__version__") == "str"
    assert declared == {name: f".{module}" for name, module in sa._EXPORTS.items()}


def mypy(tmp_path, repo, source: str):
    """(exit code, output) of mypy on ``source`` with the package of this tree on its path."""
    import os
    import subprocess
    import sys

    (tmp_path / "use.py").write_text(source)
    env = {**os.environ, "MYPYPATH": str(repo)}
    proc = subprocess.run([sys.executable, "-m", "mypy", "--follow-imports=silent", "--no-error-summary",
                           "--cache-dir", str(tmp_path / "cache"), "use.py"],
                          cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300)
    return proc.returncode, proc.stdout + proc.stderr


def test_mypy_accepts_the_exported_names(tmp_path, repo):
    """Hypothesis: a user's code that annotates with the exported classes, calls the exported
    functions and catches the exported errors type-checks (mypy exits 0), and mypy knows what the
    functions return; a misuse of the same names is an error, which it could not be if mypy saw the
    lazily loaded names as Any."""
    code, out = mypy(tmp_path, repo, """\
import numpy as np

import selfalign as sa

status: sa.Status = sa.Status.REST
profile: sa.ThreePhaseProfile = sa.ThreePhaseProfile(1.05, 0.084, 2.2, 0.9)
zone = sa.StopZone(0.5, 0.05, 2.5)
traj: sa.Trajectory = sa.simulate(sa.Scene(profile, zone, until="rest"))
batch: sa.BatchResult = sa.simulate_batch(profile, np.zeros(2), surface=zone)
state: sa.SteadyState = sa.steady_state(profile)
try:
    scene: sa.Scene = sa.load_scene("scene.yaml")
except sa.SelfalignError as exc:
    message: str = str(exc)
friction = sa.FrictionLaw("static_kinetic", 1.3)
ramped = sa.FiniteJerkProfile(1.05, 0.084, 2.2, 0.9, ramp=1e-3)
errors: tuple[type[Exception], ...] = (sa.SceneError, sa.DesignSpecError, sa.KernelError, sa.NonPhysicalProfile)
version: str = sa.__version__
reveal_type(traj)
""")
    assert code == 0, out
    assert 'Revealed type is "selfalign.solvers.results.Trajectory"' in out, out
    code, out = mypy(tmp_path, repo, "import selfalign as sa\n\ncount: int = sa.Status.REST\nsa.simulat\n")
    assert code == 1, out
    assert 'use.py:3: error: Incompatible types in assignment (expression has type "Status"' in out, out
    assert 'use.py:4: error: Module has no attribute "simulat"' in out, out
