"""Stopping in the high-friction zone (Sect. 7): outcomes of steady-state entries,
positioning accuracy (eqs. 39-41), accumulation at x_stick_min and its speed."""

import numpy as np
import pytest

from selfalign import EventKind, Reason, Record, Scene, ThreePhaseProfile, simulate, simulate_batch
from selfalign.analysis.positioning import ACCUMULATE, REST, accumulation_speed, positioning, positioning_grid
from selfalign.analysis.stick_map import stick_map
from selfalign.solvers.outcomes import STATUS_CODES, Status

#: Status code of an undecided entry.
HORIZON = STATUS_CODES[Status.HORIZON]

#: Sect. 7.2: dy = 0.084, dt = 1, w = 0.05, c_mu = 2.5.
DT, DY, W, C_MU = 1.0, 0.084, 0.05, 2.5
#: A coarse version of the Fig. 17 grid (the figure uses 101 x 101 points on the same range).
COARSE = np.linspace(0.5, 2.5, 21)


def profile(y2, y3):
    return ThreePhaseProfile(DT, DY, y2, y3)


def test_fig16_upper_all_entries_accumulate():
    """Fig. 16 (upper), (y2'', y3'') = (2.3, 1.3): every steady-state entry ends at the same
    accumulation position x_stick_min (eq. 41), so Delta_x_d = 0 (Sect. 7.2)."""
    pos = positioning(profile(2.3, 1.3), w=W, c_mu=C_MU, n_entries=64)
    assert pos.frac_accumulate == 1.0 and pos.accumulation == "all"
    np.testing.assert_array_equal(pos.x_end, pos.x_stick_min)
    assert pos.x_stick_min - pos.x_mu == pytest.approx(W * (2.3 - 1) / (C_MU - 1), abs=1e-15)
    assert pos.dx_d == 0.0 and pos.x_d == pos.x_stick_min


def test_fig16_lower_entries_stop_at_different_positions():
    """Fig. 16 (lower), (1.8, 1.1): the end positions differ (no accumulation, every entry
    at rest for good beyond x_stick_min where mu_bar >= max|y''|); Delta_x_d > 5e-3.  The
    paper shows two entries; all 64 agree with it."""
    pos = positioning(profile(1.8, 1.1), w=W, c_mu=C_MU, n_entries=64)
    assert pos.frac_stop == 1.0 and pos.accumulation == "none"
    assert np.all(pos.x_end >= pos.x_stick_min)
    assert pos.dx_d > 5e-3
    assert pos.x_d == pytest.approx(pos.x_mu + 0.5 * (pos.overshoot_min + pos.overshoot_max), abs=1e-15)


def test_accumulating_entries_approach_x_stick_min():
    """Sect. 7.2: when accumulation occurs the mass ends at x_stick_min.  Followed for 40
    periods with the exact solver (no accumulation shortcut), the entries the batch
    classifies as ACCUMULATION increase monotonically in the zone and end within 1e-12 of
    x_stick_min, never beyond it (up to 1e-15 rounding of the last tiny slips); the entries
    at rest end beyond it (Fig. 18 setting)."""
    prof = ThreePhaseProfile(1.05, DY, 2.2, 0.9)
    pos = positioning(prof, w=W, c_mu=C_MU, n_entries=8)
    assert pos.accumulation == "some"
    for i in range(8):
        traj = simulate(Scene(prof, pos.zone, x0=float(pos.x0[i]), v0=pos.v0, periods=40,
                              record=Record(events=True)), method="exact")
        sticks = traj.events[traj.events["kind"] == EventKind.STICK]["x"]
        sticks = sticks[sticks >= pos.x_mu]
        if pos.status[i] == ACCUMULATE:
            assert np.all(np.diff(sticks) > 0) and np.all(sticks <= pos.x_stick_min + 1e-15)
            assert traj.x_end == pytest.approx(pos.x_stick_min, abs=1e-12)
        else:
            assert pos.status[i] == REST and traj.x_end > pos.x_stick_min
            assert traj.x_end == pytest.approx(pos.x_end[i], abs=1e-15)


def test_entries_cover_one_period_and_do_not_touch_the_zone_first():
    """Sect. 7.1: x_mu = Delta_x (max displacement in one period) and x0s in (-vbar dt, 0]
    keep every entry out of the zone for its whole first period; Delta_x = vbar dt for a
    monotone case-1 motion and > vbar dt for case 3 (it moves back in phase 3)."""
    for y2, y3, case in ((2.4, 0.95, 1), (2.3, 1.3, 3)):
        pos = positioning(profile(y2, y3), w=W, c_mu=C_MU, n_entries=16)
        assert pos.case == case
        assert np.all(pos.entry_time >= 1.0)
        assert np.all((pos.x0 <= 0) & (pos.x0 > -pos.vbar * DT))
        if case == 1:
            assert pos.dx_period == pytest.approx(pos.vbar * DT, rel=1e-12)
        else:
            assert pos.dx_period > 1.1 * pos.vbar * DT


def test_result_independent_of_entry_sampling_start():
    """Sect. 7.1: the entries are the offsets s modulo vbar dt, so the result is periodic
    in s and the overshoot range does not depend on where the sample starts.

    (a) s -> s + vbar dt (start one period earlier) gives the same end positions (1e-12);
    (b) shifting the whole sample (offset 0.1, 0.5, 0.9 of the spacing) changes the range
    by less than the largest jump between neighbouring samples (sampling resolution)."""
    prof = profile(1.8, 1.1)
    base = positioning(prof, w=W, c_mu=C_MU, n_entries=64, offset=0.5)
    earlier = simulate_batch(prof, base.x0 - base.vbar * DT, base.v0, x_mu=base.x_mu, w=W, c_mu=C_MU)
    np.testing.assert_allclose(earlier.x_end, base.x_end, rtol=0, atol=1e-12)
    step = np.max(np.abs(np.diff(np.append(base.overshoot, base.overshoot[0]))))
    assert 0 < step < 0.2 * (base.overshoot_max - base.overshoot_min)
    for offset in (0.1, 0.9):
        other = positioning(prof, w=W, c_mu=C_MU, n_entries=64, offset=offset)
        assert abs(other.overshoot_min - base.overshoot_min) <= step
        assert abs(other.overshoot_max - base.overshoot_max) <= step


def test_outcomes_counted_on_coarse_fig17_grid():
    """Fig. 17 C on a 21 x 21 grid with 16 entries: every run ends in a counted outcome.

    Physics checked: the fractions add up to 1 where the mass moves forward (case > 0,
    vbar > 0) and are NaN elsewhere; accumulation needs y2'' >= y3'' (for y3'' > y2'' the
    point x_stick_min repels: a stick just below it is followed by a backward slip); with
    y3'' <= 1 the motion in the zone is monotone (no backward slip), so every entry comes
    to rest or accumulates; never-stopping entries (periodic stick-slip in the zone) and
    undecided ones (bounded non-periodic motion) occur only for y3'' > y2''."""
    y2, y3 = np.meshgrid(COARSE, COARSE, indexing="ij")
    grid = positioning_grid(DT, DY, y2, y3, w=W, c_mu=C_MU, n_entries=16)
    total = grid.frac_accumulate + grid.frac_stop + grid.frac_never_stop + grid.frac_undecided
    np.testing.assert_allclose(total[grid.moving], 1.0)
    assert np.all(np.isnan(total[~grid.moving]))
    assert np.array_equal(grid.moving, (grid.case > 0) & (grid.vbar > 0))
    acc, never = grid.frac_accumulate > 0, grid.frac_never_stop + grid.frac_undecided > 0
    assert acc.sum() > 20 and never.sum() > 10
    assert np.all(y2[acc] >= y3[acc])
    assert np.all(y3[never] > y2[never])
    assert np.all(grid.frac_stop[grid.moving & (y3 <= 1)] + grid.frac_accumulate[grid.moving & (y3 <= 1)] == 1)
    # Fig. 17 C/D: where all entries accumulate, the positioning error is zero.
    all_acc = grid.frac_accumulate == 1
    np.testing.assert_array_equal(grid.dx_d[all_acc], 0.0)
    assert np.all(grid.dx_d[grid.moving & (grid.frac_stop == 1)] > 0)


def test_accumulation_speed_claim():
    """Sect. 7.3: "x_mu + p (x_stick_min - x_mu) is reached in at most 5 period times for
    p = 0.99 and in at most 7 for p = 0.999".  Verified (101 x 101 grid, 64 entries; this
    test a 21 x 21 grid with 16 entries) in this sense: counted from the first stick in the
    zone (worst case over accumulating entries 3.76 and 6.71 periods), equivalently at most
    5 and 7 stick events after the first one.  Counted from the entry (first arrival at
    x_mu) it fails for p = 0.999 on the diagonal y2'' = y3'' (7.97 periods at (2.5, 2.5),
    where the slowest accumulations occur, contraction 0.49)."""
    y2, y3 = np.meshgrid(COARSE, COARSE, indexing="ij")
    grid = positioning_grid(DT, DY, y2, y3, w=W, c_mu=C_MU, n_entries=16, levels=(0.99, 0.999))
    worst_stick = np.nanmax(grid.level_from_first_stick, axis=(0, 1))
    assert np.all(worst_stick <= [5.0, 7.0])
    assert np.all(np.nanmax(grid.level_sticks, axis=(0, 1)) <= [5, 7])
    diag = accumulation_speed(profile(2.5, 2.5), w=W, c_mu=C_MU, n_entries=64)
    assert diag.worst_from_entry[1] > 7.5
    assert diag.worst_from_first_stick[1] <= 7.0
    off = np.where(y2 > y3, grid.level_from_entry[..., 1], np.nan)
    assert np.nanmax(off) <= 7.0


def test_sufficient_condition_is_not_independent_of_entries():
    """Sect. 7.3 claims accumulation from every entry if x_{n+1}(x_mu) < x_stick_min.  It holds
    for the map from any x_1 in [x_mu, x_stick_min) (tests/test_stick_map.py) but a
    steady-state entry can stick first beyond x_{n+1}(x_mu): its entry slip starts below
    x_mu, on low friction.  At (2.22, 1.36) the condition holds by 2.3e-5, yet one of 64
    entries sticks first beyond x_stick_min and stays there."""
    prof = profile(2.22, 1.36)
    pos = positioning(prof, w=W, c_mu=C_MU, n_entries=64)
    f_mu = float(stick_map(pos.x_mu, prof, w=W, c_mu=C_MU, x_mu=pos.x_mu))
    assert 0 < pos.x_stick_min - f_mu < 3e-5
    assert pos.frac_accumulate == 63 / 64
    rest = pos.status == REST
    assert np.all(pos.x_end[rest] > pos.x_stick_min)


def test_chaotic_entries_are_reported_undecided():
    """For y3'' > y2'' the backward slips in the transition zone are hyperbolic (they
    amplify differences), and at (1.6, 1.7) some entries move irregularly for 1000
    periods: reported HORIZON/BOUNDED (undecided), counted in frac_undecided, never hang."""
    pos = positioning(profile(1.6, 1.7), w=W, c_mu=C_MU, n_entries=32, max_periods=300)
    undecided = pos.status == HORIZON
    assert undecided.any() and np.all(pos.reason[undecided] == Reason.BOUNDED)
    assert pos.frac_undecided == undecided.mean()
    assert np.all(np.isnan(pos.overshoot[undecided]))


@pytest.mark.parametrize("kwargs, match", [
    ({"w": 0.0}, "w"), ({"c_mu": 1.0}, "c_mu"), ({"n_entries": 0}, "n_entries"), ({"offset": 1.0}, "offset"),
])
def test_bad_input(kwargs, match):
    """A one-line ValueError naming the quantity, before any work."""
    args = {"w": W, "c_mu": C_MU, **kwargs}
    with pytest.raises(ValueError, match=match):
        positioning(profile(2.3, 1.3), **args)


def test_profile_that_never_reaches_the_zone():
    """Case 2 (vbar < 0, Table 1): the mass never reaches the zone; positioning says so and
    the grid reports NaN there."""
    with pytest.raises(ValueError, match="never reaches the zone"):
        positioning(profile(0.95, 2.4), w=W, c_mu=C_MU)
    grid = positioning_grid(DT, DY, 0.95, 2.4, w=W, c_mu=C_MU, n_entries=4)
    assert not grid.moving and np.isnan(grid.dx_d)


def test_result_files_and_figures(tmp_path):
    """The stage's result files (write_h5/read_h5 round trip) and Figs. 14-18 drawn from them.

    fig18.h5: eq. (59) equals the exact solver's map (1e-12) wherever valid; the cobweb from
    above the threshold x_c ends at x_stick_min (1e-12), the one from below at rest beyond
    it (Fig. 18).  fig17.h5: 2-D arrays indexed [i_y2, i_y3], NaN where the mass never
    reaches the zone.  Each figure shows the data it was given."""
    from selfalign.io.hdf5 import read_h5, write_h5
    from selfalign.plots.accumulation import figure_14, figure_15, figure_16, figure_17, figure_18
    from selfalign.stages.accumulation import fig16_content, fig17_content, fig18_content

    axis2, axis3 = np.array([1.2, 1.8, 2.3]), np.array([1.1, 1.3])
    write_h5(tmp_path / "fig17.h5", *fig17_content(axis2, axis3, dt=DT, dy=DY, w=W, c_mu=C_MU, n_entries=4))
    write_h5(tmp_path / "fig18.h5", *fig18_content(ThreePhaseProfile(1.05, DY, 2.2, 0.9), w=W, c_mu=C_MU))
    write_h5(tmp_path / "fig16.h5", *fig16_content([(2.3, 1.3), (1.8, 1.1)], dt=DT, dy=DY, w=W, c_mu=C_MU,
                                                   n_entries=8))
    r17, r18, r16 = (read_h5(tmp_path / f"fig{n}.h5") for n in (17, 18, 16))
    d = r17["datasets"]
    assert d["frac_accumulate"].shape == (3, 2) and d["level_sticks"].shape == (3, 2, 2)
    assert np.isnan(d["dx_d"][0, 1]) and not d["vbar"][0, 1] > 0  # (1.2, 1.3): case 0, no motion
    assert d["frac_accumulate"][2, 1] == 1.0 and d["dx_d"][2, 1] == 0.0
    d, a = r18["datasets"], r18["attrs"]
    np.testing.assert_allclose(d["x_next_simulated"][d["valid"]], d["x_next_formula"][d["valid"]], atol=1e-12)
    assert d["cobweb_accumulate"][-1] == pytest.approx(a["x_stick_min"], abs=1e-12)
    assert d["cobweb_rest"][-1] > a["x_stick_min"]
    keys = ["y2_2.3_y3_1.3", "y2_1.8_y3_1.1"]
    figs = [figure_14(r16, keys[1]), figure_15(r16, keys[1]), figure_16(r16, keys), figure_17(r17),
            figure_18(r18)]
    line = figs[4].axes[0].lines[0]
    valid = d["valid"]
    np.testing.assert_array_equal(line.get_ydata()[valid], d["x_next_formula"][valid])
    portrait = figs[2].axes[0].lines[0]
    entry = r16["groups"][keys[0]]["groups"]["entry_0"]["datasets"]
    np.testing.assert_array_equal(portrait.get_xdata(), entry["x"])
