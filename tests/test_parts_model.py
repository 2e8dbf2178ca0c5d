"""The model of several parts (selfalign/model/parts.py, docs/explanation/several-parts.md): the parts and
their checks, the exact mode selection on a chain (chain_minimiser) and the simultaneous impact law
(impact_velocities).

chain_minimiser is checked by its optimality conditions, which are the equations of motion themselves:
a certificate that a solution satisfies them (a convex problem: satisfying them is being the minimiser)."""

import math

import numpy as np
import pytest

from selfalign.model.parts import (
    CHAIN_WORK_ROWS,
    IMPACT_WORK_ROWS,
    STATIC_WORK_ROWS,
    Part,
    chain_minimiser,
    check_parts,
    check_restitution,
    impact_velocities,
    static_kinetic_minimiser,
)

#: Rounding allowance of the optimality conditions, relative to the scale of the forces involved.
KKT_RTOL = 1e-12


def solve(b, m, s, lower, joined):
    out = np.full(len(b), np.nan)
    chain_minimiser(np.asarray(b, float), np.asarray(m, float), np.asarray(s, float), np.asarray(lower, float),
                    np.asarray(joined, bool), out, np.full((CHAIN_WORK_ROWS, len(b)), np.nan))
    return out


def impact(v, m, e, joined):
    out = np.full(len(v), np.nan)
    impact_velocities(np.asarray(v, float), np.asarray(m, float), e, np.asarray(joined, bool), out,
                      np.full((IMPACT_WORK_ROWS, len(v)), np.nan))
    return out


def optimality_violation(a, b, m, s, lower, joined) -> float:
    """How far ``a`` is from satisfying the optimality conditions of chain_minimiser's problem, in units of
    their rounding allowance (KKT_RTOL x the forces' scale x N; 0 when it satisfies them exactly).

    Along each joined run the contact force behind part i, lam_{i-1}, and the equation
    m_i (a_i - b_i) + m_i s_i xi_i = lam_{i-1} - lam_i give the set of lam_i reachable with xi_i in
    Sign(a_i) (an interval: xi_i is free in [-1, 1] where a_i = 0); each lam_i must be >= 0 and 0 where the
    contact is slack, and the run's last lam must be 0."""
    n = len(a)
    scale = max(1.0, float(np.max(np.abs(np.asarray(m) * np.asarray(b)))), float(np.max(np.asarray(m) * s)))
    tol = KKT_RTOL * scale * n
    violation = 0.0
    low = high = 0.0                        # the interval of lam_{i-1}
    for i in range(n):
        rest = m[i] * (a[i] - b[i])
        if a[i] > 0:
            lo_f = hi_f = m[i] * s[i]
        elif a[i] < 0:
            lo_f = hi_f = -m[i] * s[i]
        else:
            lo_f, hi_f = -m[i] * s[i], m[i] * s[i]
        low, high = low - rest - hi_f, high - rest - lo_f     # lam_i = lam_{i-1} - rest - m s xi
        last = i == n - 1 or not joined[i]
        if last or a[i + 1] - a[i] - lower[i] > tol:
            gap = 0.0 if low <= 0.0 <= high else min(abs(low), abs(high))
            violation = max(violation, gap)
            low = high = 0.0
        else:
            if a[i + 1] - a[i] - lower[i] < -tol:
                return math.inf
            if high < 0.0:
                violation = max(violation, -high)
            low = max(low, 0.0)
    return violation / tol


def random_problem(rng, n):
    b = rng.normal(size=n) * rng.choice([0.1, 1.0, 10.0])
    m = rng.uniform(0.2, 5.0, size=n)
    s = np.where(rng.random(n) < 0.3, 0.0, rng.uniform(0.0, 3.0, size=n))
    lower = np.where(rng.random(n - 1) < 0.5, 0.0, rng.normal(size=n - 1))
    joined = rng.random(n - 1) < 0.8
    return b, m, s, lower, joined


def test_the_minimiser_satisfies_the_equations_of_motion():
    """Hypothesis (docs, "Mode selection"): on 3,000 random chains (1-9 parts, some joined runs, zero and
    positive friction bounds, shifted constraints as Moreau's step and the impact law use) the solution
    satisfies the optimality conditions, i.e. the parts' equations of motion with set-valued friction and
    complementary contact forces, to 1e-12 of the forces' scale."""
    rng = np.random.default_rng(7)
    worst = 0.0
    for _ in range(3000):
        n = int(rng.integers(1, 10))
        problem = random_problem(rng, n)
        a = solve(*problem)
        assert np.all(np.isfinite(a))
        worst = max(worst, optimality_violation(a, *problem))
    assert worst <= 1.0, worst


def test_the_certificate_can_fail():
    """The check rejects a wrong answer: a solution with one part's acceleration moved by 1e-6, and the
    unconstrained answer where a contact binds."""
    rng = np.random.default_rng(11)
    rejected = 0
    for _ in range(200):
        problem = random_problem(rng, 5)
        a = solve(*problem)
        wrong = a.copy()
        wrong[int(rng.integers(5))] += 1e-6 * max(1.0, float(np.max(np.abs(a))))
        rejected += optimality_violation(wrong, *problem) > 1.0
    assert rejected == 200
    b, m, s = np.array([1.0, -1.0]), np.ones(2), np.zeros(2)
    assert optimality_violation(b, b, m, s, np.zeros(1), np.array([True])) == math.inf


def test_parts_pushed_together_move_as_one_with_the_mass_weighted_friction():
    """Hypothesis (docs, "Mode selection"): touching parts whose free accelerations push them together move
    as one part whose friction factor is sum m_i k_i / sum m_i: at rest under y'' = -c the cluster sticks iff
    c <= that factor, else slides at c - factor; sliding forward it decelerates at y'' + factor."""
    m, k = np.array([1.0, 2.0, 0.5]), np.array([0.5, 1.0, 3.0])
    factor = float(np.sum(m * k) / np.sum(m))
    joined, lower = np.array([True, True]), np.zeros(2)
    for c in (0.9 * factor, factor, 1.3 * factor):     # alone, the rear part would slide faster
        a = solve(np.full(3, c), m, k, lower, joined)
        expected = max(c - factor, 0.0)
        assert a == pytest.approx(np.full(3, expected), abs=1e-15), c
    # Sliding forward (v > 0) under y'' = 0.2: kinetic friction k_i behind each part, rear part pushes.
    a = solve(-0.2 - k, m, np.zeros(3), lower, joined)
    assert a == pytest.approx(np.full(3, -0.2 - factor), rel=1e-15)


def test_a_pulling_front_part_separates():
    """Hypothesis (unilateral contact): a contact cannot pull.  The front part driven forward harder than
    the rear part separates from it, each moving as alone; the rear part at rest under its stick bound
    stays stuck (a = 0) while the front one slides."""
    a = solve(np.array([0.5, 2.0]), np.ones(2), np.array([1.0, 1.0]), np.zeros(1), np.array([True]))
    assert a.tolist() == [0.0, 1.0]
    a = solve(np.array([-1.0, 3.0]), np.array([2.0, 1.0]), np.zeros(2), np.zeros(1), np.array([True]))
    assert a.tolist() == [-1.0, 3.0]


def test_open_contacts_decouple_the_parts():
    """Hypothesis: without a closed contact every part solves its own problem: a_i = soft threshold of b_i
    at s_i (stick where |b_i| <= s_i)."""
    b, s = np.array([2.0, -0.5, -3.0, 0.3]), np.array([1.0, 1.0, 0.5, 0.0])
    a = solve(b, np.ones(4), s, np.zeros(3), np.zeros(3, bool))
    assert a.tolist() == [1.0, 0.0, -2.5, 0.3]


def test_two_part_impact_is_newtons_law():
    """Hypothesis (docs, "Impacts"): two parts colliding leave with u2 - u1 = e (v1 - v2) and their momentum
    unchanged; the kinetic energy lost is (1 - e^2) m1 m2 (v1 - v2)^2 / (2 (m1 + m2))."""
    m, v = np.array([2.0, 0.5]), np.array([1.5, -0.25])
    for e in (0.0, 0.3, 1.0):
        u = impact(v, m, e, [True])
        assert u[1] - u[0] == pytest.approx(e * (v[0] - v[1]), rel=1e-14, abs=1e-15)
        assert m @ u == pytest.approx(m @ v, rel=1e-14)
        lost = (m @ v**2 - m @ u**2) / 2
        assert lost == pytest.approx((1 - e**2) * m.prod() * (v[0] - v[1]) ** 2 / (2 * m.sum()), rel=1e-12, abs=1e-15)


def test_newtons_cradle_under_the_simultaneous_law():
    """Hypothesis (docs, "Impacts": the law chosen): three equal parts, the rear one at 1 against two touching
    at rest, e = 1: u = (-1/3, 2/3, 2/3), momentum and energy conserved; e = 0: all at 1/3; separating
    parts are not touched."""
    u = impact([1.0, 0.0, 0.0], np.ones(3), 1.0, [True, True])
    assert u == pytest.approx([-1 / 3, 2 / 3, 2 / 3], rel=1e-14)
    assert u @ u == pytest.approx(1.0, rel=1e-14)
    assert impact([1.0, 0.0, 0.0], np.ones(3), 0.0, [True, True]) == pytest.approx(np.full(3, 1 / 3), rel=1e-14)
    assert impact([-1.0, 0.0, 2.0], np.ones(3), 0.5, [True, True]).tolist() == [-1.0, 0.0, 2.0]


def test_part_checks_name_what_is_wrong():
    """Bad input is refused before any work, naming the part and the parameter."""
    with pytest.raises(ValueError, match="width must be > 0"):
        Part(0.0, width=0.0)
    with pytest.raises(ValueError, match="mass must be > 0"):
        Part(0.0, width=1.0, mass=-1.0)
    with pytest.raises(ValueError, match="friction_factor must be > 0"):
        Part(0.0, width=1.0, friction_factor=0.0)
    with pytest.raises(ValueError, match="x0 must be a finite number"):
        Part(math.nan, width=1.0)
    with pytest.raises(TypeError, match="v0"):
        Part(0.0, "1", width=1.0)
    with pytest.raises(ValueError, match="at least one Part"):
        check_parts([])
    with pytest.raises(TypeError, match=r"parts\[1\] must be a Part"):
        check_parts([Part(0.0, width=1.0), 3.0])
    with pytest.raises(ValueError, match=r"parts\[2\] overlaps parts\[1\]"):
        check_parts([Part(0.0, width=1.0), Part(1.0, width=1.0), Part(1.5, width=1.0)])
    assert len(check_parts([Part(0.0, width=1.0), Part(1.0, width=1.0)])) == 2
    # Touching parts at computed positions overlap by rounding only (0.6 against 0.6000000000000001).
    assert len(check_parts([Part(i * 0.05, width=0.05) for i in range(14)])) == 14
    with pytest.raises(ValueError, match=r"parts\[1\] overlaps parts\[0\]"):
        check_parts([Part(0.6, width=0.05), Part(0.65 - 1e-12, width=0.05)])
    for bad in (-0.1, 1.01, math.nan):
        with pytest.raises(ValueError, match="restitution"):
            check_restitution(bad)
    with pytest.raises(TypeError, match="restitution"):
        check_restitution("1")


def static_solve(b, m, s, ratio, may_stick, lower, joined):
    out = np.full(len(b), np.nan)
    static_kinetic_minimiser(np.asarray(b, float), np.asarray(m, float), np.asarray(s, float), ratio,
                             np.asarray(may_stick, bool), np.asarray(lower, float), np.asarray(joined, bool), out,
                             np.full((STATIC_WORK_ROWS, len(b)), np.nan))
    return out


def test_static_kinetic_selection_with_ratio_one_is_the_chain_minimiser():
    """Hypothesis (docs/explanation/several-parts.md, "Static/kinetic friction": with r = 1 the law is
    Coulomb's): on 300 random chains the static/kinetic mode selection with r = 1 is the chain minimiser, bit
    for bit."""
    rng = np.random.default_rng(7)
    for _ in range(300):
        b, m, s, lower, joined = random_problem(rng, int(rng.integers(1, 12)))
        assert static_solve(b, m, s, 1.0, np.ones(len(b), bool), lower, joined).tolist() == \
            solve(b, m, s, lower, joined).tolist()


@pytest.mark.parametrize("push, expected", [(1.2, 0.0), (1.3, 0.0), (1.5, 0.5), (-1.4, -0.4)])
def test_one_part_sticks_under_the_static_bound_and_slips_with_the_kinetic_one(push, expected):
    """Hypothesis (eq. 2 with mu_s = r mu_k: a part at rest sticks while |y''| <= r mu_bar, else slips with
    x'' = -y'' - sign mu_bar): r = 1.3, mu_bar = 1."""
    assert static_solve([push], [1.0], [1.0], 1.3, [True], [], []).tolist() == [pytest.approx(expected, abs=1e-15)]


def test_a_pair_at_rest_breaks_away_together_with_kinetic_friction():
    """Hypothesis (the rule of static_kinetic_minimiser): two touching equal parts pushed by y'' = -1.4 stick
    where their pooled static bound r (k_0 + k_1) / 2 reaches 1.4 (k = (1, 1.2), r = 1.3: 1.43) and both slip
    forward once it does not (k = (1, 1), r = 1.3: 1.3), then at 1.4 - 1 = 0.4 each: the kinetic friction,
    not the static bound's 0.1; a part that is not at rest (may_stick False) keeps its kinetic bound."""
    assert static_solve([1.4, 1.4], [1, 1], [1.0, 1.2], 1.3, [True, True], [0.0], [True]).tolist() == [0.0, 0.0]
    out = static_solve([1.4, 1.4], [1, 1], [1.0, 1.0], 1.3, [True, True], [0.0], [True])
    assert out == pytest.approx([0.4, 0.4], abs=1e-15)
    moving = static_solve([1.4], [1.0], [1.0], 1.3, [False], [], [])
    assert moving == pytest.approx([0.4], abs=1e-15)
