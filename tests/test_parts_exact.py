"""The exact event-driven solver of several parts on one table (selfalign.solvers.parts_exact) against the
single-part exact solver, the paper's scaling (Sect. 3.2), the impact law and its own invariants
(docs/explanation/several-parts.md)."""

import math

import numpy as np
import pytest

import selfalign as sa
from selfalign.model.parts import Part
from selfalign.solvers import parts_exact as PE
from selfalign.solvers.parts_exact import simulate_parts

#: The Fig. 18 profile (Sect. 7.3): forward slips only (y3'' < 1).
FIG18 = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
#: A profile of Fig. 16 (Sect. 7.2) at dt = 1: y3'' > 1, so the parts also slip backward.
BACKWARD = sa.ThreePhaseProfile(dt=1.0, dy=0.084, y2=2.3, y3=1.3)
W = 0.05
TOL = 1e-12


def single(profile, x0=0.0, v0=0.0, periods=20):
    """(x_end, v_end) of the single-part exact solver."""
    result = sa.simulate(sa.Scene(profile, x0=x0, v0=v0, periods=periods))
    return result.x_end, result.v_end


def scaled(profile, k):
    """The profile with y'' divided by k (Sect. 3.2's scaling: a part of friction factor k under y'' moves
    as k times a part of factor 1 under y'' / k)."""
    return sa.PiecewiseConstantProfile(profile.breaks, profile.accels / k, profile.piece_position[0] / k,
                                       profile.piece_velocity[0] / k)


@pytest.fixture
def gaps(monkeypatch):
    """The smallest gap between neighbours, relative to the positions' scale, after every event of each run
    (the compiled stepper keeps it: PE._Chain.min_gap); each run's end state is finite."""
    seen = []
    run = PE._Chain.run

    def watched(self, *args, **kwargs):
        result = run(self, *args, **kwargs)
        assert np.all(np.isfinite(self.x)) and np.all(np.isfinite(self.v))
        if self.n > 1:
            seen.append(self.min_gap)
        return result

    monkeypatch.setattr(PE._Chain, "run", watched)
    return seen


@pytest.mark.parametrize("profile", [FIG18, BACKWARD], ids=["fig18", "backward"])
@pytest.mark.parametrize("x0, v0", [(0.0, 0.0), (0.3, -0.4)])
def test_one_part_equals_the_single_part_solver(profile, x0, v0):
    """Hypothesis: with one part the model is the paper's eq. (6) on a uniform surface, and both solvers
    integrate the same closed-form quadratics between the same events (Sects. 4.4.3, 5.1), so after 20
    periods of a three-phase profile x_end and v_end agree with selfalign.simulate to 1e-12."""
    x, v = single(profile, x0, v0)
    result = simulate_parts(profile, [Part(x0, v0, width=W)], periods=20)
    assert result.status == "horizon" and result.t_end == pytest.approx(20 * profile.dt, rel=1e-15)
    assert abs(result.x_end[0] - x) <= TOL and abs(result.v_end[0] - v) <= TOL
    assert result.sticks >= 19 and result.impacts == result.openings == 0


@pytest.mark.parametrize("profile", [FIG18, BACKWARD], ids=["fig18", "backward"])
@pytest.mark.parametrize("phase, x0, v0", [(0.3, 0.0, 0.0), (0.77, 0.3, -0.4), (0.05, 0.1, 0.2)])
def test_a_start_phase_equals_the_single_part_solver_started_there(profile, phase, x0, v0):
    """Hypothesis: a run that starts at tau0 = phase dt (its period boundaries at tau0 + n dt) integrates the
    same closed-form arcs as the single-part solver started at that phase (Scene.phase), piece by piece from
    inside the piece holding tau0, so with one part x_end and v_end agree to 1e-12 after 20 periods, at
    t_end = tau0 + 20 dt; parts far apart each do (they exert no contact force), from the same phase."""
    reference = sa.simulate(sa.Scene(profile, x0=x0, v0=v0, phase=phase, periods=20))
    result = simulate_parts(profile, [Part(x0, v0, width=W)], periods=20, phase=phase)
    assert result.status == "horizon" and abs(result.t_end - (phase * profile.dt + 20 * profile.dt)) <= TOL
    assert abs(result.x_end[0] - reference.x_end) <= TOL and abs(result.v_end[0] - reference.v_end) <= TOL
    starts = [(x0 - 20.0, v0), (x0, v0), (x0 + 20.0, 0.0)]
    far = simulate_parts(profile, [Part(x, v, width=W) for x, v in starts], periods=20, phase=phase)
    assert far.impacts == 0
    for i, (x, v) in enumerate(starts):
        alone = sa.simulate(sa.Scene(profile, x0=x, v0=v, phase=phase, periods=20))
        assert abs(far.x_end[i] - alone.x_end) <= TOL and abs(far.v_end[i] - alone.v_end) <= TOL


@pytest.mark.parametrize("phase", [0.2, 0.6])
def test_a_start_phase_on_a_stop_zone_equals_the_single_part_solver_started_there(phase):
    """Hypothesis: as with a uniform surface, with the transition's arcs and zone crossings (eqs. 42-44): parts
    far apart on a stop zone, each of its own width, started at tau0 = phase dt, each end as the single-part
    solver on StopZone(x_mu, w_i, c_mu) from that phase after 20 periods (to 1e-12)."""
    starts = [(-3.0, 0.03), (0.0, 0.05), (0.7, 0.08)]
    result = simulate_parts(FIG18, [Part(x0, width=w) for x0, w in starts], surface=sa.StopZone(0.15, W, 2.5),
                            periods=20, phase=phase)
    assert result.part_crossings.sum() > 0
    for i, (x0, w) in enumerate(starts):
        reference = sa.simulate(sa.Scene(FIG18, sa.StopZone(0.15, w, 2.5), x0=x0, phase=phase, periods=20))
        assert abs(result.x_end[i] - reference.x_end) <= TOL and abs(result.v_end[i] - reference.v_end) <= TOL


def test_parts_far_apart_each_move_as_alone():
    """Hypothesis: parts whose gaps never close exert no contact force (lam_i = 0 unless the gap is 0,
    docs/explanation/several-parts.md), so each moves as the single-part solver from its own start, to
    1e-12 after 20 periods."""
    starts = [(-20.0, 0.5), (0.0, 0.0), (20.0, -0.3), (40.0, 0.1)]
    parts = [Part(x0, v0, width=W) for x0, v0 in starts]
    result = simulate_parts(BACKWARD, parts, periods=20)
    assert result.impacts == 0 and result.status == "horizon"
    for i, (x0, v0) in enumerate(starts):
        x, v = single(BACKWARD, x0, v0)
        assert abs(result.x_end[i] - x) <= TOL and abs(result.v_end[i] - v) <= TOL


@pytest.mark.parametrize("count", [2, 50])
def test_touching_equal_parts_move_as_one(count, gaps):
    """Hypothesis: equal parts touching at one velocity have equal accelerations from chain_minimiser
    (docs/explanation/several-parts.md), so they stay together and move as the single part, each a width
    ahead of the one behind, to 1e-12 after 20 periods (with backward slips, which pull no contact apart
    either).  No gap becomes negative beyond a few ulp.  (Width 1/16: the touching start positions are
    exact in binary.)"""
    width = 0.0625
    parts = [Part(i * width, width=width) for i in range(count)]
    result = simulate_parts(BACKWARD, parts, periods=20)
    x, v = single(BACKWARD)
    assert result.openings == 0 and result.impacts == 0
    assert np.all(np.abs(result.x_end - (x + width * np.arange(count))) <= TOL)
    assert np.all(np.abs(result.v_end - v) <= TOL)
    assert min(gaps) >= -8 * np.finfo(float).eps


def test_a_part_that_catches_up_then_moves_with_the_other_as_one(gaps):
    """Hypothesis: with e = 0 the rear part, started fast behind a part at rest, merges with it (plastic
    impact, impact_velocities); once both stick at the end of the first period they are one cluster of equal
    parts, so over the next 19 periods they move as the single part from that position (to 1e-12)."""
    parts = [Part(-0.06, 0.5, width=W), Part(0.0, width=W)]
    first = simulate_parts(FIG18, parts, periods=1)
    assert first.impacts == 1 and np.all(first.v_end == 0.0)
    assert abs((first.x_end[1] - W) - first.x_end[0]) <= 1e-15
    result = simulate_parts(FIG18, parts, periods=20)
    x, v = single(FIG18, x0=first.x_end[0], periods=19)
    assert abs(result.x_end[0] - x) <= TOL and abs(result.x_end[1] - (x + W)) <= TOL
    assert result.impacts == 1 and result.openings == 0
    assert min(gaps) >= -8 * np.finfo(float).eps


@pytest.mark.parametrize("masses", [(1.0, 1.0), (1.0, 3.0), (2.0, 0.5)])
def test_a_pushed_cluster_moves_with_the_mass_weighted_factor(masses):
    """Hypothesis: parts pushed together (the rear one with less friction, moving forward) pool in
    chain_minimiser into one part of friction factor k = sum m_i k_i / sum m_i; by the scaling of Sect. 3.2
    such a part under y'' moves as k times a part of factor 1 under y'' / k, so x_end equals k times the
    single-part solver's on the scaled profile (to 1e-12 after 20 periods, the front part a width ahead),
    and equals this solver's own single part of factor k."""
    m0, m1 = masses
    k = (m0 * 1.0 + m1 * 2.0) / (m0 + m1)
    parts = [Part(0.0, width=W, mass=m0, friction_factor=1.0), Part(W, width=W, mass=m1, friction_factor=2.0)]
    result = simulate_parts(FIG18, parts, periods=20)
    x, v = single(scaled(FIG18, k))
    assert result.openings == 0
    assert abs(result.x_end[0] - k * x) <= TOL and abs(result.x_end[1] - (k * x + W)) <= TOL
    assert np.all(np.abs(result.v_end - k * v) <= TOL)
    alone = simulate_parts(FIG18, [Part(0.0, width=W, friction_factor=k)], periods=20)
    assert abs(alone.x_end[0] - result.x_end[0]) <= TOL


def test_parts_touching_at_rest_stick_by_their_pooled_bound():
    """Hypothesis: at v = 0 chain_minimiser pools the stick bounds of pushed parts: under y'' = -1.5 a part
    of factor 1 alone would slip, but touching a part of factor 2 in front the pair's bound is 1.5 and the
    tie |y''| = k mu_bar sticks (tie rule 1), so nothing moves, exactly, and with y'' = 0.5 otherwise the pair
    is at rest for good from the start (status rest at t = 0); under y'' = +1.5 the rear part slips backward
    alone and the contact opens."""
    parts = [Part(0.0, width=W, friction_factor=1.0), Part(W, width=W, friction_factor=2.0)]
    held = sa.PiecewiseConstantProfile([0.0, 0.25, 1.0], [-1.5, 0.5], 0.0, 0.0)
    result = simulate_parts(held, parts, periods=5)
    assert result.x_end.tolist() == [0.0, W] and result.v_end.tolist() == [0.0, 0.0]
    assert result.status == "rest" and result.t_end == 0.0 and result.events == 0
    pulled = sa.PiecewiseConstantProfile([0.0, 0.5, 1.0], [-1.5, 1.5], 0.0, 0.0)
    result = simulate_parts(pulled, parts, periods=1)
    assert result.openings == 1 and result.x_end[1] == W and result.x_end[0] < 0.0


@pytest.mark.parametrize("e", [0.0, 0.5, 1.0])
def test_an_impact_keeps_momentum_and_scales_the_relative_velocity_by_e(e):
    """Hypothesis: with y'' = 0 two parts sliding forward decelerate alike (x'' = -1, eq. 6), so their
    momentum falls at the rate sum m_i and their relative velocity changes only at the impact, where Newton's
    law (impact_velocities) keeps the momentum and turns the approach velocity dv into -e dv: the kinetic
    energy of the relative motion, m_0 m_1 dv^2 / (2 (m_0 + m_1)), is kept for e = 1 and loses the fraction
    1 - e^2 otherwise (to 1e-12 at t = 0.3, after the impact at t = 0.25)."""
    flat = sa.PiecewiseConstantProfile([0.0, 0.3], [0.0], 0.0, 0.0)
    m = np.array([1.0, 2.0])
    v0 = np.array([0.9, 0.5])
    parts = [Part(0.0, 0.9, width=0.1, mass=1.0), Part(0.2, 0.5, width=0.1, mass=2.0)]
    result = simulate_parts(flat, parts, restitution=e, periods=1)
    assert result.impacts == 1 and np.all(result.v_end > 0.0)
    assert abs(m @ result.v_end - (m @ v0 - m.sum() * 0.3)) <= TOL
    reduced = m[0] * m[1] / m.sum()
    before = 0.5 * reduced * (v0[0] - v0[1]) ** 2
    after = 0.5 * reduced * (result.v_end[1] - result.v_end[0]) ** 2
    assert abs(after - e * e * before) <= TOL
    assert abs((result.v_end[1] - result.v_end[0]) - e * (v0[0] - v0[1])) <= TOL


@pytest.mark.parametrize("e, after", [(1.0, (-1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0)), (0.0, (1.0 / 3.0,) * 3)])
def test_newtons_cradle_takes_the_simultaneous_impact_law(e, after):
    """Hypothesis: the impact law is simultaneous over the touching run (docs/explanation/several-parts.md,
    impact_velocities): a part hitting two equal touching parts at rest with speed u leaves them with
    (-1/3, 2/3, 2/3) u for e = 1 (no wave: not (0, 0, 1) u) and (1/3, 1/3, 1/3) u for e = 0.  Under y'' = 0
    the rear part arrives after s* = 1 - sqrt(1 - 2 g) with u = 1 - s* (eq. 21's deceleration, x'' = -1), and
    after the impact every part decelerates toward rest by 1, so at t = 0.01 the velocities are known in
    closed form (to 1e-12); the front two stay one cluster."""
    flat = sa.PiecewiseConstantProfile([0.0, 0.01], [0.0], 0.0, 0.0)
    width, gap = 0.0625, 0.001
    parts = [Part(0.0, 1.0, width=width), Part(gap + width, width=width), Part(gap + 2 * width, width=width)]
    result = simulate_parts(flat, parts, restitution=e, periods=1)
    s_star = 1.0 - math.sqrt(1.0 - 2.0 * gap)
    u = 1.0 - s_star
    expected = [f * u - math.copysign(0.01 - s_star, f) for f in after]
    assert result.impacts == 1 and result.openings == 0
    assert np.all(np.abs(result.v_end - expected) <= TOL)


@pytest.mark.parametrize("e, expected", [(0.0, [0.3, 0.3]), (1.0, [0.0, 0.8])])
def test_parts_that_start_touching_and_approaching_collide_at_once(e, expected):
    """Hypothesis: parts given touching with the rear one faster collide at time 0 (the impact law applies to
    the start state, and the impact counts): two equal parts at (1, 0) leave at (1/2, 1/2) for e = 0 and
    exchange their velocities for e = 1; under y'' = 0 a sliding part then decelerates by 1 and one at rest
    stays stuck, so at t = 0.2 the velocities are (0.3, 0.3) and (0, 0.8) (to 1e-12)."""
    flat = sa.PiecewiseConstantProfile([0.0, 0.2], [0.0], 0.0, 0.0)
    result = simulate_parts(flat, [Part(0.0, 1.0, width=W), Part(W, width=W)], restitution=e, periods=1)
    assert result.impacts == 1
    assert np.all(np.abs(result.v_end - expected) <= TOL)


def test_a_part_that_stops_exactly_at_its_neighbour_grazes_it():
    """Hypothesis: a part sliding at v = 1 under y'' = 0 stops after 1 at x = 0.5 (eq. 21), exactly where a
    part at rest begins: the gap closes with zero relative velocity at the moment v = 0 (tie rules 2, 4),
    so both stick, touching, without overlap, and the run is at rest (k >= max|y''| = 0)."""
    flat = sa.PiecewiseConstantProfile([0.0, 2.0], [0.0], 0.0, 0.0)
    result = simulate_parts(flat, [Part(0.0, 1.0, width=0.1), Part(0.6, width=0.1)], periods=1)
    assert result.status == "rest" and result.t_end == 1.0
    assert result.x_end.tolist() == [0.5, 0.6] and result.v_end.tolist() == [0.0, 0.0]
    assert result.impacts == 1 and result.sticks == 1


def test_a_tangent_closing_touches_and_separates(gaps):
    """Hypothesis: under y'' = -3 a part of factor 3 sliding at v = 1 (x'' = 0) behind a part of factor 1
    starting to slip from rest (x'' = 2) has the gap 0.25 - s + s^2, tangent to 0 at s = 0.5: the contact
    closes with zero relative velocity (one contact event, no impulse) and opens again at once, as the
    front part pulls away (chain_minimiser); no gap goes below 0."""
    push = sa.PiecewiseConstantProfile([0.0, 1.0, 2.0], [-3.0, 3.0], 0.0, 0.0)
    parts = [Part(0.0, 1.0, width=0.1, friction_factor=3.0), Part(0.35, width=0.1)]
    result = simulate_parts(push, parts, periods=1)
    assert result.impacts == 1 and result.openings == 0
    assert min(gaps) >= 0.0


@pytest.mark.parametrize("e", [0.5, 0.9, 0.99])
@pytest.mark.parametrize("mass", [1.0, 1000.0])
def test_bouncing_against_a_stuck_part_under_a_push_ends_in_a_plastic_contact(e, mass, gaps):
    """Hypothesis: a part of factor 1 pushed forward by y'' = -1.5 against a part of factor 3 (stuck: 1.5 < 3)
    bounces with e > 0 infinitely often in a finite time (Zeno: the relative velocity falls geometrically);
    tie rules 4-5 (the contact and velocity floors, docs/explanation/several-parts.md) end the sequence as a
    plastic contact after a finite number of impacts, well before the push ends at t = 3.  Then y'' = +1.5
    pulls the rear part back from rest (x'' = -0.5 for 3), so at t = 6 it lies 2.25 behind the contact
    position and moves at -1.5 (to 1e-12)."""
    push = sa.PiecewiseConstantProfile([0.0, 3.0, 6.0], [-1.5, 1.5], 0.0, 0.0)
    parts = [Part(0.0, width=0.1), Part(0.2, width=0.1, friction_factor=3.0, mass=mass)]
    result = simulate_parts(push, parts, restitution=e, periods=1)
    assert result.status == "horizon" and 3 <= result.impacts <= 500
    assert abs(result.x_end[0] - (result.x_end[1] - 0.1 - 2.25)) <= TOL
    assert abs(result.v_end[0] + 1.5) <= TOL and result.v_end[1] == 0.0
    assert min(gaps) >= -8 * np.finfo(float).eps


def test_a_chain_of_fifty_mixed_parts_stays_ordered_and_finite(gaps):
    """Hypothesis: the event solver keeps its invariants on a long chain of unequal parts (widths, masses,
    friction factors, start velocities; some touching, some apart) with forward and backward slips and
    partly elastic impacts: the state stays finite, no gap goes below a few ulp of the positions' scale,
    and the run reaches its horizon within the event budget."""
    rng = np.random.default_rng(5)
    parts, front = [], 0.0
    for _ in range(50):
        width = rng.uniform(0.02, 0.08)
        front += width + (0.0 if rng.random() < 0.5 else rng.uniform(0.0, 0.05))
        parts.append(Part(front, rng.uniform(-0.3, 0.3), width=width, mass=rng.uniform(0.5, 2.0),
                          friction_factor=rng.uniform(0.8, 1.6)))
    result = simulate_parts(BACKWARD, parts, restitution=0.3, periods=5, max_events=200_000)
    assert result.status == "horizon"
    assert result.impacts > 50 and result.openings > 50
    assert min(gaps) >= -8 * np.finfo(float).eps
    g = (result.x_end[1:] - [p.width for p in parts[1:]]) - result.x_end[:-1]
    assert np.all(g >= -1e-15)


@pytest.mark.parametrize("profile", [FIG18, BACKWARD], ids=["fig18", "backward"])
@pytest.mark.parametrize("x_mu, w, x0, v0", [(0.15, 0.05, 0.0, 0.0), (0.3, 0.05, 0.0, 0.0), (0.2, 0.1, 0.05, 0.3),
                                             (0.1, 0.02, -0.1, 0.0)])
def test_one_part_on_a_stop_zone_equals_the_single_part_solver(profile, x_mu, w, x0, v0):
    """Hypothesis: with one part on a stop zone the model is eq. (38), and both solvers integrate the same
    closed-form arcs (quadratic outside the transition, harmonic and hyperbolic in it: eqs. 42-44) between the
    same events (zone crossings, eq. 47's stick times), so after 20 periods x_end and v_end agree with
    selfalign.simulate to 1e-12: entries that accumulate toward x_stick_min (eq. 41, Sect. 7.3) and one that
    comes to rest for good beyond the transition."""
    zone = sa.StopZone(x_mu, w, 2.5)
    reference = sa.simulate(sa.Scene(profile, zone, x0=x0, v0=v0, periods=20))
    result = simulate_parts(profile, [Part(x0, v0, width=w)], surface=zone, periods=20)
    assert abs(result.x_end[0] - reference.x_end) <= TOL and abs(result.v_end[0] - reference.v_end) <= TOL
    held = reference.v_end == 0.0 and zone.coefficient(reference.x_end) >= profile.max_abs_acceleration
    assert result.status == ("rest" if held else "horizon")


def test_parts_far_apart_on_a_stop_zone_each_feel_their_own_width():
    """Hypothesis: each part's friction is eqs. (7)-(9) over its own width w_i (docs/explanation/several-parts.md),
    so parts that never touch each move as the single-part solver on StopZone(x_mu, w_i, c_mu): one that never
    reaches the zone, one that enters it and accumulates, one that starts on the high-friction side (to 1e-12
    after 20 periods)."""
    zone = (0.15, 2.5)
    starts = [(-3.0, 0.03), (0.0, 0.05), (0.7, 0.08)]
    parts = [Part(x0, width=w) for x0, w in starts]
    result = simulate_parts(FIG18, parts, surface=sa.StopZone(zone[0], W, zone[1]), periods=20)
    assert result.impacts == 0
    for i, (x0, w) in enumerate(starts):
        reference = sa.simulate(sa.Scene(FIG18, sa.StopZone(zone[0], w, zone[1]), x0=x0, periods=20))
        assert abs(result.x_end[i] - reference.x_end) <= TOL and abs(result.v_end[i] - reference.v_end) <= TOL


@pytest.mark.parametrize("c_mu, k_rear, k_front", [(2.5, 1.0, 1.0), (3.0, 1.0, 1.0), (2.5, 1.2, 1.0), (2.5, 1.5, 1.0)])
def test_a_pushed_pair_accumulates_where_its_pooled_friction_holds(c_mu, k_rear, k_front, gaps):
    """Hypothesis: two touching parts of equal mass pushed into a stop zone by the Fig. 18 profile (forward
    slips only) move as one cluster whose friction is the mean of their k mu_bar (chain_minimiser's pooling);
    they come to rest for good where that mean reaches max|y''| = y2'' (the two-part analogue of x_stick_min,
    eq. 41): with the front part on the high-friction side, where the rear one's k mu_bar is 2 y2'' - k_f c_mu,
    i.e. its front at x_mu + w ((2 y2'' - k_f c_mu) / k_r - 1) / (c_mu - 1).  A rear part of higher factor
    first falls behind (the contact opens at the first push) and catches up once the front one brakes in the
    zone.  They approach the rest position stick by stick, as the single part approaches x_stick_min
    (Sect. 7.3), and reach it to rounding within 60 periods (1e-12); no gap goes below 0 beyond a few ulp."""
    zone = sa.StopZone(0.15, W, c_mu)
    parts = [Part(-W, width=W, friction_factor=k_rear), Part(0.0, width=W, friction_factor=k_front)]
    result = simulate_parts(FIG18, parts, surface=zone, periods=60)
    rest = 0.15 + W * ((2.0 * FIG18.y2 - k_front * c_mu) / k_rear - 1.0) / (c_mu - 1.0)
    assert abs(result.x_end[0] - rest) <= TOL and abs(result.x_end[1] - (rest + W)) <= TOL
    assert result.openings == (0 if k_rear == k_front else 1) and np.all(result.v_end == 0.0)
    assert min(gaps) >= -8 * np.finfo(float).eps


def test_a_sliding_pair_separates_where_its_contact_force_vanishes(gaps):
    """Hypothesis: inside a sliding cluster of two equal masses the contact force is lam = m (b_r - b_f) / 2
    with b_i = -y'' - k_i mu_bar_i (chain_minimiser's pooling, docs/explanation/several-parts.md); it is affine
    in the displacement in the zone and falls to zero exactly where k_r mu_bar_r = k_f mu_bar_f.  A pair of
    factors (0.8, 0.7) pushed by the Fig. 18 profile into StopZone(0.1, 0.05, 2) slides together with the front
    part on the high-friction side (0.7 c_mu = 1.4) until the rear part's mu_bar reaches 1.75, its front at
    x_mu + 0.75 w: there the contact opens, at one velocity and one acceleration (to 1e-12), and the parts
    never overlap.  The state at each event is read by stopping the run there (its event budget): the first
    opening of the contact between parts sliding at one velocity is that one."""
    parts = [Part(-0.05, width=0.05, friction_factor=0.8), Part(0.0, width=0.05, friction_factor=0.7)]
    zone = sa.StopZone(0.1, 0.05, 2.0)
    result = simulate_parts(FIG18, parts, surface=zone, periods=12)
    opened, budget, openings = None, 1, 0
    while opened is None and budget <= result.events:
        chain = PE._Chain(FIG18, parts, 0.0, zone)
        stop = chain.run(12, budget)
        if stop.openings > openings and chain.v[0] == chain.v[1] > 0.0:
            opened = (chain.x + chain.origin, chain.v.copy(), chain.a.copy())
        openings, budget = stop.openings, budget + 1
    assert opened is not None and result.openings >= 1
    x, v, a = opened
    assert abs(x[0] - (0.1 + 0.75 * 0.05)) <= TOL and abs(x[1] - x[0] - 0.05) <= TOL
    assert v[0] == v[1] > 0.0 and abs(a[1] - a[0]) <= TOL
    assert min(gaps) >= -8 * np.finfo(float).eps


def random_chain(seed, rear, *, widths, touching, gap, factors, count=8):
    """``count`` parts of random widths, start velocities in [-0.3, 0.3], masses and friction factors, the
    rear-most with its rear at ``rear``; each touches the one behind it with probability ``touching``, else
    lies up to ``gap`` ahead of it."""
    rng = np.random.default_rng(seed)
    parts, front = [], rear
    for _ in range(count):
        width = rng.uniform(*widths)
        front += width + (0.0 if rng.random() < touching else rng.uniform(0.0, gap))
        parts.append(Part(front, rng.uniform(-0.3, 0.3), width=width, mass=rng.uniform(0.5, 2.0),
                          friction_factor=rng.uniform(*factors)))
    return parts


def test_a_mixed_chain_entering_a_stop_zone_stays_ordered_and_finite(gaps):
    """Hypothesis: on a stop zone the clusters follow harmonic and hyperbolic arcs, contacts close on a search
    that cannot pass a closing (conservative advancement with exact derivatives) and open where a contact force
    falls to zero; the invariants hold: a finite state, no gap below a few ulp, the horizon reached."""
    parts = random_chain(11, -0.4, widths=(0.02, 0.08), touching=0.5, gap=0.05, factors=(0.8, 1.6))
    result = simulate_parts(BACKWARD, parts, surface=sa.StopZone(0.0, 0.05, 2.0), restitution=0.3, periods=15)
    assert result.status in ("horizon", "rest")
    assert result.impacts > 10
    assert min(gaps) >= -8 * np.finfo(float).eps


@pytest.mark.parametrize("surface", [None, sa.StopZone(3.0, 0.05, 2.5)], ids=["uniform", "zone"])
def test_a_chain_of_a_hundred_parts_keeps_its_invariants_and_restarts_from_its_end_state(surface, gaps):
    """Hypothesis: the solver's invariants hold at scale: a chain of 100 unequal parts (half of them touching)
    under the Fig. 16 profile (slips both ways: contacts close and open in every period), plastic contacts,
    on a uniform surface and running into a stop zone, ends 50 periods with status horizon or rest, finite,
    with no gap below -16 ulp of the positions (none below -8 ulp of the positions' scale after any event).
    The run depends on its state only (positions and velocities: touching contacts are found again within
    the contact tolerance, velocity runs pool again within the velocity floor, tie rules 4-5), so the same run
    in two halves, the second started from the first's end state, ends where the whole run does, to 1e-12
    (plastic contacts: no impact sequence amplifies rounding differences, as e > 0 can,
    tests/test_parts_crosscheck.py)."""
    parts = random_chain(7, 0.0, widths=(0.02, 0.08), touching=0.5, gap=0.05, factors=(0.8, 1.6), count=100)
    result = simulate_parts(BACKWARD, parts, surface=surface, periods=50)
    assert result.status in ("horizon", "rest") and result.impacts > 100 and result.openings > 100
    assert np.all(np.isfinite(result.x_end)) and np.all(np.isfinite(result.v_end))
    g = (result.x_end[1:] - [p.width for p in parts[1:]]) - result.x_end[:-1]
    assert np.all(g >= -16 * np.spacing(np.maximum(np.abs(result.x_end[:-1]), np.abs(result.x_end[1:]))))
    assert min(gaps) >= -8 * np.finfo(float).eps
    first = simulate_parts(BACKWARD, parts, surface=surface, periods=25)
    restart = [Part(x, v, width=p.width, mass=p.mass, friction_factor=p.friction_factor)
               for x, v, p in zip(first.x_end, first.v_end, parts)]
    second = simulate_parts(BACKWARD, restart, surface=surface, periods=25)
    assert np.max(np.abs(second.x_end - result.x_end)) <= TOL and np.max(np.abs(second.v_end - result.v_end)) <= TOL
    if surface is not None:
        assert result.part_crossings.sum() > 0


@pytest.mark.parametrize("surface, e", [(None, 0.5), (sa.StopZone(0.0, 0.05, 2.0), 0.0)], ids=["uniform", "zone"])
def test_the_exact_solver_and_moreau_time_stepping_agree(surface, e):
    """Hypothesis: the exact solver and Moreau's midpoint time-stepping of the same model
    (selfalign.solvers.parts_moreau, a first-order scheme, Sect. 4.1) are independent; on a chain of eight
    unequal parts (some touching, impacts, contacts opening; on the stop zone also harmonic and hyperbolic
    arcs) over five periods they agree to the time-stepping's error, measured at 3e-6 to 1e-5 for
    h = dt / 1e5 (and ten times that for dt / 1e4): the test allows 5e-5."""
    from selfalign.solvers.parts_moreau import moreau_parts

    parts = random_chain(3, -0.3, widths=(0.03, 0.07), touching=0.6, gap=0.03, factors=(0.7, 1.5))
    exact = simulate_parts(BACKWARD, parts, surface=surface, restitution=e, periods=5)
    moreau = moreau_parts(BACKWARD, parts, surface=surface, restitution=e, periods=5, steps_per_period=100_000)
    assert exact.impacts > 5
    assert np.max(np.abs(moreau.x_end - exact.x_end)) <= 5e-5
    assert np.max(np.abs(moreau.v_end - exact.v_end)) <= 5e-5


def single_part_events(profile, surface, x0, v0, periods):
    """(sticks, slip starts and reversals, zone crossings) in the event log of the single-part exact solver."""
    traj = sa.simulate(sa.Scene(profile, surface or sa.Uniform(), x0=x0, v0=v0, periods=periods,
                                record=sa.Record(events=True)))
    kinds = traj.events["kind"]
    return (int(np.sum(kinds == int(sa.EventKind.STICK))),
            int(np.sum((kinds == int(sa.EventKind.SLIP)) | (kinds == int(sa.EventKind.REVERSAL)))),
            int(np.sum(kinds == int(sa.EventKind.ZONE))))


@pytest.mark.parametrize("profile, surface, starts", [
    (BACKWARD, None, [(-20.0, 0.5, W), (0.0, 0.0, W), (20.0, -0.3, W)]),
    (FIG18, sa.StopZone(0.15, W, 2.5), [(-3.0, 0.0, 0.03), (0.0, 0.0, 0.05), (0.7, 0.0, 0.08)]),
], ids=["uniform", "zone"])
def test_parts_far_apart_count_their_events_as_alone(profile, surface, starts):
    """Hypothesis: parts that never touch move as alone (docs/explanation/several-parts.md), so each part's
    sticks, slip starts (from stick, or reversals) and zone crossings are those of the single-part solver's
    event log over the same 20 periods (on a stop zone the part's own width, eqs. 7-9), exactly, and it
    takes part in no contact closing or opening; the totals of sticks and slips are the sums over the
    parts (each cluster is one part)."""
    parts = [Part(x0, v0, width=w) for x0, v0, w in starts]
    result = simulate_parts(profile, parts, surface=surface, periods=20)
    for i, (x0, v0, w) in enumerate(starts):
        zone = None if surface is None else sa.StopZone(surface.x_mu, w, surface.c_mu)
        expected = single_part_events(profile, zone, x0, v0, 20)
        assert (result.part_sticks[i], result.part_slips[i], result.part_crossings[i]) == expected, i
    assert result.part_sticks.shape == (3,) and result.part_sticks.sum() == result.sticks > 0
    assert result.part_slips.sum() == result.slips > 0
    assert not result.part_impacts.any() and not result.part_openings.any()
    assert (result.part_crossings.sum() > 0) == (surface is not None)


def test_events_per_part_count_every_part_of_a_cluster_and_both_parts_of_a_contact():
    """Hypothesis: a stick or slip start of a cluster is one event in which each of its parts takes part, and a
    contact closing or opening involves the two parts of the contact: a pushed pair (docs/explanation/
    several-parts.md: touching, they move as one part) counts the same sticks and slips for both parts, each
    the total; in the chase of Fig. 18 (the rear part, k = 0.7, hits the front one in every period) each of
    the two parts counts every impact and opening; in a chain of eight, the counts per part add up to twice
    the totals of closings and openings."""
    pair = simulate_parts(FIG18, [Part(0.0, width=W), Part(W, width=W)], periods=10)
    assert pair.part_sticks.tolist() == [pair.sticks] * 2 and pair.part_slips.tolist() == [pair.slips] * 2
    assert pair.sticks >= 10 and not pair.part_impacts.any()
    chase = simulate_parts(FIG18, [Part(0.0, width=W, friction_factor=0.7), Part(0.06, width=W)], periods=10)
    assert chase.part_impacts.tolist() == [chase.impacts] * 2 and chase.impacts >= 5
    assert chase.part_openings.tolist() == [chase.openings] * 2
    parts = random_chain(3, -0.3, widths=(0.03, 0.07), touching=0.6, gap=0.03, factors=(0.7, 1.5))
    chain = simulate_parts(BACKWARD, parts, restitution=0.5, periods=5)
    assert chain.part_impacts.sum() == 2 * chain.impacts > 0 and chain.part_openings.sum() == 2 * chain.openings > 0
    assert chain.part_sticks.sum() >= chain.sticks and chain.part_slips.sum() >= chain.slips


def test_parts_held_for_good_end_at_rest():
    """Hypothesis: a part whose friction k mu_bar is at least max|y''| can never slip once stuck (Sect. 3.2's
    stick condition with k mu_bar for 1), so a run whose parts all stick where this holds ends with status
    'rest' at that moment: at once from rest, or at the stick of eq. (21) from v0 = 0.3 in the dwell (y'' = 0,
    stop after 0.3 / k)."""
    parts = [Part(0.0, width=W, friction_factor=3.0), Part(0.1, width=W, friction_factor=2.5)]
    result = simulate_parts(FIG18, parts, periods=5)
    assert result.status == "rest" and result.t_end == 0.0 and result.events == 0
    parts[0] = Part(0.0, 0.3, width=W, friction_factor=3.0)
    result = simulate_parts(FIG18, parts, periods=5)
    assert result.status == "rest" and abs(result.t_end - 0.1) <= TOL and result.sticks == 1


def test_the_event_budget_ends_the_run_with_an_error():
    """Hypothesis: a run that uses up max_events stops with status 'error' and a message naming the budget,
    at a finite state, at the first event time that reaches the budget (one event time may count several
    events: a break and the slip it starts)."""
    result = simulate_parts(FIG18, [Part(0.0, width=W)], periods=20, max_events=5)
    assert result.status == "error" and "max_events = 5" in result.message
    assert 5 <= result.events <= 6 and np.isfinite(result.x_end[0]) and result.t_end < 2 * FIG18.dt


def test_the_compiled_event_loop_allocates_nothing():
    """Hypothesis: the event loop runs in the arrays the caller allocated (selfalign.solvers.engine.parts), so
    numba's runtime counts the same allocations for a run of 2 periods as for one of 50 with hundreds more events
    (those of passing the arrays in), on a stop zone with impacts (e = 0.3); NUMBA_NRT_STATS=1 makes it count,
    in a fresh process, after a first run has started the runtime."""
    import subprocess
    import sys

    code = ("import selfalign as sa\n"
            "from numba.core.runtime import rtsys\n"
            "from selfalign.model.parts import Part\n"
            "from selfalign.solvers import parts_exact as PE\n"
            "profile = sa.ThreePhaseProfile(dt=1.0, dy=0.084, y2=2.3, y3=1.3)\n"
            "parts = [Part(i * 0.0625, 0.1 * (i % 3), width=0.0625) for i in range(20)]\n"
            "PE._Chain(profile, parts, 0.3, sa.StopZone(0.5, 0.05, 2.0)).run(1, 10)\n"
            "for periods in (2, 50):\n"
            "    chain = PE._Chain(profile, parts, 0.3, sa.StopZone(0.5, 0.05, 2.0))\n"
            "    before = rtsys.get_allocation_stats().alloc\n"
            "    result = chain.run(periods, 10 ** 7)\n"
            "    print(result.events, rtsys.get_allocation_stats().alloc - before)\n")
    env = {**__import__("os").environ, "NUMBA_NRT_STATS": "1"}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    (few, allocated_few), (many, allocated_many) = [map(int, line.split()) for line in out.stdout.split("\n") if line]
    assert many >= few + 300 and allocated_many == allocated_few


@pytest.mark.parametrize("call, error, words", [
    (lambda: simulate_parts(FIG18, [], periods=1), ValueError, "at least one Part"),
    (lambda: simulate_parts(FIG18, [Part(0.0, width=W), Part(0.01, width=W)], periods=1), ValueError,
     "parts[1] overlaps parts[0]"),
    (lambda: simulate_parts(FIG18, [Part(0.0, width=W), "part"], periods=1), TypeError, "parts[1]"),
    (lambda: Part(0.0, width=0.0), ValueError, "width"),
    (lambda: Part(math.nan, width=W), ValueError, "x0"),
    (lambda: Part(0.0, math.inf, width=W), ValueError, "v0"),
    (lambda: simulate_parts(FIG18, [Part(0.0, width=W)], restitution=1.5, periods=1), ValueError, "restitution"),
    (lambda: simulate_parts(FIG18, [Part(0.0, width=W)], restitution=-0.1, periods=1), ValueError,
     "restitution"),
    (lambda: simulate_parts(FIG18, [Part(0.0, width=W)], restitution=math.nan, periods=1), ValueError,
     "restitution"),
    (lambda: simulate_parts(FIG18, [Part(0.0, width=W)], periods=0), ValueError, "periods"),
    (lambda: simulate_parts(FIG18, [Part(0.0, width=W)], periods=2.5), TypeError, "periods"),
    (lambda: simulate_parts(FIG18, [Part(0.0, width=W)], periods=1, max_events=0), ValueError, "max_events"),
    (lambda: simulate_parts(FIG18, [Part(0.0, width=W)], periods=1, phase=1.0), ValueError, "phase"),
    (lambda: simulate_parts(FIG18, [Part(0.0, width=W)], periods=1, phase=-0.1), ValueError, "phase"),
    (lambda: simulate_parts(FIG18, [Part(0.0, width=W)], periods=1, phase=math.nan), ValueError, "phase"),
    (lambda: simulate_parts(FIG18, [Part(0.0, width=W)], periods=1, phase="0.5"), TypeError, "phase"),
    (lambda: simulate_parts(sa.FourierProfile(1.0, [0.01], [0.0]), [Part(0.0, width=W)], periods=1), TypeError,
     "PiecewiseConstantProfile"),
    (lambda: simulate_parts(FIG18, [Part(0.0, width=W)], surface="uniform", periods=1), TypeError, "surface"),
    (lambda: simulate_parts(FIG18, [Part(0.0, width=W)], surface=sa.StopZone, periods=1), TypeError, "surface"),
])
def test_bad_input_is_refused_naming_the_parameter(call, error, words):
    """Hypothesis: every input is checked before any work, and the error names the part (its index) or the
    parameter and what is allowed."""
    with pytest.raises(error) as info:
        call()
    assert words in str(info.value)
