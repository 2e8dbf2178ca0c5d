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
    gave "Status.REST" and numpy cut that to the value's length, "Stat")."""
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
