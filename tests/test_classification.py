"""The a-priori case decision of Sect. 5.1 (Table 1, flow chart of Fig. 8) kept as a data
structure.  Its agreement with simulated steady states on dense grids of the Fig. 10, 11 and
17 settings is tested in test_steady_state.py next to the reference simulation."""

import numpy as np
import pytest

from selfalign import ThreePhaseProfile
from selfalign.analysis.classification import (
    CASE_LABELS,
    DECISION_TREE,
    Condition,
    Decision,
    DecisionTree,
    Leaf,
    classify,
    classify_grid,
    decision_quantities,
)
from selfalign.analysis.steady_state import steady_state_grid


def test_tree_is_a_complete_flow_chart():
    """Fig. 8 as data: every case of Table 1 (and case 0) is exactly one leaf, every decision
    has one "yes" and one "no" edge to existing nodes, every node is reachable from the root
    and the walk starts at the root; labels are non-empty text for drawing."""
    nodes = dict(DECISION_TREE.nodes())
    edges = DECISION_TREE.edges()
    assert DECISION_TREE.nodes()[0][0] == DECISION_TREE.root == "feasible"
    leaves = [attrs["case"] for attrs in nodes.values() if attrs["kind"] == "case"]
    assert sorted(leaves) == [0, 1, 2, 3, 4, 5] == sorted(CASE_LABELS)
    decisions = [n for n, attrs in nodes.items() if attrs["kind"] == "decision"]
    for node in decisions:
        assert sorted(label for parent, _, label in edges if parent == node) == ["no", "yes"]
        assert nodes[node]["label"] and nodes[node]["condition"]
    assert {child for _, child, _ in edges} | {DECISION_TREE.root} == set(nodes)
    assert len(edges) == 2 * len(decisions) == len(nodes) - 1  # a tree
    assert nodes["restick"]["condition"] == "v_back <= t1"
    assert nodes["case4"]["label"] == "case 4: slip-slip"


@pytest.mark.parametrize("quantities, case", [
    ({"q": 1.2, "y2": 2.0, "y3": 2.0, "t1": np.nan, "v_back": np.nan}, 0),
    ({"q": 0.5, "y2": 2.0, "y3": 0.5, "t1": 0.3, "v_back": -0.1}, 1),
    ({"q": 0.5, "y2": 0.5, "y3": 2.0, "t1": 0.3, "v_back": 0.1}, 2),
    ({"q": 0.5, "y2": 2.0, "y3": 2.0, "t1": 0.3, "v_back": 0.1}, 3),
    ({"q": 0.5, "y2": 2.0, "y3": 2.0, "t1": 0.3, "v_back": 0.4}, 4),
    ({"q": 0.5, "y2": 0.5, "y3": 0.5, "t1": 0.3, "v_back": -0.1}, 5),
    # ties: q = 1 is feasible, |y''| = 1 sticks, v_back = t1 rests (for an instant) at t1
    ({"q": 1.0, "y2": 1.0, "y3": 1.0, "t1": 0.0, "v_back": 0.0}, 5),
    ({"q": 0.5, "y2": 1.0, "y3": 2.0, "t1": 0.3, "v_back": 0.1}, 2),
    ({"q": 0.5, "y2": 2.0, "y3": 1.0, "t1": 0.3, "v_back": 0.0}, 1),
    ({"q": 0.5, "y2": 2.0, "y3": 2.0, "t1": 0.3, "v_back": 0.3}, 3),
])
def test_tree_routes_each_branch(quantities, case):
    """Table 1 conditions of Sect. 5.1 with the model's tie rules (|y''| = 1 sticks)."""
    assert DECISION_TREE.evaluate(quantities) == case


def test_evaluate_is_vectorised_and_broadcasts():
    """evaluate returns an int8 case array of the broadcast shape of the quantities."""
    q = {"q": np.array([[0.5], [2.0]]), "y2": np.array([0.5, 2.0, 2.0]), "y3": 2.0,
         "t1": 0.3, "v_back": np.array([0.1, 0.1, 0.4])}
    cases = DECISION_TREE.evaluate(q)
    assert cases.dtype == np.int8
    assert cases.tolist() == [[2, 3, 4], [0, 0, 0]]


def test_quantities_of_the_case1_derivation():
    """Sect. 5.1 / Appendix: the quantities the tree tests, for one profile: q, t1 of the
    profile, and v_back = -(x'(t3)) of a mass at rest at t1 = (y3''-1) times the time from
    the phase-3 reversal (eq. 21) to t3 (to 1e-13)."""
    p = ThreePhaseProfile(1.0, 0.084, 3.0, 3.0)
    qty = decision_quantities(p.dt, p.dy, p.y2, p.y3)
    assert qty["q"] == p.feasibility and qty["t1"] == p.t1 and qty["t2"] == p.t2
    t_rev = p.t2 + (p.y2 - 1) * (p.t2 - p.t1) / (1 + p.y3)   # eq. 21 with y3 slope -(1 + y3)
    assert qty["v_back"] == pytest.approx((p.y3 - 1) * (p.dt - t_rev), rel=1e-13)


def test_forward_slip_from_rest_at_t1_always_ends_before_t3():
    """Why Fig. 8 needs no "does the forward slip end before t3?" node: from rest at t1 the
    slip ends strictly inside [t2, t3) for every feasible profile with y2'' > 1 (cases 1 and
    3; 200,000 random profiles over six decades of y'' and q in (0, 1])."""
    rng = np.random.default_rng(8)
    n = 200_000
    dt = 10.0 ** rng.uniform(-2, 2, n)
    y2 = 10.0 ** rng.uniform(0, 3, n) * (1 + 1e-9)
    y3 = 10.0 ** rng.uniform(-3, 3, n)
    q = rng.uniform(1e-6, 1.0, n)
    dy = (q * dt) ** 2 / (8.0 * (1.0 / y2 + 1.0 / y3))
    ss = steady_state_grid(dt, dy, y2, y3)
    qty = decision_quantities(dt, dy, y2, y3)
    sel = np.isin(ss.case, (1, 3))
    assert sel.sum() > n // 2
    end = ss.forward_start[sel] + ss.forward_time[sel]
    assert np.all(end > qty["t2"][sel]) and np.all(end < dt[sel])


def test_classify_accepts_profile_mapping_and_tuple():
    """classify(profile_or_params) -> int for a ThreePhaseProfile, its params() dict or a
    (dt, dy, y2, y3) tuple/list; an infeasible set is case 0 (no exception)."""
    p = ThreePhaseProfile(1.38, 0.064, 2.0, 0.6)
    for obj in (p, p.params(), (1.38, 0.064, 2.0, 0.6), [1.38, 0.064, 2.0, 0.6],
                {"dt": 1.38, "dy": 0.064, "y2": 2.0, "y3": 0.6}):
        assert classify(obj) == 1 and isinstance(classify(obj), int)
    assert classify((0.072, 0.021, 30.0, 30.0)) == 0
    assert classify_grid(0.072, 0.021, [30.0, 300.0], 300.0).tolist() == [0, 3]


@pytest.mark.parametrize("obj, match", [
    ({"kind": "polynomial", "dt": 1.0, "dy": 0.1}, "three-phase"),
    ({"dt": 1.0, "dy": 0.1, "y2": 2.0}, "y3"),
    ((1.0, 0.1, 2.0), "tuple"),
    ((1.0, 0.1, 0.0, 2.0), "y2 must be finite and > 0"),
    ((1.0, np.inf, 2.0, 2.0), "dy must be finite and > 0"),
])
def test_classify_rejects_bad_input(obj, match):
    """Bad input is a one-line ValueError naming the quantity and what is allowed."""
    with pytest.raises(ValueError, match=match):
        classify(obj)


@pytest.mark.parametrize("obj, match", [("fast", "tuple"), ((1.0, "0.1", 2.0, 2.0), "dy must be a real number")])
def test_classify_rejects_input_of_the_wrong_type(obj, match):
    """Hypothesis: a string instead of the parameters, or instead of one of them, is a TypeError
    naming what is allowed (the string is not read as a number)."""
    with pytest.raises(TypeError, match=match):
        classify(obj)


def test_tree_construction_is_checked():
    """A tree with a dangling edge or an unknown comparison is refused when built."""
    with pytest.raises(ValueError, match="unknown node"):
        DecisionTree("a", [Decision("a", "?", Condition("y2", ">", 1.0), yes="b", no="c"), Leaf("b", 1)])
    with pytest.raises(ValueError, match="op"):
        Condition("y2", "=>", 1.0)
