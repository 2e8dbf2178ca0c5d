"""The planar study (docs/explanation/planar-alignment.md; the paper's Sect. 8, recommendation 4): the drift v_bar
of a point part under a planar table motion, its limits of low and high acceleration, and where drifting parts
stop at a strip and at a corner of two strips; the stage's result file, figures and recording.

The strips are the paper's stop zone along their normal (eqs. 7-9) with its Sect. 7 setting, w = 0.05 and
c_mu = 2.5, and the three-phase motion is the Fig. 18 profile (dt = 1.05, dy = 0.084, y2'' = 2.2, y3'' = 0.9), so
x_stick_min - x_mu = w (max|Y''| - 1) / (c_mu - 1) = 0.04 along x (eq. 41).
"""

import math

import numpy as np
import pytest
from test_figures import assert_data_matches

import selfalign as sa
from selfalign.analysis.planar_alignment import (
    AT_LIMIT_WIDTHS,
    corner_alignment,
    entry_starts,
    line_alignment,
    stick_depth,
    strip_at,
)
from selfalign.analysis.planar_drift import (
    acceleration_limit,
    harmonic_orbit,
    high_acceleration_drift,
    power_fit,
    steady_drift,
    three_phase_pair,
)
from selfalign.analysis.steady_state import steady_state
from selfalign.io.hdf5 import read_dataset_attrs, read_h5, reproducible_bytes, write_h5
from selfalign.io.recording import Boxes, Recording, read_boxes, read_lines, write_recording
from selfalign.model.planar import PlanarProfile
from selfalign.plots.planar import alignment_figure, drift_figure
from selfalign.plots.style import LINE_COLORS, SPECIAL, print_check
from selfalign.stages.planar import planar_recording, planar_results

FIG18 = (1.05, 0.084, 2.2, 0.9)
W, C_MU = 0.05, 2.5
#: The exact solvers reproduce closed forms to rounding; the steady state is declared when the period-boundary
#: velocity repeats within tol = 1e-10, so a v_bar carries at most tol / (1 - rho) of the transient (rho the
#: contraction per period, at most 0.9 for these motions): 1e-8 leaves room for both.
STEADY = 1e-8

#: A shrunk stage (the workflow's config is larger): every group, a few runs each.
SMALL = {"method": "exact", "solver_options": {}, "tol": 1e-10, "max_periods": 5000,
         "three_phase": dict(zip(("dt", "dy", "y2", "y3"), FIG18)), "offsets": 2, "ratios": [0.0, 0.5],
         "harmonic": {"dt": 1.0, "a": 0.05, "second": 0.3},
         "harmonic_ratios": [0.0, 0.5], "symmetric": {"a": 0.05, "ratios": [1.0], "angle": 0.5},
         "low_scales": [0.4],
         "limit": {"scales": [8.0, 16.0], "three_phase": {"dt": 1.0, "dy": 0.064, "y2": 3.0, "y3": 1.5,
                                                          "ratio": 0.5, "offset": 0.3},
                   "harmonic": {"ratio": 0.4, "offset": 0.25}},
         "alignment": {"w": W, "c_mu": C_MU, "planar": {"ratio": 0.4, "offset": 0.5}, "angles": [0.0, 40.0],
                       "distance": 0.1, "starts": 2, "lateral": [0.0, 0.05], "max_periods": 400,
                       "corner": {"half_angle": 45.0, "starts": 1, "lateral": [-0.1, 0.1]},
                       "example": {"angle": 40.0, "periods": 60}}}


def pair(ratio, offset, scale=1.0):
    return three_phase_pair(*FIG18, ratio=ratio, offset=offset, scale=scale)


@pytest.fixture(scope="module")
def stage():
    """The shrunk stage's groups (planar_results)."""
    return planar_results(SMALL)


def test_low_acceleration_sticks_exactly():
    """Hypothesis (docs page, "Low acceleration"): below max|Y''| = 1 the disc of friction holds a part at rest,
    v = 0 solves the inclusion for every t, so v_bar = 0 exactly and the first period is already steady."""
    profile = pair(0.5, 0.3, scale=0.4)
    assert profile.max_abs_acceleration <= 1.0
    drift = steady_drift(profile)
    assert drift.v_bar.tolist() == [0.0, 0.0] and drift.periods == 1 and drift.converged


@pytest.mark.parametrize(("a", "b", "angle"), [(0.1, 0.1, 0.0), (0.1, 0.04, 0.0), (0.1, 0.0, 0.5)])
def test_orbits_with_half_period_symmetry_never_drift(a, b, angle):
    """Hypothesis (docs page, "Orbits that never drift"): for Y(t + dt/2) = -Y(t) (a circle, an ellipse, a line at
    an angle) -x(t + dt/2) is a motion too, so the unique steady velocity gives v_bar = -v_bar = 0, at an
    acceleration (max|Y''| = 3.9) where the part slips; |v_bar| <= STEADY."""
    profile = harmonic_orbit(1.0, a, b, angle=angle)
    assert profile.max_abs_acceleration > 3.0
    assert np.hypot(*steady_drift(profile).v_bar) <= STEADY


@pytest.mark.parametrize("ratio", [0.5, 1.0])
def test_pair_in_phase_is_the_one_dimensional_steady_state(ratio):
    """Hypothesis (the 1-D reduction, Sect. 5.1): two three-phase profiles of one shape in phase are the 1-D motion
    sqrt(1 + r^2) P along (1, r); v_bar is the closed-form vbar of that profile along (1, r), to STEADY."""
    k = math.hypot(1.0, ratio)
    reference = steady_state(sa.ThreePhaseProfile(FIG18[0], k * FIG18[1], k * FIG18[2], k * FIG18[3])).vbar
    np.testing.assert_allclose(steady_drift(pair(ratio, 0.0)).v_bar, reference * np.array([1.0, ratio]) / k,
                               rtol=0, atol=STEADY)


def test_harmonic_orbit_half_a_period_later_is_mirrored():
    """Hypothesis: delaying the y motion b sin(w t) by half a period more turns it into -b sin(w t), the mirror
    image y -> -y of the table motion, so v_bar is mirrored: (v_x, v_y) -> (v_x, -v_y), to STEADY."""
    first = steady_drift(harmonic_orbit(1.0, 0.05, 0.025, offset=0.1, second=0.3)).v_bar
    second = steady_drift(harmonic_orbit(1.0, 0.05, 0.025, offset=0.6, second=0.3)).v_bar
    assert abs(first[1]) > 1e-3
    np.testing.assert_allclose(second, [first[0], -first[1]], rtol=0, atol=STEADY)


def test_median_of_velocities_limits():
    """Hypothesis (docs page, "High acceleration"): the limit is the geometric median of Y'(t): zero for a circle
    (to 1e-12 of its speed 0.63); for a motion along a line the median of y'(t) along it (the Fig. 18 profile at
    0.7 rad: the median of a million samples, to 1e-5, the change of y' over a sample of the 8192), which is the
    dwell velocity y'_ini when the dwell lasts more than half the period (t1 = 0.53 of dt = 1; to 1e-9)."""
    assert np.hypot(*high_acceleration_drift(harmonic_orbit(1.0, 0.1, 0.1))) <= 1e-12
    fig18 = sa.ThreePhaseProfile(*FIG18)
    t = (np.arange(10**6) + 0.5) * fig18.dt / 10**6
    along = high_acceleration_drift(PlanarProfile(x=fig18, angle=0.7))
    np.testing.assert_allclose(along, np.median(fig18.velocity(t)) * np.array([math.cos(0.7), math.sin(0.7)]),
                               rtol=0, atol=1e-5)
    dwell = sa.ThreePhaseProfile(1.0, 0.064, 3.0, 1.5)
    assert dwell.t1 > 0.5
    np.testing.assert_allclose(high_acceleration_drift(PlanarProfile(x=dwell)), [dwell.yd_ini, 0.0], rtol=0, atol=1e-9)


@pytest.mark.parametrize("scale", [64.0, 256.0])
def test_dwell_limit_has_the_second_term_of_the_derivation(scale):
    """Hypothesis (docs page, "The next term for a long dwell"): for a 1-D three-phase motion with t1 > dt/2 scaled
    by lambda, vbar = lambda y'_ini - (dt - t1)^2 / dt + O(1/lambda); the closed form of Sect. 5.1 meets it within
    0.5 / lambda (measured: 0.29 / lambda)."""
    base = sa.ThreePhaseProfile(1.0, 0.064, 3.0, 1.5)
    vbar = steady_state(sa.ThreePhaseProfile(1.0, scale * 0.064, scale * 3.0, scale * 1.5)).vbar
    two_terms = scale * base.yd_ini - (base.dt - base.t1) ** 2 / base.dt
    assert abs(vbar - two_terms) <= 0.5 / scale


@pytest.mark.parametrize("family", ["three_phase", "harmonic"])
def test_high_acceleration_error_falls_as_one_over_acceleration(family):
    """Hypothesis (docs page, "High acceleration"): v_bar = lambda c + O(1) for the motion scaled by lambda, so
    the error over the table's peak speed falls as 1 / max|Y''|: the exponent between scales 16 and 32 lies in
    [-1.15, -0.85] and error * max|Y''| in [0.1, 2] (measured: 0.65 and 0.87)."""
    if family == "three_phase":
        profiles = [three_phase_pair(1.0, 0.064, 3.0, 1.5, ratio=0.5, offset=0.3, scale=s) for s in (16.0, 32.0)]
    else:
        profiles = [harmonic_orbit(1.0, 0.05 * s, 0.02 * s, offset=0.25, second=0.3) for s in (16.0, 32.0)]
    fit = acceleration_limit(profiles)
    assert -1.15 <= fit.slope <= -0.85
    assert np.all((0.1 <= fit.error * fit.max_acceleration) & (fit.error * fit.max_acceleration <= 2.0))


def test_power_fit_recovers_a_power_law():
    """Hypothesis: the least-squares line in log-log recovers y = 3 x^-1.5 exactly (to 1e-12)."""
    x = np.array([2.0, 5.0, 11.0])
    slope, constant = power_fit(x, 3.0 * x**-1.5)
    assert abs(slope + 1.5) <= 1e-12 and abs(constant - 3.0) <= 1e-12


def test_strip_along_the_drift_is_the_one_dimensional_zone():
    """Hypothesis (docs page, "A motion along the drift"): for a table motion along x the part moves on its line,
    where the strip at angle theta is the 1-D stop zone of width w / cos(theta) starting where the line meets the
    edge; each entry ends where the 1-D exact solver ends on that zone (to 1e-9 of the position), and all of them
    at depth x_stick_min along n (accumulation, Sect. 7.3)."""
    theta = math.radians(50.0)
    profile = pair(0.0, 0.0)
    result = line_alignment(profile, w=W, c_mu=C_MU, angles=[theta], distance=0.1, offsets=[0.0, 0.5],
                            lateral=[0.03])
    normal = result.normals[0]
    for start, end in zip(result.start[0], result.x_end[0]):
        assert start[1] == pytest.approx(end[1], abs=1e-12)                # the motion stays on its line y = const
        edge = (0.0 - normal[1] * start[1]) / normal[0]
        alone = sa.simulate(sa.Scene(profile.x, sa.StopZone(x_mu=edge, w=W / normal[0], c_mu=C_MU), x0=start[0],
                                     until="rest", max_periods=400))
        assert abs(end[0] - alone.x_end) <= 1e-9
    assert np.all(np.abs(result.depth - 0.04) <= AT_LIMIT_WIDTHS * W)


def test_oblique_strip_accumulates_along_n_but_not_along_the_strip():
    """Hypothesis (docs page, "To a line"): for the planar motion (the pair at ratio 0.4, phase 0.5) every entry at
    40 degrees ends at depth x_stick_min along n (within AT_LIMIT_WIDTHS w; Delta x_d along n 0), while along the
    strip each entry line keeps its own position: Delta x_d along the strip is at least the entry lines' half
    spread 0.025."""
    result = line_alignment(pair(0.4, 0.5), w=W, c_mu=C_MU, angles=[math.radians(40.0)], distance=0.1,
                            offsets=[0.0, 0.5], lateral=[0.0, 0.05])
    assert result.at_limit.tolist() == [1.0] and result.dx_d_normal[0] <= AT_LIMIT_WIDTHS * W
    assert result.dx_d_along[0] >= 0.025


def test_corner_stops_each_part_at_the_first_strip():
    """Hypothesis (docs page, "To a point"): friction is the larger of the two strips', so a part stops for good
    at x_stick_min of the first strip it reaches, wherever along it: entries from either side of the drift line
    end on different strips, far apart from the corner point (more than 2 w)."""
    corner = corner_alignment(pair(0.0, 0.0), w=W, c_mu=C_MU, half_angle=math.radians(45.0), distance=0.1,
                              offsets=[0.0], lateral=[-0.1, 0.1])
    assert sorted(corner.first.tolist()) == [0, 1] and corner.entries.stopped.all()
    depths = corner.entries.x_end @ np.array([s.normal for s in corner.strips]).T
    np.testing.assert_allclose(depths[np.arange(2), corner.first], 0.04, rtol=0, atol=AT_LIMIT_WIDTHS * W)
    assert corner.spread_radius > 2 * W


def test_stick_depth_is_eq_41():
    """Hypothesis: x_stick_min - x_mu = w (max|Y''| - 1) / (c_mu - 1) (eq. 41): 0.04 on the Fig. 18 setting."""
    assert stick_depth(2.2, W, C_MU) == pytest.approx(0.04, abs=1e-15)


def test_entry_starts_span_one_period_of_advance():
    """Hypothesis: the starts lie distance + s advance behind the edge along the drift, per entry line."""
    starts = entry_starts([1.0, 0.0], [math.sqrt(0.5), math.sqrt(0.5)], 0.1, distance=0.2, offsets=[0.0, 0.5],
                          lateral=[0.0])
    np.testing.assert_allclose(starts, [[-0.2, 0.0], [-0.25, 0.0]], rtol=0, atol=1e-15)


@pytest.mark.parametrize(("call", "error", "message"), [
    (lambda: steady_drift(sa.ThreePhaseProfile(*FIG18)), TypeError, "PlanarProfile"),
    (lambda: steady_drift(pair(0.0, 0.0), method="euler"), ValueError, "method"),
    (lambda: steady_drift(pair(0.0, 0.0), tol=0.0), ValueError, "tol"),
    (lambda: high_acceleration_drift(pair(0.0, 0.0), samples=4), ValueError, "samples"),
    (lambda: acceleration_limit([pair(0.0, 0.0)]), ValueError, "at least two"),
    (lambda: three_phase_pair(*FIG18, ratio=-1.0, offset=0.0), ValueError, "ratio"),
    (lambda: three_phase_pair(*FIG18, ratio=1.0, offset=1.0), ValueError, "offset"),
    (lambda: harmonic_orbit(1.0, 0.1, -0.1), ValueError, "b must"),
    (lambda: power_fit([1.0], [1.0]), ValueError, "power_fit"),
    (lambda: stick_depth(3.0, W, C_MU), ValueError, "c_mu"),
    (lambda: strip_at([0.0, 0.0], 0.3, x_mu=0.0, w=W, c_mu=C_MU), ValueError, "direction"),
    (lambda: line_alignment(pair(0.0, 0.0), w=W, c_mu=C_MU, angles=[1.6], distance=0.1, offsets=[0.0],
                            lateral=[0.0]), ValueError, "angles"),
    (lambda: line_alignment(harmonic_orbit(1.0, 0.03, 0.03), w=W, c_mu=C_MU, angles=[0.0], distance=0.1,
                            offsets=[0.0], lateral=[0.0]), ValueError, "does not drift"),
    (lambda: corner_alignment(pair(0.0, 0.0), w=W, c_mu=C_MU, half_angle=0.0, distance=0.1, offsets=[0.0],
                              lateral=[0.0]), ValueError, "half_angle"),
    (lambda: Recording(np.arange(2.0), {}, lines={"a": np.zeros((1, 1, 2))}), ValueError, "lines"),
    (lambda: Recording(np.arange(2.0), {}, boxes={"a": Boxes(np.zeros((2, 1, 3)), np.ones(1), 1.0)}), ValueError,
     "boxes"),
])
def test_bad_input_is_refused_by_name(call, error, message):
    """Hypothesis: bad input is refused before any simulation, with a message naming the argument."""
    with pytest.raises(error, match=message):
        call()


def test_stage_file_is_documented_and_reproducible(stage, tmp_path):
    """Hypothesis: every dataset of results/planar/planar.h5 carries units and a description, and two writes of
    the same settings give the same bytes (no measured value in this stage)."""
    datasets, attrs, groups = stage
    paths = [write_h5(tmp_path / f"planar_{i}.h5", datasets, attrs, groups, config=SMALL) for i in range(2)]
    assert reproducible_bytes(paths[0]) == reproducible_bytes(paths[1]) == paths[0].read_bytes()
    documented = read_dataset_attrs(paths[0])
    assert documented and all(a.get("units") and a.get("description") for a in documented.values())
    np.testing.assert_array_equal(read_h5(paths[0])["groups"]["line_along"]["datasets"]["x_end"],
                                  groups["line_along"]["datasets"]["x_end"])


def test_stage_numbers_answer_the_questions(stage):
    """Hypothesis (docs page): in the shrunk stage the symmetric orbit and the motion below max|Y''| = 1 do not
    drift (to STEADY and exactly), the oblique strip (40 degrees) accumulates every entry along n for both motions,
    and the corner's ends lie more than 2 w from the corner point."""
    g = stage[2]
    assert np.abs(g["symmetric"]["datasets"]["v_bar"]).max() <= STEADY
    assert np.all(g["low_acceleration"]["datasets"]["v_bar"] == 0.0)
    assert g["line_along"]["datasets"]["at_limit"][1] == 1.0 and g["line_planar"]["datasets"]["at_limit"][1] == 1.0
    assert g["corner"]["datasets"]["spread_radius"] > 2 * W


def test_figures_and_recording_show_the_result(stage, tmp_path):
    """Hypothesis: the figures draw the result's numbers (panel (a) of the drift figure colours |v_bar| of the map,
    to 1e-12) and the recording holds the example paths as boxes in the plane over the strips' edges."""
    result = {"groups": stage[2]}
    fig = drift_figure(result)
    v = stage[2]["drift_three_phase"]["datasets"]["v_bar"]
    np.testing.assert_allclose(fig.axes[0].collections[0].get_array().ravel(), np.hypot(*v.T).ravel(), atol=1e-12)
    assert len(alignment_figure(result).axes) == 4
    path = write_recording(tmp_path / "planar.rrd", planar_recording(result))
    index, centres, _ = read_boxes(path)["line/part"]
    x = stage[2]["example_line"]["datasets"]["x"]
    np.testing.assert_allclose(centres[: len(x), 0], x, rtol=0, atol=1e-6)   # stored as float32
    assert len(read_lines(path)["corner/strips"]) == 4


@pytest.mark.parametrize("name", ["planar_drift", "planar_alignment"])
def test_figures_match_their_references(repo, stage, update_figure_refs, name):
    """Hypothesis: the figures of the shrunk stage draw the numbers of tests/figure_refs/<name>.json (the
    figure test's tolerances), so a change of the study or of the drawing shows."""
    fig = (drift_figure if name == "planar_drift" else alignment_figure)({"groups": stage[2]})
    assert_data_matches(repo, fig, name, update_figure_refs)


@pytest.mark.parametrize("name", ["planar_drift", "planar_alignment"])
def test_figures_meet_the_print_standard(stage, name):
    """Hypothesis (docs/explanation/figures.md): the planar figures print two columns wide (174 mm), their
    panels lettered a, b, c (d), with no text below 7 pt, no parameter titles and no ASCII mathematics, and
    every line in a colour of the Okabe-Ito palette, black or grey."""
    from matplotlib.colors import to_hex

    fig = (drift_figure if name == "planar_drift" else alignment_figure)({"groups": stage[2]})
    assert print_check(fig) == []
    assert round(fig.get_figwidth() * 25.4) == 174
    letters = [ax.get_title(loc="left") for ax in fig.axes if ax.get_title(loc="left")]
    assert letters == (["a", "b", "c"] if name == "planar_drift" else ["a", "b", "c", "d"])
    palette = {c.lower() for c in LINE_COLORS} | {"#000000", "#666666"}
    assert {to_hex(line.get_color()) for ax in fig.axes for line in ax.lines} <= palette


def test_angles_where_every_entry_accumulates_are_marked(stage):
    """Hypothesis (docs page, "To a line"): panel (b) of the alignment figure draws Delta x_d along n in the
    encoding "dx_zero" of the figure standard exactly at the angles where every entry accumulates at
    x_stick_min (at_limit 1), for each motion, and not where only some entries do (at_limit 1/2)."""
    groups = dict(stage[2])
    planar = groups["line_planar"]
    groups["line_planar"] = {**planar, "datasets": {**planar["datasets"], "at_limit": np.array([0.5, 1.0])}}
    fig = alignment_figure({"groups": groups})
    marked = [line for line in fig.axes[1].lines if line.get_markerfacecolor() == SPECIAL["dx_zero"]["facecolor"]]
    assert len(marked) == 2
    along = groups["line_along"]["datasets"]
    np.testing.assert_allclose(marked[0].get_xdata(), np.degrees(along["angle"][along["at_limit"] == 1.0]),
                               rtol=0, atol=1e-12)
    np.testing.assert_allclose(marked[1].get_xdata(), [40.0], rtol=0, atol=1e-12)
