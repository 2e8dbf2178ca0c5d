"""The planar model (docs/explanation/planar-model.md): PlanarProfile, Strip, planar scenes and scene files, and
Moreau time-stepping with the friction disc (selfalign.solvers.planar_moreau)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import selfalign as sa
from selfalign.model.planar import planar_coefficient, rotation, strip_rows

FIG18 = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
ZONE = dict(x_mu=0.5, w=0.05, c_mu=2.5)


def test_planar_profile_is_the_rotated_pair_of_its_components():
    """Y(t) = R(angle) (P_x(t), P_y(t - offset dt)) (docs/explanation/planar-model.md), for position, velocity
    and acceleration, at random times."""
    fourier = sa.FourierProfile(1.05, [0.02, 0.01], [0.0, 0.005])
    planar = sa.PlanarProfile(FIG18, fourier, offset=0.3, angle=0.4)
    t = np.random.default_rng(1).uniform(-3.0, 3.0, 50)
    for what in ("position", "velocity", "acceleration"):
        pair = np.stack([getattr(FIG18, what)(t), getattr(fourier, what)(t - 0.3 * 1.05)], axis=-1)
        np.testing.assert_allclose(getattr(planar, what)(t), pair @ rotation(0.4).T, rtol=0, atol=1e-13)


def test_largest_acceleration_is_exact_for_pieces_and_refined_for_fourier():
    """max|Y''| is a piece end's for piecewise-constant and piecewise-linear components (|Y''| is convex on a
    piece) and a refined grid maximum for Fourier ones: it bounds a fine sampling from above and is reached by it
    to 1e-9 (a circle of radius a (2 pi / dt)^2 is exact)."""
    jerk = sa.FiniteJerkProfile(1.05, 0.084, 2.2, 0.9, ramp=0.05)
    t = np.linspace(0.0, 1.05, 200_001)
    for planar in (sa.PlanarProfile(FIG18, FIG18, offset=0.25), sa.PlanarProfile(FIG18, jerk, offset=0.6, angle=1.0),
                   sa.PlanarProfile(sa.FourierProfile(1.05, [0.02, 0.003], [0.0, 0.0]),
                                    sa.FourierProfile(1.05, [0.0, 0.0], [0.01, 0.004]), offset=0.1)):
        sampled = float(np.max(np.hypot(*np.moveaxis(planar.acceleration(t), -1, 0))))
        assert planar.max_abs_acceleration >= sampled - 1e-12
        assert planar.max_abs_acceleration <= sampled * (1 + 1e-9)
    circle = sa.PlanarProfile(sa.FourierProfile(1.0, [0.1], [0.0]), sa.FourierProfile(1.0, [0.0], [0.1]))
    assert circle.max_abs_acceleration == pytest.approx(0.1 * (2 * math.pi) ** 2, rel=1e-14)


def test_pieces_hold_the_merged_constant_accelerations():
    """pieces(): the merged pieces of both components, Y'' constant on each and equal to the profile's
    acceleration inside it; the y component's period start (a jump of the three-phase profile) is a switch."""
    planar = sa.PlanarProfile(FIG18, FIG18, offset=0.25, angle=0.3)
    starts, accels = planar.pieces()
    assert starts[0] == 0.0 and np.all(np.diff(starts) > 0)
    assert np.any(np.isclose(starts, 0.25 * 1.05, rtol=0, atol=1e-15))
    ends = np.append(starts[1:], 1.05)
    for a, b, acc in zip(starts, ends, accels):
        inside = np.linspace(a, b, 7)[1:-1]
        np.testing.assert_allclose(planar.acceleration(inside), np.tile(acc, (5, 1)), rtol=0, atol=1e-15)
    with pytest.raises(ValueError, match="not all piecewise constant"):
        sa.PlanarProfile(sa.FourierProfile(1.0, [0.1], [0.0])).pieces()


@pytest.mark.parametrize("call, error, match", [
    (lambda: sa.Strip((0.0, 0.0), 0.5, 0.05, 2.5), ValueError, "normal must be a unit vector.*zero normal"),
    (lambda: sa.Strip((1.0, 1e-5), 0.5, 0.05, 2.5), ValueError, "normal must be a unit vector"),
    (lambda: sa.Strip((1.0,), 0.5, 0.05, 2.5), TypeError, "normal must be a pair"),
    (lambda: sa.Strip((1.0, math.nan), 0.5, 0.05, 2.5), ValueError, r"normal\[1\] must be a finite number"),
    (lambda: sa.Strip((1.0, 0.0), 0.5, -0.05, 2.5), ValueError, "w must be > 0"),
    (lambda: sa.Strip((1.0, 0.0), 0.5, 0.05, 0.5), ValueError, "c_mu must be >= 1"),
    (lambda: sa.PlanarProfile(FIG18, sa.ThreePhaseProfile(1.1, 0.084, 2.2, 0.9)), ValueError, "y.dt = 1.1 differs"),
    (lambda: sa.PlanarProfile(FIG18, offset=1.0), ValueError, r"offset must lie in \[0, 1\)"),
    (lambda: sa.PlanarProfile(FIG18, angle=math.inf), ValueError, "angle must be a finite number"),
    (lambda: sa.PlanarProfile("three_phase"), TypeError, "x must be a selfalign profile"),
    (lambda: sa.Scene(sa.PlanarProfile(FIG18), periods=1, x0=0.1), TypeError, "x0 of a planar scene must be a pair"),
    (lambda: sa.Scene(sa.PlanarProfile(FIG18), periods=1, v0=(0.0, math.inf)), sa.SceneError,
     r"v0\[1\] must be a finite number"),
    (lambda: sa.Scene(sa.PlanarProfile(FIG18), sa.StopZone(**ZONE), periods=1), sa.SceneError,
     "a planar scene takes strips, not a StopZone"),
    (lambda: sa.Scene(FIG18, sa.Strip((1, 0), **ZONE), periods=1), TypeError, "strips need a PlanarProfile"),
    (lambda: sa.Scene(sa.PlanarProfile(FIG18), [sa.Strip((1, 0), **ZONE), "zone"], periods=1), TypeError,
     "surface of a planar scene must be"),
    (lambda: sa.Scene(sa.PlanarProfile(FIG18), friction=sa.FrictionLaw("stribeck", 1.5, 0.1), periods=1),
     sa.SceneError, "stribeck is not simulated in the plane"),
    (lambda: sa.Scene(sa.PlanarProfile(FIG18), periods=1, record=sa.Record(series=("y",))), sa.SceneError,
     "a planar scene records the series"),
])
def test_bad_planar_input_is_refused_naming_the_parameter(call, error, match):
    """Bad input is refused before any work, naming the parameter and what is allowed: zero or non-unit normals,
    profiles of different periods, non-finite values, and what a planar scene cannot have."""
    with pytest.raises(error, match=match):
        call()


def test_strips_combine_by_the_largest_coefficient():
    """mu_bar(x) = max_k mu_bar of eqs. 7-9 at n_k . x - x_mu,k (1 without strips); a strip with n = (1, 0) is the
    1-D StopZone along the first axis."""
    strips = (sa.Strip((1.0, 0.0), 0.5, 0.05, 2.5), sa.Strip((0.0, 1.0), 0.2, 0.1, 1.5))
    rows = strip_rows(strips)
    zone = sa.StopZone(0.5, 0.05, 2.5)
    for x, y in np.random.default_rng(2).uniform(0.0, 0.7, (200, 2)):
        expected = max(float(zone.coefficient(x)), float(sa.StopZone(0.2, 0.1, 1.5).coefficient(y)))
        assert planar_coefficient(x, y, rows) == expected
    assert planar_coefficient(3.0, -4.0, strip_rows(())) == 1.0


def test_planar_scene_files_round_trip_and_refuse_bad_keys(tmp_path):
    """A planar scene file loads to the scene it describes and to_dict() writes it back (docs/explanation/
    planar-model.md, "Scenes"); a strip without w takes body.width; a key a planar scene cannot use is refused."""
    text = """
name: planar_file
profile:
  kind: planar
  x: {kind: three_phase, dt: 1.05, dy: 0.084, y2: 2.2, y3: 0.9}
  y: {kind: fourier, dt: 1.05, cos_coeffs: [0.01], sin_coeffs: [0.0]}
  offset: 0.25
  angle: 0.5
surface:
  kind: strips
  strips:
    - {normal: [1, 0], x_mu: 0.5, c_mu: 2.5}
    - {normal: [0.6, 0.8], x_mu: 0.3, w: 0.1, c_mu: 1.5}
body: {width: 0.05}
start: {x0: [0.1, 0.2], v0: [0.0, -0.1], phase: 0.5}
horizon: {periods: 3}
solver: {method: moreau, options: {steps_per_period: 500}}
"""
    path = tmp_path / "planar.yaml"
    path.write_text(text)
    scene = sa.load_scene(path)
    assert scene.planar and scene.x0 == (0.1, 0.2) and scene.v0 == (0.0, -0.1)
    assert scene.strips == (sa.Strip((1, 0), 0.5, 0.05, 2.5), sa.Strip((0.6, 0.8), 0.3, 0.1, 1.5))
    assert scene.profile == sa.PlanarProfile(FIG18, sa.FourierProfile(1.05, [0.01], [0.0]), offset=0.25, angle=0.5)
    assert sa.scene_from_dict(scene.to_dict()) == scene
    for old, new, message in (("x0: [0.1, 0.2]", "x0: [0.1, 0.2, 0.3]", "start.x0"),
                              ("normal: [1, 0]", "normal: [2, 0]", r"surface.strips\[0\]: normal must be a unit"),
                              ("steps_per_period: 500", "iteration: exact", "do nothing for a planar scene"),
                              ("offset: 0.25", "offset: 1.5", "offset")):
        path.write_text(text.replace(old, new))
        with pytest.raises(sa.SceneError, match=message):
            sa.load_scene(path)


def _moreau(scene, steps=1000):
    return sa.simulate(scene, "moreau", steps_per_period=steps)


@pytest.mark.parametrize("surface", ["uniform", "zone"])
def test_moreau_along_one_axis_is_the_1d_moreau(surface):
    """A table moving along the first axis and a strip with n = (1, 0) reproduce the 1-D Moreau run of the paper's
    Fig. 18 setting (Sect. 4.1): the disc projection of a vector along one axis is the 1-D soft threshold, so y
    stays exactly 0 and x agrees to 1e-12 (1-D positions are kept relative to an origin, so a last rounding
    differs); the outcome, rest at x_stick,min of eq. 41 on the zone, is the same."""
    one_d = sa.Scene(FIG18, sa.StopZone(**ZONE) if surface == "zone" else sa.Uniform(), x0=0.1,
                     **(dict(until="rest", max_periods=400) if surface == "zone" else dict(periods=40)))
    planar = sa.Scene(sa.PlanarProfile(FIG18), [sa.Strip((1.0, 0.0), **ZONE)] if surface == "zone" else sa.Uniform(),
                      x0=(0.1, 0.0), **(dict(until="rest", max_periods=400) if surface == "zone" else dict(periods=40)))
    a, b = _moreau(one_d), _moreau(planar)
    assert b.x_end[1] == 0.0 and b.v_end[1] == 0.0
    assert abs(a.x_end - b.x_end[0]) <= 1e-12 and abs(a.v_end - b.v_end[0]) <= 1e-12
    assert (a.reason, a.period_end) == (b.reason, b.period_end)
    if surface == "zone":
        assert b.reason is sa.Reason.REST


def test_moreau_is_isotropic():
    """Turning the table motion and the strips together by theta turns the trajectory (isotropic friction,
    docs/explanation/planar-model.md): end states agree to rounding, 1e-12 over 40 periods."""
    profile = sa.PlanarProfile(FIG18, FIG18, offset=0.25)
    strips = [sa.Strip((0.6, 0.8), 1.2, 0.05, 2.5)]
    base = _moreau(sa.Scene(profile, strips, x0=(0.1, -0.2), periods=40))
    for theta in (0.3, 2.0, -1.2):
        turned = _moreau(sa.Scene(profile.rotated(theta), [s.rotated(theta) for s in strips],
                                  x0=tuple(rotation(theta) @ [0.1, -0.2]), periods=40))
        np.testing.assert_allclose(turned.x_end, rotation(theta) @ base.x_end, rtol=0, atol=1e-12)
        np.testing.assert_allclose(turned.v_end, rotation(theta) @ base.v_end, rtol=0, atol=1e-12)


def test_a_strip_parallel_to_the_motion_never_stops_the_part():
    """A table moving along the first axis drives the part along it; a strip whose normal is perpendicular to the
    motion (n = (0, 1), the part starting outside it) is never reached, so the part walks on as on a uniform
    surface (the same end state, bit for bit)."""
    profile = sa.PlanarProfile(FIG18)
    free = _moreau(sa.Scene(profile, x0=(0.0, 0.0), periods=60))
    strip = _moreau(sa.Scene(profile, [sa.Strip((0.0, 1.0), 0.01, 0.05, 2.5)], x0=(0.0, 0.0), periods=60))
    np.testing.assert_array_equal(free.x_end, strip.x_end)
    assert strip.x_end[0] > 1.0


def test_moreau_converges_to_the_steady_drift_at_first_order():
    """Moreau's scheme is first order (Sect. 4.1): the end position after 10 periods of a diagonal three-phase
    motion converges with a fitted order in [0.8, 1.3] over h = dt/500 ... dt/8000 against dt/64000."""
    scene = sa.Scene(sa.PlanarProfile(FIG18, FIG18, offset=0.25), x0=(0.0, 0.0), periods=10)
    reference = _moreau(scene, 64_000).x_end
    steps = np.array([500, 1000, 2000, 4000, 8000])
    errors = [np.max(np.abs(_moreau(scene, n).x_end - reference)) for n in steps]
    slope = -np.polyfit(np.log(steps), np.log(errors), 1)[0]
    assert 0.8 <= slope <= 1.3, (slope, errors)


def test_moreau_planar_outcomes_and_counts():
    """A part stuck where r mu_bar >= max|Y''| is at rest for good (REST with until='rest'): under Coulomb friction
    with max|Y''| < 1, and under static/kinetic friction with 1 < max|Y''| <= r (the stick window is r h mu_bar);
    samples are (n, 2) series from the start state; a walking part counts one slip start per stick."""
    quiet = sa.PlanarProfile(sa.ThreePhaseProfile(dt=1.05, dy=0.02, y2=0.9, y3=0.5))
    rest = _moreau(sa.Scene(quiet, x0=(0.3, 0.4), until="rest", max_periods=10))
    assert rest.reason is sa.Reason.REST and tuple(rest.x_end) == (0.3, 0.4)
    held = sa.Scene(sa.PlanarProfile(FIG18), friction=sa.FrictionLaw("static_kinetic", 2.5), x0=(0.0, 0.0),
                    until="rest", max_periods=10, record=sa.Record(series=("x", "v", "mode"), samples_per_period=8))
    traj = _moreau(held)
    assert traj.reason is sa.Reason.REST and traj.x.shape[1] == 2 and np.all(traj.mode == 0)
    walk = _moreau(sa.Scene(sa.PlanarProfile(FIG18), x0=(0.0, 0.0), periods=5,
                            record=sa.Record(series=("x", "v", "mode"), samples_per_period=8)))
    assert walk.x.shape == (41, 2) and walk.t[0] == 0.0 and walk.t[-1] == pytest.approx(5 * 1.05, abs=1e-12)
    assert walk.info["sticks"] == walk.info["slips"] >= 5 and np.all(np.isfinite(walk.x))
