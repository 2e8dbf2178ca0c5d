"""Every formula once (docs/explanation/architecture.md): each numbered equation of the paper the package
implements has exactly one implementing function in the equation index (selfalign.model.registry,
selfalign.cli.equations); no other function carries its implementation marker (a comment that
starts with ``# eq.``, or a docstring line ``Implements eq.``); docs/reference/equations.md is the index
as ``selfalign equations`` prints it; and the shared formulas are the ones the engine, analyses
and design tool run."""

import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from selfalign.cli.commands import selfalign as cli
from selfalign.cli.equations import FORMULA_MODULES, formulas, index, markdown
from selfalign.model import registry
from selfalign.model.friction import level_position, static_stick_limit, stick_limit, stribeck_factor
from selfalign.model.profiles import ThreePhaseProfile, three_phase_feasibility

PACKAGE = Path(__file__).resolve().parents[1] / "selfalign"
DOCS = Path(__file__).resolve().parents[1] / "docs" / "reference" / "equations.md"


def _markers():
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        module = ".".join(path.relative_to(PACKAGE.parent).with_suffix("").parts)
        found += registry.implementation_markers(path.read_text(encoding="utf-8"), module)
    return found


def test_every_equation_has_one_owner_and_no_other_function_implements_it():
    idx = index()
    assert {"7", "9", "41", "42", "59", "60"} <= set(idx)
    misplaced = registry.misplaced_markers(_markers(), idx)
    assert not misplaced, f"functions implementing an equation another function owns: {misplaced}"
    unowned = [m for m in _markers() if m[1] not in idx]
    assert not unowned, f"implementation markers of equations without an owner in the index: {unowned}"


def test_a_second_owner_or_a_misplaced_marker_is_found():
    """The checks can fail: a second function tagged with eq. (41), and a comment '# eq. (41)' in
    a function that is not its owner."""
    @registry.formula(eqs=("41",), kernel=False)
    def rewritten(a, w, c):
        """x_stick_min again."""
        return w * (a - 1.0) / (c - 1.0)
    registry.TAGGED.remove(rewritten)
    with pytest.raises(ValueError, match="more than one implementing function.*'41'"):
        registry.equation_index(formulas() + [rewritten])
    source = "def helper(a):\n    # eq. (41): permanent stick\n    return a\n"
    markers = registry.implementation_markers(source, "somewhere")
    assert markers == [("somewhere.helper", "41", 2)]
    assert registry.misplaced_markers(markers, index()) == markers
    prose = "def helper(a):\n    # x_stick_min of eq. (41), see stick_limit\n    return a\n"
    assert registry.implementation_markers(prose, "somewhere") == []


def test_a_formula_says_what_it_implements():
    with pytest.raises(TypeError, match="bare @formula"):
        registry.formula(lambda x: x)
    with pytest.raises(TypeError, match="exactly one of eqs"):
        registry.formula(eqs=("41",), unnumbered="both")
    with pytest.raises(ValueError, match="equation numbers"):
        registry.formula(eqs=(41,))


def test_equation_page_is_current():
    """docs/reference/equations.md is `selfalign equations`: regenerate it with
    `selfalign equations -o docs/reference/equations.md` after changing a formula's tag or docstring."""
    assert DOCS.read_text(encoding="utf-8") == markdown()
    result = CliRunner().invoke(cli, ["equations"])
    assert result.exit_code == 0 and result.output == markdown()


def test_every_formula_module_is_indexed():
    """The modules that mark formulas are exactly FORMULA_MODULES (a new one must join the index)."""
    marking = sorted(".".join(p.relative_to(PACKAGE.parent).with_suffix("").parts)
                     for p in PACKAGE.rglob("*.py")
                     if "@formula(" in p.read_text(encoding="utf-8") and p.name != "registry.py")
    assert marking == sorted(FORMULA_MODULES)


def test_shared_formulas_reduce_to_the_papers():
    """Invariants of the shared formulas: at r = 1 the static limit is eq. (41); the Stribeck
    factor is r at rest and 1 for |v| >> v_s; eq. (60)'s fixed point is eq. (41) inside the zone;
    q of the three-phase profile is 1 exactly on the edge of case 0."""
    assert static_stick_limit(2.2, 1.0, 0.3, 2.5) == stick_limit(2.2, 0.3, 2.5)
    assert static_stick_limit(2.2, 1.1, 0.3, 2.5) == pytest.approx(0.3 * (2.2 / 1.1 - 1.0) / 1.5, rel=1e-15)
    assert stribeck_factor(0.0, 1.3, 0.01, 1.0) == 1.3
    assert stribeck_factor(10.0, 1.3, 0.01, 1.0) == 1.0
    assert level_position(2.2, 0.3, 2.5) == stick_limit(2.2, 0.3, 2.5)
    assert stick_limit(0.9, 0.3, 2.5) == -math.inf and level_position(0.9, 0.3, 2.5) < 0.0
    dt, y2, y3 = 1.05, 2.2, 0.9
    dy_edge = dt * dt / (8.0 * (1.0 / y2 + 1.0 / y3))
    assert float(three_phase_feasibility(dt, dy_edge, y2, y3)) == pytest.approx(1.0, rel=1e-15)
    assert ThreePhaseProfile(dt, 0.084, y2, y3).feasibility == pytest.approx(
        float(three_phase_feasibility(dt, 0.084, y2, y3)), rel=0)
    assert np.isfinite(stick_limit(2.2, 1.0, 2.5))
