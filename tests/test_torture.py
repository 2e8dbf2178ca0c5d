"""Hard cases stay numerically stable (docs/explanation/robustness.md).

One test per hazard.  The exact solver must give the right answer, checked against a
closed form, an invariant or an exact rational reference (:func:`rational_reference`:
on a uniform surface with piecewise-constant y'' every arc has constant x'', so every
event time is rational and the motion of the float-defined profile can be followed
in ``fractions.Fraction`` without any rounding).  The Moreau and ivp solvers must stay
finite and converge, or say in their status and message why they cannot.  Every run is
bounded by ``periods`` / ``max_periods`` so that a regression fails instead of hanging.
"""

import math
from fractions import Fraction

import numpy as np
import pytest

import selfalign as sa
from selfalign.analysis.stick_map import stick_map_contraction

EPS = np.finfo(float).eps
FIG18 = sa.ThreePhaseProfile(1.05, 0.084, 2.2, 0.9)  # Sect. 5.1 / 7.3 settings, case 1
FINAL = (sa.Status.HORIZON, sa.Status.REST, sa.Status.ACCUMULATION, sa.Status.NEVER_STOPS)


def run(profile, surface=None, method="exact", options=None, **scene):
    traj = sa.simulate(sa.Scene(profile, surface=surface or sa.Uniform(), **scene), method=method,
                       **(options or {}))
    assert_finite(traj)
    return traj


def assert_finite(traj):
    """No NaN or inf leaves the library: end state, info numbers and every series."""
    assert math.isfinite(traj.x_end) and math.isfinite(traj.v_end) and math.isfinite(traj.tau_end), traj
    for name, values in traj.series.items():
        assert np.all(np.isfinite(values)), name
    for key, value in traj.info.items():
        if isinstance(value, float) and key not in ("x_stick_min",):
            assert math.isfinite(value), (key, value)


def rational_reference(profile, v0, periods, x0=0):
    """(x, v, total |dx|) after ``periods`` periods from (x0, v0) at t = 0 on a uniform surface,
    in exact rational arithmetic of the model (DESIGN): x'' = -y'' - d with d = sign(v), stick
    at v = 0 iff |y''| <= 1, else slip in the direction -sign(y'')."""
    breaks = [Fraction(b) for b in profile.breaks]
    accels = [Fraction(a) for a in profile.accels]
    x, v, moved = Fraction(x0), Fraction(v0), Fraction(0)
    for _ in range(periods):
        for i, a in enumerate(accels):
            s, end = breaks[i], breaks[i + 1]
            while s < end:
                if v == 0 and abs(a) <= 1:
                    break  # stuck until the piece ends (y'' is constant on it)
                d = (v > 0) - (v < 0) if v != 0 else -((a > 0) - (a < 0))
                acc = -a - d
                stops = v != 0 and acc * d < 0 and s - v / acc <= end  # braked to v = 0 in the piece
                step = (-v / acc) if stops else end - s
                dx = v * step + acc * step * step / 2
                x, moved = x + dx, moved + abs(dx)
                v = Fraction(0) if stops else v + acc * step
                s += step
    return x, v, moved


def assert_matches_reference(traj, profile, v0, periods, ulps=64):
    """Exact solver against the rational reference, to ``ulps`` of the total distance moved."""
    x_ref, v_ref, moved = rational_reference(profile, v0, periods)
    tol = ulps * EPS * float(moved + abs(x_ref))
    assert abs(traj.x_end - float(x_ref)) <= tol, (traj.x_end, float(x_ref), tol)
    v_scale = profile.max_abs_acceleration * profile.dt
    assert abs(traj.v_end - float(v_ref)) <= ulps * EPS * v_scale, (traj.v_end, float(v_ref))


def moreau_converges(profile, x_exact, surface=None, **scene):
    """Moreau converges at first order: over ten steps h = dt/n, n = 200 ... 7700 in ratio
    1.5 (not powers of two, whose error constants can alias: the constant of the O(h) error
    depends on where the steps fall relative to the events, docs/explanation/solvers.md), the
    Theil-Sen slope of log error against log h lies in [0.7, 1.5], and every error is at
    most 10 periods h max|y''|."""
    from scipy.stats import theilslopes

    steps = np.unique(np.round(200 * 1.5 ** np.arange(10)).astype(int))
    errors = []
    for n in steps:
        traj = run(profile, surface, "moreau", {"h": profile.dt / n}, **scene)
        assert traj.status in FINAL, traj.message
        errors.append(abs(traj.x_end - x_exact))
    errors, h = np.array(errors), profile.dt / steps
    bound = 10 * scene.get("periods", 1) * h * max(profile.max_abs_acceleration, 1.0)
    assert np.all(errors <= bound), (errors, bound)
    if np.all(errors > 1e-12):
        slope = theilslopes(np.log(errors), np.log(h)).slope
        assert 0.7 <= slope <= 1.5, (slope, errors)


# ------------------------------------------------------------------------------------------
# 1. Exact ties
# ------------------------------------------------------------------------------------------

@pytest.mark.parametrize("y2, y3, case", [(1.0, 0.9, 5), (1.0, 1.5, 2), (2.2, 1.0, 1), (1.0, 1.0, 5)])
def test_tie_table_acceleration_equals_friction(y2, y3, case):
    """Hazard: y2'' = 1 or y3'' = 1 exactly, so |y''| = mu_bar during a whole piece and the
    stick/slip decision is a tie (docs/explanation/paper.md: ties stick).  Expected: the case of
    Table 1 with ties on the sticking side, the exact solver equal to the rational reference
    to 64 ulp of the distance moved and to n vbar dt (closed form, steady_state) to 1e-12
    relative; ivp within its rtol; Moreau converging with h."""
    p = sa.ThreePhaseProfile(1.05, 0.02, y2, y3)
    ss = sa.steady_state(p)
    assert ss.case == case == sa.classify(p)
    n = 200
    traj = run(p, v0=ss.v0, periods=n)
    assert traj.status is sa.Status.HORIZON
    assert_matches_reference(run(p, v0=ss.v0, periods=8), p, ss.v0, 8)
    assert abs(traj.x_end - n * ss.vbar * p.dt) <= 1e-12 * max(abs(n * ss.vbar * p.dt), p.dt)
    if case == 5:
        assert traj.x_end == 0.0 and traj.v_end == 0.0  # pure stick: nothing moves at all
    ivp = run(p, method="ivp", v0=ss.v0, periods=20)
    assert abs(ivp.x_end - 20 * ss.vbar * p.dt) <= 1e-7 * max(abs(20 * ss.vbar * p.dt), p.dt)
    moreau_converges(p, 20 * ss.vbar * p.dt, v0=ss.v0, periods=20)


def test_tie_stick_exactly_where_friction_equals_max_acceleration():
    """Hazard: a stick at x with mu_bar(x) = max|y''| exactly (eq. 41's x_stick_min, all
    numbers dyadic: x_mu = 0.5, w = 0.5, c_mu = 3 give mu_bar(0.75) = 2 = y2'').  Expected:
    REST for good at exactly x = 0.75 from every solver (DESIGN: ties stick)."""
    p = sa.ThreePhaseProfile(1.0, 0.02, 2.0, 1.5)
    zone = sa.StopZone(0.5, 0.5, 3.0)
    assert zone.x_stick_min(p.max_abs_acceleration) == 0.75 and zone.coefficient(0.75) == 2.0
    for method in ("exact", "moreau", "ivp"):
        traj = run(p, zone, method, x0=0.75, until="rest", max_periods=5)
        assert traj.status is sa.Status.REST, (method, traj.message)
        assert traj.x_end == 0.75 and traj.v_end == 0.0, method


# A dyadic profile in which the backward slip arriving at t3 ends exactly at t1 (v_back = t1,
# the case-3/case-4 boundary of Fig. 8): dwell 0 on [0, 1/2), -3 on [1/2, 1), +3 on [1, 3/2).
ZERO_STICK = sa.PiecewiseConstantProfile([0.0, 0.5, 1.0, 1.5], [0.0, -3.0, 3.0], 0.0, 0.0)


def test_zero_length_stick_on_case_boundary():
    """Hazard: a stick of zero length, on the boundary v_back = t1 between cases 3 and 4
    (Fig. 8): from x' = -1/2 at t = 0 the dwell brakes the backward slip to 0 exactly at
    t1 = 1/2, where y'' jumps to -3 and the mass slips forward at once.  Expected: STICK then
    SLIP at the same time tau = 1/2 (no lost or duplicated event, no Zeno loop), and an
    advance of exactly 3/16 per period (the rational reference) for 100 periods."""
    n = 100
    traj = run(ZERO_STICK, v0=-0.5, periods=n)
    assert traj.x_end == float(rational_reference(ZERO_STICK, Fraction(-1, 2), n)[0]) == 3 * n / 16
    assert traj.v_end == -0.5
    one = run(ZERO_STICK, v0=-0.5, periods=1, record=sa.Record(events=True))
    kinds = [sa.EventKind(k) for k in one.events["kind"]]
    assert kinds[0] is sa.EventKind.STICK and one.events["tau"][0] == 0.5
    slip = [e for e in one.events if e["kind"] == sa.EventKind.SLIP]
    assert len(slip) == 1 and slip[0]["tau"] == 0.5 and slip[0]["mode"] == sa.solvers.outcomes.FORWARD_SLIP
    assert one.stats["events"] <= 6
    ivp = run(ZERO_STICK, method="ivp", v0=-0.5, periods=n)
    assert ivp.x_end == pytest.approx(3 * n / 16, rel=1e-10)
    moreau_converges(ZERO_STICK, 3 * 20 / 16, v0=-0.5, periods=20)


# ------------------------------------------------------------------------------------------
# 2. Grazing
# ------------------------------------------------------------------------------------------

# Period 3: y'' = +3 on [0, 1/2) (backward slip, x'' = -2), 0 on [1/2, 3/2) (the backward
# slip brakes to 0 exactly at 3/2), -3/2 on [3/2, 5/2) (forward slip, x'' = 1/2), 0 on
# [5/2, 3) (brakes to 0 exactly at 3).  Zero mean y''; net advance -3/8 per period.
GRAZING = sa.PiecewiseConstantProfile([0.0, 0.5, 1.5, 2.5, 3.0], [3.0, 0.0, -1.5, 0.0], 0.0, 0.0)


def test_grazing_velocity_zero_at_switch_time():
    """Hazard: the relative velocity reaches 0 exactly at a switch time (twice per period),
    where the v = 0 event and the profile break coincide (exact solver tie rule 3).
    Expected: v = 0 exactly at both breaks, the next piece decides the mode, and x advances
    by exactly -3/8 per period (rational reference) over 100 periods; ivp and Moreau agree
    within their accuracy."""
    n = 100
    traj = run(GRAZING, periods=n)
    assert traj.status is sa.Status.HORIZON
    assert traj.x_end == float(rational_reference(GRAZING, 0, n)[0]) == -0.375 * n
    one = run(GRAZING, periods=1, record=sa.Record(events=True))
    at_breaks = one.events[np.isin(one.events["tau"], [1.5, 0.0])]
    assert at_breaks.size and np.all(at_breaks["v"] == 0.0)
    assert one.stats["events"] <= 8
    ivp = run(GRAZING, method="ivp", periods=n)
    assert ivp.x_end == pytest.approx(-0.375 * n, rel=1e-10)
    moreau_converges(GRAZING, -0.375 * 20, periods=20)


# ------------------------------------------------------------------------------------------
# 3. Accumulation
# ------------------------------------------------------------------------------------------

def test_accumulation_reaches_limit_with_bounded_work():
    """Hazard: infinitely many ever shorter slips converging to x_stick_min (Sect. 7.3, eq. 41:
    x_mu + w (y2 - 1)/(c_mu - 1) = 1/2 + 1/25 = 0.54 exactly in rationals).  Expected:
    ACCUMULATION with x_end = the limit to 1e-12, a geometric contraction equal to eq. (59)'s
    cos(omega (t2 - t1)) (stick_map_contraction; the measured ratio of the last increments,
    to 1e-4), and a bounded number of events
    (< 200 for accumulation_tol = 1e-12).  Moreau (scheme limit) reaches the same limit;
    ivp, whose stick events go through the same accumulation test (docs/explanation/solvers.md), ends
    in the accumulation (or at rest) at the limit to 1e-9."""
    zone = sa.StopZone(0.5, 0.05, 2.5)
    limit = Fraction(1, 2) + Fraction(1, 20) * (Fraction(11, 5) - 1) / (Fraction(5, 2) - 1)
    assert limit == Fraction(27, 50)
    traj = run(FIG18, zone, until="rest", max_periods=1000)
    assert traj.status is sa.Status.ACCUMULATION, traj.message
    assert abs(traj.x_end - float(limit)) <= 1e-12 and traj.v_end == 0.0
    assert traj.info["limit"] == traj.x_end
    assert traj.info["contraction"] == pytest.approx(
        abs(stick_map_contraction(FIG18, w=0.05, c_mu=2.5, x_mu=0.5)), rel=1e-4)
    assert traj.stats["events"] < 200 and traj.period_end < 100
    moreau = run(FIG18, zone, "moreau", until="rest", max_periods=1000)
    assert moreau.status is sa.Status.ACCUMULATION and abs(moreau.x_end - float(limit)) <= 1e-12
    ivp = run(FIG18, zone, "ivp", until="rest", max_periods=200)
    assert ivp.status in (sa.Status.ACCUMULATION, sa.Status.REST), ivp.message
    assert abs(ivp.x_end - float(limit)) <= 1e-9


# ------------------------------------------------------------------------------------------
# 4. Motion that never stops inside the stopping zone
# ------------------------------------------------------------------------------------------

def test_periodic_motion_inside_zone_is_detected():
    """Hazard: with y3'' > y2'' (case 3) the stick positions approach a periodic orbit inside
    the transition zone where the mass slips back during y3'' every period and never comes
    to rest; a naive until-rest loop would run forever.  Expected: NEVER_STOPS well before
    max_periods, with the state at the period boundary a fixed point of the period map
    (one more period returns x to 1e-12 and v to 1e-12); Moreau and ivp stop at max_periods
    with HORIZON and a message saying they cannot decide."""
    p = sa.ThreePhaseProfile(1.05, 0.02, 2.2, 2.5)
    zone = sa.StopZone(0.5, 0.05, 3.5)
    traj = run(p, zone, until="rest", max_periods=2000)
    assert traj.status is sa.Status.NEVER_STOPS, traj.message
    assert traj.period_end < 2000 and zone.x_mu < traj.x_end < zone.x_end
    again = run(p, zone, x0=traj.x_end, v0=traj.v_end, periods=1)
    assert abs(again.x_end - traj.x_end) <= 1e-12 and abs(again.v_end - traj.v_end) <= 1e-12
    for method in ("moreau", "ivp"):
        other = run(p, zone, method, until="rest", max_periods=50)
        assert other.status is sa.Status.HORIZON and "max_periods" in other.message, (method, other.message)


def test_walking_through_a_weak_zone_is_detected():
    """Hazard: c_mu = 1.5 < max|y''| = 2.2, so the mass can stick nowhere in the high-friction
    region (x_stick_min = +inf, eq. 41) and walks on forever.  Expected: NEVER_STOPS with a
    positive net advance per period, after few periods; Moreau and ivp say so too (the same
    period-boundary test, docs/explanation/solvers.md)."""
    zone = sa.StopZone(0.5, 0.05, 1.5)
    assert zone.x_stick_min(FIG18.max_abs_acceleration) == math.inf
    traj = run(FIG18, zone, until="rest", max_periods=1000)
    assert traj.status is sa.Status.NEVER_STOPS and "walks through" in traj.message
    assert traj.x_end >= zone.x_end and traj.period_end < 100
    moreau = run(FIG18, zone, "moreau", until="rest", max_periods=1000)
    assert moreau.status is sa.Status.NEVER_STOPS
    ivp = run(FIG18, zone, "ivp", until="rest", max_periods=30)
    assert ivp.status is sa.Status.NEVER_STOPS and "walks through" in ivp.message


# ------------------------------------------------------------------------------------------
# 5. Stiff transition
# ------------------------------------------------------------------------------------------

def test_stiff_transition_zone():
    """Hazard: w = 1e-9, c_mu = 1e3, i.e. the spring of eq. (42) has b1 ~ 1e12
    (omega ~ 1e6, a period of 6e-6 against dt = 1.05).  From rest at x = x_mu = 0 the mass
    slips forward at t1 as the harmonic oscillator x'' + b1 x = y2'' - 1 (eq. 42): x =
    (y2 - 1)(1 - cos omega s)/b1, v = 0 at s = pi/omega, where mu_bar = 1 + 2 (y2 - 1) =
    3.4 >= max|y''|.  Expected: exact REST at 2 (y2 - 1)/b1 (rtol 1e-12) at tau = t1 +
    pi/omega (1e-12); ivp REST at the same place to 1e-14 absolute; Moreau (omega h ~ 1e3)
    finite, REST, within O(h) of it."""
    zone = sa.StopZone(0.0, 1e-9, 1e3)
    b1 = zone.b1
    traj = run(FIG18, zone, until="rest", max_periods=5)
    assert traj.status is sa.Status.REST, traj.message
    assert traj.x_end == pytest.approx(2 * (FIG18.y2 - 1) / b1, rel=1e-12)
    assert traj.tau_end == pytest.approx(FIG18.t1 + math.pi / math.sqrt(b1), abs=1e-12)
    ivp = run(FIG18, zone, "ivp", until="rest", max_periods=5)
    assert ivp.status is sa.Status.REST and abs(ivp.x_end - traj.x_end) <= 1e-14
    moreau = run(FIG18, zone, "moreau", until="rest", max_periods=5)
    h = FIG18.dt / 1000
    assert moreau.status is sa.Status.REST and abs(moreau.x_end - traj.x_end) <= 10 * h


# ------------------------------------------------------------------------------------------
# 6. Long horizons
# ------------------------------------------------------------------------------------------

@pytest.mark.parametrize("x0, phase", [(0.0, 0.0), (1e6, 0.0), (0.0, 0.3)])
def test_million_periods_no_drift(x0, phase):
    """Hazard: 10^6 periods in uniform friction; a growing float time or a per-period sum
    would drift.  Expected (DESIGN "Solver contract"): the end time is exactly
    (10^6, phase dt) and x_end = x0 + n vbar dt (vbar from steady_state, case 1) to 1e-12
    relative in the distance moved; the start-up period from (x0, 0) at phase 0.3 differs
    from the steady one only by a bounded offset (checked against the one-period run).
    Moreau fast-forwards too, stays finite and within O(h) per period."""
    n = 10**6
    ss = sa.steady_state(FIG18)
    traj = run(FIG18, x0=x0, phase=phase, periods=n)
    assert traj.status is sa.Status.HORIZON
    assert (traj.period_end, traj.tau_end) == (n, phase * FIG18.dt)
    if phase == 0.0:
        assert abs((traj.x_end - x0) - n * ss.vbar * FIG18.dt) <= 1e-12 * n * ss.vbar * FIG18.dt
    else:  # after the first period the motion is the steady one
        first = run(FIG18, x0=x0, phase=phase, periods=1)
        expected = first.x_end + (n - 1) * ss.vbar * FIG18.dt
        assert abs(traj.x_end - expected) <= 1e-12 * n * ss.vbar * FIG18.dt
    moreau = run(FIG18, method="moreau", x0=x0, phase=phase, periods=n)
    assert (moreau.period_end, moreau.tau_end) == (n, phase * FIG18.dt)
    h = FIG18.dt / 1000
    assert abs(moreau.x_end - traj.x_end) <= 10 * h * n * ss.vbar


def test_long_horizon_ivp_agrees():
    """The ivp baseline has no fast-forward: over 300 periods it stays within 1e-8 relative
    of n vbar dt (DOP853, rtol 1e-8), with the end time exactly (300, 0)."""
    ss = sa.steady_state(FIG18)
    ivp = run(FIG18, method="ivp", periods=300)
    assert (ivp.period_end, ivp.tau_end) == (300, 0.0)
    assert ivp.x_end == pytest.approx(300 * ss.vbar * FIG18.dt, rel=1e-8)


# ------------------------------------------------------------------------------------------
# 7. Large offsets
# ------------------------------------------------------------------------------------------

@pytest.mark.parametrize("method", ["exact", "moreau", "ivp"])
def test_large_offset_is_as_accurate_as_zero(method):
    """Hazard: x_mu = 1e6 + 0.5, positions near it; absolute positions there have an ulp of
    1.2e-10, so computing in absolute x would lose the 1e-12 accuracy of the accumulation.
    Expected: the run relative to the zone is the same as at x_mu = 0.5 (same status, same
    number of periods, same event times; x_end - x_mu equal to 1 ulp of 1e6), and for the exact
    solver the relative end position info['x_rel_end'] is bit-for-bit the same."""
    runs = []
    for offset in (0.0, 1e6):
        zone = sa.StopZone(offset + 0.5, 0.05, 2.5)
        runs.append(run(FIG18, zone, method, x0=offset, until="rest", max_periods=300,
                        record=sa.Record(events=method != "moreau")))
    near, far = runs
    assert near.status is far.status and near.period_end == far.period_end
    assert abs((far.x_end - 1e6) - near.x_end) <= np.spacing(1e6)
    assert far.tau_end == near.tau_end
    if method != "moreau":
        np.testing.assert_array_equal(far.events["tau"], near.events["tau"])
        np.testing.assert_allclose(far.events["x"] - 1e6, near.events["x"], rtol=0, atol=np.spacing(1e6))
    if method == "exact":
        assert far.info["x_rel_end"] == near.info["x_rel_end"]


# ------------------------------------------------------------------------------------------
# 8. Edge of feasibility, extreme accelerations and periods
# ------------------------------------------------------------------------------------------

def edge_profile(dt, y2, y3, shrink):
    """The three-phase profile with q = shrink (q = 1 is the case-0 boundary, docs/explanation/model.md)."""
    k = 1.0 / y2 + 1.0 / y3
    return sa.ThreePhaseProfile(dt, dt * dt / (8.0 * k) * shrink**2, y2, y3)


@pytest.mark.parametrize("dt, y2, y3, shrink", [
    (1.05, 2.2, 0.9, 1 - 1e-12),   # case-0 boundary approached to 1e-12: t1 ~ 1e-6 dt
    (1.05, 2.2, 0.9, 1.0),         # on the boundary: t1 = 0, the dwell piece is dropped
    (1e-3, 1e6, 4e5, 1 - 1e-12),   # huge accelerations, tiny period (case 4)
    (1e-2, 1e6, 1e6, 1.0),         # huge, symmetric, on the boundary (net motion ~ 0)
    (1e3, 1e-3, 2e-3, 1 - 1e-12),  # tiny accelerations, huge period (pure stick)
    (1e3, 3.0, 1.5, 1 - 1e-12),    # huge period, moderate accelerations (case 4)
    (0.5, 1e-3, 1e6, 0.5),         # accelerations 9 decades apart (case 2)
])
def test_edge_of_feasibility_and_extreme_scales(dt, y2, y3, shrink):
    """Hazard: the case-0 boundary q -> 1 (t1 -> 0, ~1e-12 relative) and accelerations from
    1e-3 to 1e6 with periods from 1e-3 to 1e3: pieces of length ~1e-9 dt, velocities and
    displacements spanning many decades, cancellation in the net advance.  Expected: the
    exact solver equals the rational reference (from the closed-form steady start velocity
    v0) to 64 ulp of the distance moved over 12 periods; Moreau and ivp finite; ivp to 1e-7
    of the distance moved."""
    p = edge_profile(dt, y2, y3, shrink)
    assert p.feasibility <= 1.0 and 1.0 - p.feasibility <= max(1.0 - shrink, 0.0) + 1e-15
    ss = sa.steady_state(p)
    n = 12
    traj = run(p, v0=ss.v0, periods=n)
    assert traj.status is sa.Status.HORIZON
    assert_matches_reference(traj, p, ss.v0, n)
    _, _, moved = rational_reference(p, ss.v0, n)
    ivp = run(p, method="ivp", v0=ss.v0, periods=n)
    assert ivp.status is sa.Status.HORIZON
    assert abs(ivp.x_end - traj.x_end) <= 1e-7 * float(moved) + 1e-300
    moreau = run(p, method="moreau", v0=ss.v0, periods=n)
    assert moreau.status is sa.Status.HORIZON


def test_beyond_the_boundary_is_case_zero():
    """Hazard: q = 1 + 1e-12 (just infeasible).  Expected: ThreePhaseProfile raises
    NonPhysicalProfile naming the condition; the vectorised functions give case 0 and NaN
    (never a profile with complex or negative t1)."""
    dt, y2, y3 = 1.05, 2.2, 0.9
    k = 1.0 / y2 + 1.0 / y3
    dy = dt * dt / (8.0 * k) * (1 + 1e-12) ** 2
    with pytest.raises(sa.NonPhysicalProfile, match="case 0"):
        sa.ThreePhaseProfile(dt, dy, y2, y3)
    assert sa.classify((dt, dy, y2, y3)) == 0
    assert math.isnan(sa.steady_state((dt, dy, y2, y3)).vbar)


# ------------------------------------------------------------------------------------------
# 9. Non-finite or out-of-range inputs
# ------------------------------------------------------------------------------------------

NAN, INF = float("nan"), float("inf")


@pytest.mark.parametrize("build, name", [
    (lambda: sa.ThreePhaseProfile(NAN, 0.084, 2.2, 0.9), "dt"),
    (lambda: sa.ThreePhaseProfile(1.05, INF, 2.2, 0.9), "dy"),
    (lambda: sa.ThreePhaseProfile(1.05, 0.084, -2.2, 0.9), "y2"),
    (lambda: sa.ThreePhaseProfile(1.05, 0.084, 2.2, 0.0), "y3"),
    (lambda: sa.PolynomialProfile(1.0, NAN), "dy"),
    (lambda: sa.PolynomialProfile(1.0, 0.1, forward_fraction=1.0), "forward_fraction"),
    (lambda: sa.PolynomialProfile(1.0, 0.1, forward_fraction=NAN), "forward_fraction"),
    (lambda: sa.FourierProfile(INF, [0.1], [0.0]), "dt"),
    (lambda: sa.FourierProfile(1.0, [NAN], [0.0]), "Fourier"),
    (lambda: sa.PiecewiseConstantProfile([0.0, NAN, 1.0], [1.0, -1.0], 0.0, 0.0), "breaks"),
    (lambda: sa.PiecewiseConstantProfile([0.0, 0.5, 1.0], [INF, -1.0], 0.0, 0.0), "accels"),
    (lambda: sa.PiecewiseConstantProfile([0.0, 0.7, 0.5, 1.0], [1.0, -1.0, 0.5], 0.0, 0.0), "breaks"),
    (lambda: sa.PiecewiseConstantProfile([0.2, 0.7, 1.0], [1.0, -1.0], 0.0, 0.0), "breaks"),
    (lambda: sa.PiecewiseConstantProfile([0.0, 0.5, 1.0], [1.0, -1.0], NAN, 0.0), "y_start"),
    (lambda: sa.StopZone(NAN, 0.05, 2.5), "x_mu"),
    (lambda: sa.StopZone(0.5, INF, 2.5), "w"),
    (lambda: sa.StopZone(0.5, 0.0, 2.5), "w"),
    (lambda: sa.StopZone(0.5, 0.05, INF), "c_mu"),
    (lambda: sa.StopZone(0.5, 0.05, 0.5), "c_mu"),
    (lambda: sa.Scene(FIG18, x0=NAN, periods=1), "x0"),
    (lambda: sa.Scene(FIG18, v0=INF, periods=1), "v0"),
    (lambda: sa.Scene(FIG18, phase=1.0, periods=1), "phase"),
    (lambda: sa.Scene(FIG18, phase=NAN, periods=1), "phase"),
    (lambda: sa.Scene(FIG18, periods=0), "periods"),
    (lambda: sa.Scene(FIG18, periods=2.5), "periods"),
    (lambda: sa.Scene(FIG18, until="rest", max_periods=0), "max_periods"),
    (lambda: sa.steady_state((1.05, NAN, 2.2, 0.9)), "dy"),
    (lambda: sa.steady_state((1.05, 0.084, INF, 0.9)), "y2"),
    (lambda: sa.classify((-1.05, 0.084, 2.2, 0.9)), "dt"),
    (lambda: sa.classify((1.05, 0.084, 2.2, NAN)), "y3"),
])
def test_bad_input_raises_naming_the_quantity(build, name):
    """Hazard: NaN, inf or out-of-range numbers entering the public API.  Expected: a
    ValueError before any work whose message names the quantity (never a NaN result)."""
    with pytest.raises(ValueError, match=name):
        build()


@pytest.mark.parametrize("method, options, name", [
    ("exact", {"accumulation_tol": NAN}, "accumulation_tol"),
    ("exact", {"max_events": 0}, "max_events"),
    ("moreau", {"h": NAN}, "h"),
    ("moreau", {"h": -1e-3}, "h"),
    ("moreau", {"h": INF}, "h"),
    ("ivp", {"rtol": NAN}, "rtol"),
    ("ivp", {"atol": -1.0}, "atol"),
    ("ivp", {"max_events": 0}, "max_events"),
])
def test_bad_solver_options_raise(method, options, name):
    """Hazard: non-finite or out-of-range solver options.  Expected: ValueError naming the
    option, before any work."""
    with pytest.raises(ValueError, match=name):
        sa.simulate(sa.Scene(FIG18, periods=1), method=method, **options)


@pytest.mark.parametrize("x_n", [NAN, INF, -INF])
def test_stick_map_rejects_non_finite_positions(x_n):
    """Hazard: a non-finite x_n given to the closed-form stick map of eq. (59).  Expected:
    ValueError naming x_n, not a NaN (or inf) stick position."""
    from selfalign.analysis.stick_map import stick_map
    with pytest.raises(ValueError, match="x_n"):
        stick_map(x_n, FIG18, w=0.05, c_mu=2.5, x_mu=0.5)


@pytest.mark.parametrize("kw, name", [
    ({"w": NAN}, "w"), ({"c_mu": INF}, "c_mu"), ({"x_mu": NAN}, "x_mu"), ({"c_mu": 1.0}, "c_mu"),
])
def test_stick_map_rejects_bad_zone(kw, name):
    """Hazard: a non-finite or degenerate zone in the stick map.  Expected: ValueError naming
    the parameter."""
    from selfalign.analysis.stick_map import stick_map
    with pytest.raises(ValueError, match=name):
        stick_map(0.5, FIG18, **{"w": 0.05, "c_mu": 2.5, "x_mu": 0.5, **kw})


@pytest.mark.parametrize("text, key", [
    (".nan", "profile.dt"), (".inf", "profile.dt"), ("-.inf", "profile.dt"),
])
def test_scene_file_rejects_non_finite_numbers(tmp_path, text, key):
    """Hazard: YAML's .nan / .inf in a scene file.  Expected: SceneError naming file and key."""
    path = tmp_path / "bad.yaml"
    path.write_text(f"profile: {{kind: three_phase, dt: {text}, dy: 0.084, y2: 2.2, y3: 0.9}}\n"
                    "horizon: {periods: 1}\n")
    with pytest.raises(sa.SceneError, match=f"bad.yaml: {key}"):
        sa.load_scene(path)


@pytest.mark.parametrize("block, key", [
    ("surface: {kind: stop_zone, x_mu: .nan, c_mu: 2.5}\nbody: {width: 0.05}", "surface.x_mu"),
    ("surface: {kind: stop_zone, x_mu: 0.5, c_mu: 2.5}\nbody: {width: .inf}", "body.width"),
    ("start: {x0: .nan}", "start.x0"),
    ("start: {phase: 1.5}", "start.phase"),
    ("solver: {method: moreau, options: {h: .nan}}", "solver.options.h"),
])
def test_scene_file_rejects_bad_blocks(tmp_path, block, key):
    """Hazard: non-finite or out-of-range values in any block of a scene file.  Expected:
    SceneError naming the file and the key."""
    path = tmp_path / "bad.yaml"
    path.write_text("profile: {kind: three_phase, dt: 1.05, dy: 0.084, y2: 2.2, y3: 0.9}\n"
                    f"horizon: {{periods: 1}}\n{block}\n")
    with pytest.raises(sa.SceneError, match=f"bad.yaml: {key}"):
        sa.load_scene(path)
