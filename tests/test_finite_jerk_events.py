"""Event location of the exact solver on finite-jerk (piecewise-linear y'') profiles, uniform surface
and stop zone (eqs. 7-9), and the profile's own limits: a ramp ends on its level, a ramp below the
rounding of its break times is refused.

The argument that no event in a bracket is missed is in the docstrings of kernel._jerk_arc_end
(stop zone) and kernel._slip_minimum (uniform surface), and in docs/explanation/model.md.  The tests
below are the cases the bracketing used to miss: an edge crossed and a stop within one bracket,
and a dip of the slip velocity through 0 between two grid points."""

from __future__ import annotations

import warnings

import mpmath
import numpy as np
import pytest
from conftest import random_three_phase

import selfalign as sa
from selfalign.io.scene_files import scene_from_dict
from selfalign.model.design_spec import DesignSpec
from selfalign.model.errors import SceneError
from selfalign.model.friction import FrictionLaw
from selfalign.model.profiles import MIN_RAMP_FRACTION, FiniteJerkProfile, PiecewiseLinearProfile
from selfalign.solvers.outcomes import EventKind

STOPS = (int(EventKind.STICK), int(EventKind.REVERSAL))


def test_a_slip_that_crosses_the_edge_and_stops_in_one_bracket_changes_friction_at_the_edge():
    """A backward slip from the high-friction region (x > x_mu + w) crosses x_mu + w and comes to
    rest in the transition zone within one bracketing interval (1/16 of the plateau).  The arc is
    split at the edge (a ZONE event at x_mu + w, then the stop with the zone's friction), and the
    end of the period agrees with solve_ivp to its tolerance: within 1e-12 at rtol 1e-12 and within
    1e-13 at rtol 1e-13 (measured 2.3e-15), at x = 0.066981 as a 40-digit integration of the model
    gives.  Kept in the high region's friction, the slip stopped at 0.068119 (25 % of w off)."""
    profile = FiniteJerkProfile(dt=1.894938754863851, dy=0.44171055687034616, y2=2.007288840463955,
                                y3=25.26034499836723, ramp=2.6206890177234233e-09)
    zone = sa.StopZone(x_mu=0.0657331206208891, w=0.004585538105349093, c_mu=15.86714150454164)
    scene = sa.Scene(profile, zone, x0=0.10135612223723969, v0=0.0, phase=0.7329592009141759, periods=1,
                     record=sa.Record(events=True))
    exact = sa.simulate(scene)
    ev = exact.events
    stop = np.flatnonzero(np.isin(ev["kind"], STOPS))[0]
    assert ev["kind"][stop - 1] == int(EventKind.ZONE) and ev["x"][stop - 1] == zone.x_mu + zone.w
    assert zone.x_mu < ev["x"][stop] < zone.x_mu + zone.w
    assert abs(exact.x_end - 0.066981) <= 5e-7
    for rtol in (1e-12, 1e-13):
        ivp = sa.simulate(scene, method="ivp", rtol=rtol, atol=rtol * 1e-2)
        assert abs(ivp.x_end - exact.x_end) <= rtol, rtol


def first_stop_referee(a, zone, x0, v0):
    """The position where a slip from (x0, v0) under the constant table acceleration a first comes
    to rest, in 40-digit arithmetic, from the energy balance of x'' = -a - sigma mu_bar(x) (eqs. 6-9):
    d(v^2 / 2) / du = -sigma (a + sigma mu_bar) along the path u.  mu_bar is 1, 1 + b1 (x - x_mu),
    c_mu on the three regions, so on each the remaining energy is a quadratic in u, solved exactly."""
    mp = mpmath.mp
    mp.dps = 40
    sigma = 1 if v0 > 0 else -1
    x_mu, w, c = (mpmath.mpf(v) for v in (zone.x_mu, zone.w, zone.c_mu))
    b1, a = (c - 1) / w, mpmath.mpf(a)
    bounds = sorted([x_mu, x_mu + w], key=lambda b: sigma * b)
    ahead = [b for b in bounds if sigma * (b - mpmath.mpf(x0)) > 0]
    energy, start = mpmath.mpf(v0) ** 2 / 2, mpmath.mpf(x0)
    for end in ahead + [None]:
        mid = start + sigma * mpmath.mpf("1e-30")          # the region the path is in
        slope = sigma * b1 if x_mu < mid < x_mu + w else 0
        mu = 1 if mid <= x_mu else (c if mid >= x_mu + w else 1 + b1 * (start - x_mu))
        k1, k2 = sigma * (a + sigma * mu), slope / 2          # energy(u) = E - k1 u - k2 u^2
        length = abs(end - start) if end is not None else mpmath.inf
        roots = mpmath.polyroots([-energy, k1, k2], asc=True) if k2 != 0 else ([energy / k1] if k1 != 0 else [])
        inside = sorted(mpmath.re(r) for r in roots if abs(mpmath.im(r)) < mpmath.mpf("1e-30")
                        and 0 <= mpmath.re(r) <= length)
        if inside:
            return float(start + sigma * inside[0])
        energy -= k1 * length + k2 * length**2
        start = end
    return None


def edge_scenes(count, seed):
    """Slips that cross a zone edge and stop just past it, on a plateau of random finite-jerk
    profiles (ramps 1e-9 ... 0.1 dt): backward through x_mu + w or x_mu, forward through x_mu or
    x_mu + w; the start velocity gives the energy to reach the edge plus a stop 1e-4 ... 0.5 of the
    start distance past it (distances 1e-3 ... 0.5 of w)."""
    def complete(rng, dt, dy, y2, y3):
        try:
            p = FiniteJerkProfile(dt, dy, y2, y3, ramp=dt * np.exp(rng.uniform(np.log(1e-9), np.log(0.1))))
        except ValueError:
            return None
        zone = sa.StopZone(rng.uniform(-0.2, 0.2), np.exp(rng.uniform(np.log(0.002), np.log(0.05))),
                           rng.uniform(1.5, 16.0))
        b1 = (zone.c_mu - 1.0) / zone.w
        start, end, a = [(p.breaks[1], p.breaks[2], 0.0), (p.breaks[3], p.breaks[4], -y2),
                         (p.breaks[5], p.breaks[6], y3)][rng.integers(3)]
        delta = zone.w * np.exp(rng.uniform(np.log(1e-3), np.log(0.5)))
        past = delta * np.exp(rng.uniform(np.log(1e-4), np.log(0.5)))
        case = rng.integers(4)
        # (start offset from x_mu, direction, work to the edge, work past it per unit length at the edge)
        if case == 0:        # backward from the high region through x_mu + w
            x0, sigma, work, rate = zone.w + delta, -1.0, (zone.c_mu - a) * delta, 1.0 + b1 * zone.w - a
        elif case == 1:      # forward from the low region through x_mu
            x0, sigma, work, rate = -delta, 1.0, (a + 1.0) * delta, a + 1.0
        elif case == 2:      # forward in the zone through x_mu + w
            d = min(delta, zone.w)
            x0, sigma, work, rate = zone.w - d, 1.0, (a + 1.0 + b1 * (zone.w - d / 2)) * d, a + zone.c_mu
        else:                # backward in the zone through x_mu
            d = min(delta, zone.w)
            x0, sigma, work, rate = d, -1.0, (1.0 + b1 * d / 2 - a) * d, 1.0 - a
        if not (work > 0.0 and rate > 0.0):
            return None
        return p, zone, a, (start, end), zone.x_mu + x0, sigma * np.sqrt(2.0 * (work + rate * past)), \
            (start + rng.uniform(0.0, 0.5) * (end - start)) / dt
    return random_three_phase(count, seed, accelerations=(0.5, 30.0), strokes=(0.05, 0.95), complete=complete)


def test_slips_that_stop_just_past_an_edge_stop_where_the_energy_balance_says():
    """200 slips that cross a zone edge (either edge, either direction, from the low or high
    region or from inside the zone) and stop just past it; the 195 that stop on the plateau of y''
    they start on are checked, 187 of them stopping within 1/16 of the plateau (the bracket) after
    the crossing.  Where the slip first comes to rest equals the 40-digit energy balance
    (first_stop_referee) to 1e-15 (measured <= 1.4e-17), and the edge is logged (a ZONE event)
    before the stop.  Before the edge was searched for in a bracket that ends with a
    stop, 134 of 300 such slips were off by more than 1e-12, up to 1.7e-5.  (solve_ivp is no
    referee here: at rtol 1e-13 its step can hold both the crossing and the stop, and it misses
    the edge in a quarter of them, by up to 1.5e-6.)"""
    checked = 0
    for p, zone, a, (start, end), x0, v0, phase in edge_scenes(200, seed=22):
        traj = sa.simulate(sa.Scene(p, zone, x0=x0, v0=v0, phase=phase, periods=1, record=sa.Record(events=True)))
        ev = traj.events
        stop = np.flatnonzero(np.isin(ev["kind"], STOPS))[0]
        if not ev["tau"][stop] + p.dt * ev["period"][stop] < end:      # the plateau ended first
            continue
        assert int(EventKind.ZONE) in ev["kind"][:stop].tolist()
        assert abs(ev["x"][stop] - first_stop_referee(a, zone, x0, v0)) <= 1e-15, (p, zone, x0, v0, phase)
        checked += 1
    assert checked >= 190


@pytest.mark.parametrize("surface", [sa.Uniform(), sa.StopZone(10.0, 0.05, 2.5)], ids=["uniform", "zone"])
@pytest.mark.parametrize("ratio", [1.0, 1.5])
def test_a_dip_of_the_slip_velocity_between_grid_points_stops_the_slip(surface, ratio):
    """A forward slip entering the ramp of y'' from 0 to -y2 (jerk -y2/T) with v0 = 0.99 T / (2 y2):
    x' = v0 - s + y2 s^2 / (2 T) dips through 0 at s1 = (T / y2) (1 - sqrt(1 - 2 y2 v0 / T)) and back
    at (T / y2) (1 + 0.1), both within the first sixteenth of the ramp (no grid point sees x' < 0).
    At s1 |y''| = 0.9 < r mu_bar, so the mass sticks there and slips again where |y''| = r (r = 1:
    the paper's Coulomb law; r = 1.5: static/kinetic), at s = r T / y2.  The uniform surface's smooth
    stepper and, far below the zone (mu_bar = 1), the stop-zone stepper log the stick and the slip
    at these times to 1e-14 and the stick at x = v0 s1 - s1^2 / 2 + y2 s1^3 / (6 T) to 1e-15;
    before, both slid through the dip (the end of the period 2.3e-6 off for r = 1, 5.5e-5 for 1.5)."""
    dt, y2 = 1.05, 20.0
    ramp = 0.01 * dt
    profile = FiniteJerkProfile(dt, 0.4, y2, 5.0, ramp=ramp)
    start = profile.breaks[2]                               # the ramp from 0 to -y2 starts here
    v0 = 0.99 * ramp / (2.0 * y2)
    s1 = ramp / y2 * (1.0 - np.sqrt(1.0 - 2.0 * y2 * v0 / ramp))
    friction = FrictionLaw("static_kinetic", ratio) if ratio > 1.0 else FrictionLaw()
    traj = sa.simulate(sa.Scene(profile, surface, friction=friction, x0=0.0, v0=v0, phase=start / dt, periods=1,
                                record=sa.Record(events=True)))
    ev = traj.events
    assert ev["kind"][:2].tolist() == [int(EventKind.STICK), int(EventKind.SLIP)]
    assert abs(ev["tau"][0] - (start + s1)) <= 1e-14
    assert abs(ev["tau"][1] - (start + ratio * ramp / y2)) <= 1e-14
    assert abs(ev["x"][0] - (v0 * s1 - s1**2 / 2.0 + y2 * s1**3 / (6.0 * ramp))) <= 1e-15


def tiny_ramp_profiles(count, seed):
    """Random finite-jerk profiles with ramps of 1e-10 ... 1e-6 dt, ramp or jerk given, y2'' and y3''
    in [2, 8]."""
    def complete(rng, dt, dy, y2, y3):
        fraction = np.exp(rng.uniform(np.log(1e-10), np.log(1e-6)))
        kw = {"ramp": dt * fraction} if rng.random() < 0.5 else {"jerk": (y2 + y3) / (dt * fraction)}
        try:
            return FiniteJerkProfile(dt, dy, y2, y3, **kw)
        except ValueError:
            return None
    return random_three_phase(count, seed, accelerations=(2.0, 8.0), strokes=(0.05, 0.9), complete=complete)


def test_ramps_end_on_their_levels():
    """y'' of a finite-jerk profile stays within its levels 0, -y2, +y3: a ramp's a + j s, with
    break times rounded to ~eps dt, passes its level by ~|j| eps dt (5e-8 of it for a ramp of 1e-9 dt),
    so every piece ends on its level exactly (``ends``) and y'' is clamped between its piece's start
    and end.  For 200 profiles with ramps of 1e-10 ... 1e-6 dt, y'' at the breaks, a few ulps
    around them and on a grid lies in [-y2, y3] exactly, each piece ends on its level, and
    max|y''| (the solvers' rest-for-good bound) is max(y2, y3)."""
    for p in tiny_ramp_profiles(200, seed=3):
        assert p.ends.tolist() == [0.0, 0.0, -p.y2, -p.y2, p.y3, p.y3, p.y3 / 2.0]
        assert p.max_abs_acceleration == max(p.y2, p.y3)
        near = np.concatenate([np.nextafter(p.breaks, -np.inf), p.breaks, np.nextafter(p.breaks, np.inf),
                               p.breaks + 1e-12 * p.dt, p.breaks - 1e-12 * p.dt, np.linspace(0.0, p.dt, 2001)])
        acc = p.acceleration(np.clip(near, 0.0, np.nextafter(p.dt, 0.0)))
        assert acc.min() >= -p.y2 and acc.max() <= p.y3
        lengths = np.diff(p.breaks)
        assert np.all(np.abs(p.accels + p.jerks * lengths - p.ends) <= 64 * np.finfo(float).eps
                      * (np.abs(p.jerks) * p.dt + np.abs(p.ends)))


def test_rest_for_good_holds_on_a_finite_jerk_profile_with_static_friction():
    """A part stuck in the high-friction region where r mu_bar = r c_mu exceeds max|y''| = y3 by
    1e-10 relative: until rest reports REST at once (r mu_bar >= max|y''|), and over 26 periods
    the exact solver keeps it stuck (no event, x unchanged), as solve_ivp and Moreau do.  With
    the ramp's end 5e-8 past y3 (a ramp of 1.1e-9 dt) the exact solver had slipped and moved -13.5."""
    profile = FiniteJerkProfile(dt=2.3306958575432506, dy=0.4074294031507002, y2=0.8514994181888922,
                                y3=5.012491056219614, ramp=2.5898668734937754e-09)
    zone = sa.StopZone(0.14990798281717432, 0.001252392204892083, 1.6566822587882808)
    friction = FrictionLaw("static_kinetic", 3.0256200488301195)
    x0 = 0.41249198266242665
    rest = sa.simulate(sa.Scene(profile, zone, friction=friction, x0=x0, until="rest"))
    assert rest.status is sa.Status.REST and rest.x_end == x0, rest.message
    scene = sa.Scene(profile, zone, friction=friction, x0=x0, periods=26)
    exact = sa.simulate(scene)
    assert exact.x_end == x0 and exact.stats["events"] == 0
    assert sa.simulate(scene, method="ivp", rtol=1e-12, atol=1e-14).x_end == x0
    assert sa.simulate(scene, method="moreau", steps_per_period=2000).x_end == x0


@pytest.mark.parametrize("zone", [False, True], ids=["uniform", "zone"])
def test_a_stuck_mass_at_the_tie_stays_stuck(zone):
    """The tie r mu_bar = max|y''| (decide_mode: stick while |y''| <= r mu_bar): on a uniform surface
    with r = max(y2, y3), and in a zone's high-friction region with c_mu = 2 and r = max(y2, y3) / 2
    (exact), a mass at rest stays at rest for 10 periods from every phase, for 100 profiles with
    ramps of 1e-10 ... 1e-6 dt: no event, x unchanged.  y'' never passes its levels."""
    for k, p in enumerate(tiny_ramp_profiles(100, seed=4)):
        top = max(p.y2, p.y3)
        surface = sa.StopZone(-1.0, 0.5, 2.0) if zone else sa.Uniform()
        friction = FrictionLaw("static_kinetic", top / 2.0 if zone else top)
        traj = sa.simulate(sa.Scene(p, surface, friction=friction, x0=0.0, phase=(k % 10) / 10, periods=10))
        assert traj.x_end == 0.0 and traj.stats["events"] == 0, p


def test_ramps_below_the_rounding_of_their_break_times_are_refused():
    """A ramp shorter than 2^-48 dt (MIN_RAMP_FRACTION: its ends t -+ ramp / 2 are floats rounded by
    up to eps dt / 2) is refused with a ValueError naming ramp and the smallest allowed value, as is
    a jerk that makes one (or a ramp of dt or more), before any work and without a numpy warning;
    so is a design spec's actuator.ramp below 2^-48 of its longest period, and a scene file's ramp.
    The paper's jump is ThreePhaseProfile (ramp 0 in a scene file)."""
    fig18 = dict(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    smallest = MIN_RAMP_FRACTION * fig18["dt"]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for ramp in (1e-300, 1e-17 * fig18["dt"], 0.99 * smallest, fig18["dt"], 1e300):
            with pytest.raises(ValueError, match=f"ramp must lie in \\[{smallest!r}, 1.05\\)"):
                FiniteJerkProfile(**fig18, ramp=ramp)
        for jerk in (1e-300, 1.0, 1e300, 1.01 * 0.9 / smallest):
            with pytest.raises(ValueError, match="jerk must lie in .*2.9523809523809526, 2412642657"):
                FiniteJerkProfile(**fig18, jerk=jerk)
    with pytest.raises(ValueError, match="actuator.ramp must be at least 2"):
        DesignSpec(mu=0.2, mu_uncertainty=0.05, c_mu=(2.5, 2.5), width=2e-3, max_stroke=1e-3, max_acceleration=6.0,
                   period=(0.08, 0.08), distance=5e-3, tolerance=150e-6, ramp=1e-300)
    with pytest.raises(SceneError, match="ramp must lie in"):
        scene_from_dict({"profile": {"kind": "three_phase", **fig18, "ramp": 1e-300}, "horizon": {"periods": 3}})


@pytest.mark.parametrize("surface", [sa.Uniform(), sa.StopZone(0.05, 0.05, 2.5)], ids=["uniform", "zone"])
def test_the_shortest_ramp_runs_as_the_paper_jump(surface):
    """At the shortest ramp allowed (2^-48 dt) the exact solver runs 10 periods of Fig. 18's
    setting in a few events (no stall) and ends where the paper's profile does to 1e-13
    (measured 4.6e-15 uniform, 0 on the zone)."""
    fig18 = dict(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    paper = sa.simulate(sa.Scene(sa.ThreePhaseProfile(**fig18), surface, periods=10))
    traj = sa.simulate(sa.Scene(FiniteJerkProfile(**fig18, ramp=MIN_RAMP_FRACTION * fig18["dt"]), surface,
                                periods=10), max_events=1000)
    assert traj.status is sa.Status.HORIZON, traj.message
    assert abs(traj.x_end - paper.x_end) <= 1e-13


def test_a_piecewise_linear_profile_with_jumps_is_the_paper_profile():
    """y'' may jump at the breaks of a PiecewiseLinearProfile: the paper's three-phase profile written
    with zero jerks is run by the smooth stepper on a uniform surface as by the piecewise-constant one,
    from 12 starts (x0, v0, phase), 10 periods, ends within 1e-12 (measured <= 2e-15).  A stuck mass
    slips at the break where |y''| jumps past r mu_bar: before, Brent's method converged to the near
    side of the jump, where the slip ended at once and stuck again, with no end."""
    paper = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
    jumps = PiecewiseLinearProfile(paper.breaks, paper.accels, np.zeros(3), paper.y_ini, paper.yd_ini)
    rng = np.random.default_rng(5)
    for _ in range(12):
        start = dict(x0=rng.uniform(-0.1, 0.1), v0=rng.choice([0.0, rng.uniform(-0.3, 0.3)]), phase=rng.uniform(0, 1))
        a = sa.simulate(sa.Scene(paper, periods=10, **start))
        b = sa.simulate(sa.Scene(jumps, periods=10, **start), max_events=10_000)
        assert b.status is sa.Status.HORIZON, b.message
        assert abs(a.x_end - b.x_end) <= 1e-12, start
