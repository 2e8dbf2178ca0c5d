"""A-priori classification of the steady state (Table 1, flow chart of Fig. 8).

The decision is kept as data: :data:`DECISION_TREE` is a binary tree whose
decision nodes test one :class:`Condition` on named quantities (see
:func:`decision_quantities`) and whose leaves are the cases of Table 1.  The
same object classifies whole grids (:meth:`DecisionTree.evaluate`) and can be
walked to draw the flow chart (:meth:`DecisionTree.nodes`,
:meth:`DecisionTree.edges`).

Cases: 0 non-physical profile, 1 stick-slip with x' >= 0, 2 stick-slip with
x' <= 0, 3 general stick-slip, 4 slip-slip, 5 pure stick.

Why these three tests suffice (derivations in :mod:`selfalign.analysis.steady_state`):
stick at v = 0 is possible in a phase iff |y''| <= 1 (ties stick), so with
y2 <= 1 and y3 <= 1 the mass never leaves v = 0 (case 5); with only y2 > 1
it can only slip forward (case 1), with only y3 > 1 only backward (case 2).
With both > 1 it can stick only in the dwell [0, t1].  If it does, it is at
rest at t1, slips forward from t1, reverses in phase 3 and arrives at t3
with backward speed ``v_back``; the backward slip decelerates at 1 in the
dwell, so the stick recurs iff v_back <= t1 (case 3), else no stick ever
occurs (case 4).  The paper's natural further question "does the forward
slip started at t1 end before t3?" is always yes and needs no node: from rest
at t1 the absolute mass velocity decreases at rate 1 while the table velocity
y' returns to its dwell value at t3, so x'(t3) = -(t3 - t1) < 0.
"""

from __future__ import annotations

import operator
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np

from ..model.errors import check_real
from ..model.profiles import CASE_LABELS, ThreePhaseProfile, three_phase_feasibility, three_phase_times

_OPS = {"<=": operator.le, "<": operator.lt, ">": operator.gt, ">=": operator.ge}


@dataclass(frozen=True)
class Condition:
    """``lhs op rhs`` where ``lhs`` names a quantity and ``rhs`` is a quantity name or a number."""

    lhs: str
    op: str
    rhs: str | float

    def __post_init__(self):
        if self.op not in _OPS:
            raise ValueError(f"Condition op must be one of {sorted(_OPS)}, got {self.op!r}")

    def __call__(self, quantities: Mapping[str, np.ndarray]) -> np.ndarray:
        rhs = quantities[self.rhs] if isinstance(self.rhs, str) else self.rhs
        # NaN (infeasible entries) compares False; the feasibility node routes those first.
        return _OPS[self.op](np.asarray(quantities[self.lhs]), rhs)

    def __str__(self):
        rhs = self.rhs if isinstance(self.rhs, str) else f"{self.rhs:g}"
        return f"{self.lhs} {self.op} {rhs}"


@dataclass(frozen=True)
class Decision:
    """An inner node: ``question`` is the flow-chart text, ``condition`` its test."""

    id: str
    question: str
    condition: Condition
    yes: str
    no: str


@dataclass(frozen=True)
class Leaf:
    """A terminal node: one case of Table 1."""

    id: str
    case: int

    @property
    def label(self) -> str:
        return f"case {self.case}: {CASE_LABELS[self.case]}"


class DecisionTree:
    """A binary decision tree over named quantities; leaves are cases."""

    def __init__(self, root: str, nodes):
        self.root = root
        self._nodes = {node.id: node for node in nodes}
        if root not in self._nodes:
            raise ValueError(f"root {root!r} is not a node id")
        for node in self._nodes.values():
            if isinstance(node, Decision):
                for child in (node.yes, node.no):
                    if child not in self._nodes:
                        raise ValueError(f"node {node.id!r} points to unknown node {child!r}")

    def __getitem__(self, node_id: str) -> Decision | Leaf:
        return self._nodes[node_id]

    def nodes(self) -> list[tuple[str, dict]]:
        """``(id, attributes)`` in depth-first order from the root.

        Decision attributes: kind="decision", label (the question),
        condition (its formula as text).  Leaf attributes: kind="case",
        label, case.
        """
        out = []
        for node in self._walk():
            if isinstance(node, Decision):
                out.append((node.id, {"kind": "decision", "label": node.question,
                                      "condition": str(node.condition)}))
            else:
                out.append((node.id, {"kind": "case", "label": node.label, "case": node.case}))
        return out

    def edges(self) -> list[tuple[str, str, str]]:
        """``(parent, child, "yes" | "no")`` in depth-first order."""
        return [(node.id, child, label) for node in self._walk() if isinstance(node, Decision)
                for child, label in ((node.yes, "yes"), (node.no, "no"))]

    def _walk(self):
        stack = [self.root]
        while stack:
            node = self._nodes[stack.pop()]
            yield node
            if isinstance(node, Decision):
                stack.extend((node.no, node.yes))

    def evaluate(self, quantities: Mapping[str, np.ndarray]) -> np.ndarray:
        """Case (int8) for every entry of the broadcast quantity arrays."""
        shape = np.broadcast_shapes(*(np.shape(v) for v in quantities.values()))
        cases = np.zeros(shape, dtype=np.int8)

        def route(node_id, mask):
            node = self._nodes[node_id]
            if isinstance(node, Leaf):
                cases[mask] = node.case
                return
            test = np.broadcast_to(node.condition(quantities), shape)
            route(node.yes, mask & test)
            route(node.no, mask & ~test)

        route(self.root, np.ones(shape, dtype=bool))
        return cases


#: The flow chart of Fig. 8 (ties |y''| = 1 and v_back = t1 count as stick).
DECISION_TREE = DecisionTree("feasible", [
    Decision("feasible", "Does a physical profile exist?", Condition("q", "<=", 1.0),
             yes="forward_slip", no="case0"),
    Decision("forward_slip", "Can the mass slip forward in [t1, t2] (y2'' > 1)?",
             Condition("y2", ">", 1.0), yes="both_slip", no="backward_slip"),
    Decision("backward_slip", "Can the mass slip backward in [t2, t3] (y3'' > 1)?",
             Condition("y3", ">", 1.0), yes="case2", no="case5"),
    Decision("both_slip", "Can the mass slip backward in [t2, t3] (y3'' > 1)?",
             Condition("y3", ">", 1.0), yes="restick", no="case1"),
    Decision("restick", "Does the backward slip reaching t3 stop within the dwell [0, t1]?",
             Condition("v_back", "<=", "t1"), yes="case3", no="case4"),
    Leaf("case0", 0), Leaf("case1", 1), Leaf("case2", 2),
    Leaf("case3", 3), Leaf("case4", 4), Leaf("case5", 5),
])


def check_parameters(dt, dy, y2, y3) -> tuple[np.ndarray, ...]:
    """Broadcast (dt, dy, y2, y3) to float arrays; ValueError unless all are finite and > 0."""
    arrays = np.broadcast_arrays(*(np.asarray(a, dtype=float) for a in (dt, dy, y2, y3)))
    for name, a in zip(("dt", "dy", "y2", "y3"), arrays):
        bad = ~(np.isfinite(a) & (a > 0.0))
        if bad.any():
            raise ValueError(f"{name} must be finite and > 0; {int(bad.sum())} entr"
                             f"{'y is' if bad.sum() == 1 else 'ies are'} not (first: {float(a[bad].flat[0])!r})")
    return tuple(arrays)


def decision_quantities(dt, dy, y2, y3) -> dict[str, np.ndarray]:
    """Quantities the tree tests, broadcast over the inputs (NaN where infeasible).

    ``q``: feasibility number of :func:`selfalign.model.profiles.three_phase_feasibility`;
    ``t1``, ``t2``: switch times of the profile; ``swing``: u = y2 (t2 - t1),
    the table velocity swing (eq. 63); ``v_back``: backward speed -x'(t3)
    reached by a mass at rest at t1 (meaningful for y2, y3 > 1):
    v_back = (y3 - 1) E with E = u (y2 + y3) / (y2 y3 (1 + y3)) the time from
    the phase-3 velocity reversal to t3.  ``dt``, ``dy`` and the float-array
    ``y2``, ``y3`` come along so that callers need no second broadcast.
    """
    dt, dy, y2, y3 = check_parameters(dt, dy, y2, y3)
    times = three_phase_times(dt, dy, y2, y3)
    swing = y2 * (times.t2 - times.t1)
    v_back = (y3 - 1.0) * swing * (y2 + y3) / (y2 * y3 * (1.0 + y3))
    return {"q": three_phase_feasibility(dt, dy, y2, y3), "dt": dt, "dy": dy, "y2": y2, "y3": y3,
            "t1": times.t1, "t2": times.t2, "swing": swing, "v_back": v_back}


def classify_grid(dt, dy, y2, y3) -> np.ndarray:
    """Case (int8 array) for broadcast parameter arrays; case 0 where infeasible."""
    return DECISION_TREE.evaluate(decision_quantities(dt, dy, y2, y3))


def profile_parameters(profile_or_params) -> tuple[float, float, float, float]:
    """(dt, dy, y2, y3) from a ThreePhaseProfile, a mapping with those keys, or a 4-sequence."""
    obj = profile_or_params
    if isinstance(obj, ThreePhaseProfile):
        return obj.dt, obj.dy, obj.y2, obj.y3
    if isinstance(obj, Mapping):
        if obj.get("kind", "three_phase") != "three_phase":
            raise ValueError(f"parameters must describe a three-phase profile, got kind {obj['kind']!r}")
        missing = [key for key in ("dt", "dy", "y2", "y3") if key not in obj]
        if missing:
            raise ValueError(f"three-phase parameters miss key(s) {missing}; need dt, dy, y2, y3")
        values = obj["dt"], obj["dy"], obj["y2"], obj["y3"]
    elif isinstance(obj, (tuple, list)):
        if len(obj) != 4:
            raise ValueError(f"expected a tuple (dt, dy, y2, y3) of 4 numbers, got {len(obj)}")
        values = tuple(obj)
    else:
        raise TypeError("expected a ThreePhaseProfile, a mapping with dt, dy, y2, y3, "
                        f"or a tuple (dt, dy, y2, y3); got {type(obj).__name__}")
    for name, value in zip(("dt", "dy", "y2", "y3"), values):
        check_real(name, value)
    return values


def classify(profile_or_params) -> int:
    """Case of Table 1 (0-5) for one three-phase profile or parameter set.

    The a-priori classification of the steady state on a uniform surface (Sect. 5, the
    flow chart of Fig. 8, kept as data in
    ``selfalign.analysis.classification.DECISION_TREE``).  Cases: 0 non-physical
    profile, 1 stick-slip with x' >= 0, 2 stick-slip with x' <= 0, 3 general stick-slip,
    4 slip-slip, 5 pure stick.  The ties ``|y''| = 1`` and v_back = t1 count as stick.  Stick
    at v = 0 is possible in a phase iff ``|y''| <= 1``, so with y2 <= 1 and y3 <= 1 the mass
    never leaves v = 0 (case 5), with only y2 > 1 it can only slip forward (case 1), with
    only y3 > 1 only backward (case 2); with both > 1 it can stick only in the dwell, and
    the stick recurs iff the backward speed v_back reached at t3 is at most t1 (case 3,
    else case 4).  ``selfalign.analysis.classification.classify_grid`` classifies whole
    grids.

    Parameters
    ----------
    profile_or_params : ThreePhaseProfile, dict or tuple
        A :class:`~selfalign.ThreePhaseProfile`, a mapping with the keys
        dt, dy, y2, y3 (a ``kind`` key, if any, must be "three_phase"), or a tuple or list
        (dt, dy, y2, y3).  Parameters of a non-physical profile are allowed (case 0).

    Returns
    -------
    int
        The case of Table 1, 0-5.

    Raises
    ------
    TypeError
        If the argument is none of these, or a parameter is not a real number.
    ValueError
        If the tuple does not hold 4 parameters, the mapping names another kind or misses a
        key, or a parameter is not finite and > 0.

    See Also
    --------
    steady_state : The steady state of the case (Sect. 5.1).

    Examples
    --------
    >>> import selfalign as sa
    >>> sa.classify(sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9))  # Fig. 18: stick-slip, x' >= 0
    1
    >>> sa.classify({"dt": 1.0, "dy": 0.084, "y2": 1.4, "y3": 1.3})  # Fig. 9: slip-slip
    4
    >>> sa.classify((1.0, 0.05, 0.9, 0.8)), sa.classify((1.0, 1.0, 1.0, 1.0))
    (5, 0)
    """
    return int(classify_grid(*profile_parameters(profile_or_params)))
