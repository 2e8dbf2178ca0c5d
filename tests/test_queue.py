"""A queue of parts at the stop zone (docs/explanation/queue.md, selfalign.analysis.queue): where parts that
arrive one after another come to rest, against the single part (eq. 41, Sect. 7) and the pooled rest condition
of a pushed cluster (docs/explanation/several-parts.md); the stage's result file and its recording as boxes.

All on the Fig. 18 setting (Sect. 7.3: dt = 1.05, dy = 0.084, y2'' = 2.2, y3'' = 0.9; c_mu = 2.5, w = 0.05), where
x_stick_min - x_mu = w (2.2 - 1) / (2.5 - 1) = 0.04.
"""

import math

import numpy as np
import pytest
import yaml
from figcheck import compare_figure_data, figure_data, load_reference
from test_figures import ATOL, RTOL, assert_data_matches

import selfalign as sa
from selfalign.analysis.queue import (
    QUEUE_EVENTS,
    aligned_times,
    pooled_rest,
    queue_parts,
    queue_study,
    run_queue,
    single_rest,
    spread_factors,
)
from selfalign.io.hdf5 import read_dataset_attrs, read_h5, write_h5
from selfalign.io.recording import Boxes, Recording, read_boxes, read_logs, read_recording, write_recording
from selfalign.model.parts import Part
from selfalign.plots.parts import HORIZON, motion_figure, queue_figure
from selfalign.plots.style import LINE_COLORS, SPECIAL, print_check
from selfalign.solvers.parts_exact import simulate_parts
from selfalign.stages.parts import queue_recording, queue_results

PROFILE = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
ZONE = sa.StopZone(x_mu=0.5, w=0.05, c_mu=2.5)
#: x_stick_min - x_mu of eq. (41) on the Fig. 18 setting.
STICK = 0.04
#: Rest positions found by the exact solver agree with closed forms to rounding; 1e-12 leaves room for it.
EXACT = 1e-12
#: A cluster approaches its pooled rest stick by stick, as the single part approaches x_stick_min (Sect. 7.3):
#: the tests run until the period-end positions repeat to rounding.
SETTLED = 1e-14


def test_one_part_reproduces_the_single_part_rest_position():
    """Hypothesis: a queue of one part is the paper's single part.  From 0.25 before the zone it accumulates
    at x_stick_min = x_mu + w (max|y''| - 1) / (c_mu - 1) (eq. 41, Sect. 7.3); the queue's period-by-period
    run ends where the single-part exact solver (``sa.simulate``) ends, both to 1e-12."""
    run = run_queue(PROFILE, ZONE, queue_parts(1, ZONE, distance=0.25, spacing=0.0), settle=SETTLED)
    alone = sa.simulate(sa.Scene(PROFILE, ZONE, x0=0.25, v0=0.0, until="rest", max_periods=1000))
    assert run.status in ("rest", "settled")
    assert abs(run.x_end[0] - ZONE.x_stick_min(2.2)) <= EXACT
    assert abs(run.x_end[0] - alone.x_end) <= EXACT
    assert single_rest(PROFILE, ZONE, distance=0.25, settle=SETTLED) == run.x_end[0]


def test_period_by_period_run_is_the_one_run():
    """Hypothesis: every period of the profile starts at phase 0, so a queue run one period at a time from each
    period's end state is the run over all periods at once (docs/explanation/queue.md); three parts touching,
    after 20 periods, to 1e-12."""
    parts = queue_parts(3, ZONE, distance=0.25, spacing=0.0)
    run = run_queue(PROFILE, ZONE, parts, max_periods=20)
    whole = simulate_parts(PROFILE, parts, surface=ZONE, periods=20)
    assert run.status == "horizon" and run.x.shape == (21, 3)
    np.testing.assert_allclose(run.x_end, whole.x_end, rtol=0, atol=EXACT)
    # the events per part and period add up to the one run's per part (a break at a period end is no event)
    assert run.part_events.shape == (20, 3, len(QUEUE_EVENTS))
    for k, kind in enumerate(QUEUE_EVENTS):
        assert run.part_events[:, :, k].sum(axis=0).tolist() == getattr(whole, "part_" + kind).tolist(), kind


def test_parts_fed_far_apart_first_stops_alone_then_the_pair_pools():
    """Hypothesis: a part fed far behind the first one finds it at rest at the single-part position (eq. 41), as
    if alone; it cannot rest behind it (its own k mu_bar = 1 < max|y''| on the uniform surface), so it pushes
    the pair on to the pooled rest: the mean of the two coefficients reaches max|y''|, the front at
    x_mu + 2 (x_stick_min - x_mu) (docs/explanation/several-parts.md), the two touching, all to 1e-12."""
    run = run_queue(PROFILE, ZONE, queue_parts(2, ZONE, distance=0.25, spacing=3.0), settle=SETTLED)
    far = run.x[:, 1] - ZONE.w - run.x[:, 0] > 0.1
    waiting = run.x[np.nonzero(far)[0][-1]]         # the last period end with the rear part far behind
    assert np.nonzero(far)[0][-1] > 30
    assert abs(waiting[1] - ZONE.x_stick_min(2.2)) <= EXACT
    assert abs(run.x_end[1] - (ZONE.x_mu + 2 * STICK)) <= EXACT
    assert abs(run.x_end[1] - ZONE.w - run.x_end[0]) <= EXACT


@pytest.mark.parametrize("n", [3, 5])
def test_pushed_cluster_rests_at_the_pooled_condition(n):
    """Hypothesis: N equal parts pushed together rest where the mean of their coefficients reaches max|y''| =
    2.2 (docs/explanation/several-parts.md: a pushed cluster holds by its pooled bound); one part is in its
    transition at a time, so the front lies at x_mu + N (x_stick_min - x_mu) (docs/explanation/queue.md),
    which :func:`pooled_rest` finds by bisection and the solver reaches, both to 1e-12."""
    run = run_queue(PROFILE, ZONE, queue_parts(n, ZONE, distance=0.25, spacing=0.05), settle=SETTLED)
    expected = ZONE.x_mu + n * STICK - ZONE.w * np.arange(n)[::-1]
    np.testing.assert_allclose(pooled_rest(PROFILE, ZONE, np.ones(n)), expected, rtol=0, atol=EXACT)
    np.testing.assert_allclose(run.x_end, expected, rtol=0, atol=EXACT)
    mu = ZONE.coefficient(run.x_end)
    assert abs(mu.mean() - 2.2) <= EXACT


def test_pooled_rest_weighs_masses_and_friction_factors():
    """Hypothesis: the pooled rest condition is sum m_i k_i mu_bar_i = max|y''| sum m_i (docs/explanation/
    several-parts.md); at the front position :func:`pooled_rest` returns it holds to 1e-12 for unequal parts."""
    k, m = np.array([0.8, 1.3, 1.1]), np.array([2.0, 0.5, 1.0])
    x = pooled_rest(PROFILE, ZONE, k, m)
    assert abs(np.sum(m * k * ZONE.coefficient(x)) / m.sum() - 2.2) <= EXACT
    np.testing.assert_allclose(np.diff(x), ZONE.w, rtol=0, atol=EXACT)


def test_study_marks_the_front_part_and_the_push_through():
    """Hypothesis (docs/explanation/queue.md): on the Fig. 18 setting the front part of one part ends at the
    single-part position and of two parts at x_mu + 2 (x_stick_min - x_mu) = x_mu + 1.6 w, past the strip's
    high side x_mu + w: pushed through; both parts lie in the zone."""
    study = queue_study(PROFILE, ZONE, n_max=2, spacings=[0.05], restitutions=[0.0, 0.5], spreads=[0.0],
                        distance=0.25)
    assert study["front_at_single"][0, :, 0].tolist() == [[True, False]] * 2
    assert study["front_through"][0, :, 0].tolist() == [[False, True]] * 2
    assert study["in_zone"][0, :, 0].tolist() == [[1, 2]] * 2
    np.testing.assert_allclose(study["error"][0, :, 0, 1, 0], STICK, rtol=0, atol=EXACT)
    assert np.isnan(study["x_end"][0, 0, 0, 0, 1])


def test_aligned_times_follow_the_samples():
    """Hypothesis: a part is aligned from the first period end after which it stays within the tolerance of its
    end position; a single part arrives at x_stick_min within the fourth period (its rest, Sect. 7.3)."""
    run = run_queue(PROFILE, ZONE, queue_parts(1, ZONE, distance=0.25, spacing=0.0))
    t = aligned_times(run, 1e-3)
    inside = np.abs(run.x[:, 0] - run.x_end[0]) <= 1e-3
    first = int(np.argmax(inside))
    assert inside[first:].all() and not inside[first - 1]
    assert t[0] == run.t[first]


def _design_result():
    """A design result (read_h5 layout) of the three-phase family: the Fig. 18 profile and zone in SI, for a part
    2 mm wide with mu = 0.2 (scales of Sect. 3.2, L = the width)."""
    si = sa.SIScale(mu=0.2, g=9.81, L=0.002)
    accel = si.unit("acceleration")
    spec = {"name": "fig18_in_si", "mu": 0.2, "g": 9.81, "width": 0.002, "distance": 0.01, "tolerance": 1e-4}
    profile = {"period": 1.05 * si.T, "stroke": 0.084 * si.L, "y2": 2.2 * accel, "y3": 0.9 * accel, "c_mu": 2.5}
    return {"attrs": {"spec": spec, "family": "three_phase"},
            "groups": {"profile": {"datasets": profile}, "performance": {"datasets": {"t_rest": 1.0}}}}


def _settings(repo):
    settings = yaml.safe_load((repo / "workflow/config/config.yaml").read_text())["stages"]["parts"]
    settings.update(n_max=2, spacings=[0.05], restitutions=[0.0], spreads=[0.0], max_periods=300,
                    motion={"n": 2, "spacing": 0.05, "restitution": 0.0}, settle=SETTLED,
                    design={**settings["design"], "n_max": 2, "max_periods": 1000, "settle": SETTLED})
    return settings


@pytest.fixture(scope="module")
def stage_file(repo, tmp_path_factory):
    """The stage's result file on shrunk settings (two parts) and the Fig. 18 design in SI."""
    settings = _settings(repo)
    zone = yaml.safe_load((repo / "workflow/config/config.yaml").read_text())["stages"]["accumulation"]["zone"]
    return write_h5(tmp_path_factory.mktemp("parts") / "queue.h5", *queue_results(settings, zone, _design_result()),
                    config=settings)


def test_stage_writes_every_dataset_with_units_and_the_si_queue(stage_file):
    """Hypothesis: the stage's file documents every dataset (units, description); the SI queue of the design
    with the Fig. 18 shape rests as in model units: one part at x_stick_min, 0.8 of the 2 mm width past the
    strip's edge (eq. 41), two parts with the front one 0.8 width further (1e-12 relative)."""
    path = stage_file
    attrs = read_dataset_attrs(path)
    assert attrs and all(a.get("units") and a.get("description") for a in attrs.values())
    assert attrs["design_queue/throughput"]["units"] == "1/s (SI)"
    assert attrs["design_queue/x_end"]["units"] == "m (SI)"
    d = read_h5(path)["groups"]["design_queue"]["datasets"]
    assert d["x_single"] == pytest.approx(0.8 * 0.002, rel=EXACT)
    assert d["x_end"][1, 0] == pytest.approx(1.6 * 0.002, rel=EXACT)
    assert d["throughput"][0] == pytest.approx(1.0 / d["t_aligned"][0, 0], rel=EXACT)


def test_recording_holds_one_box_per_part_at_every_period_end(stage_file, tmp_path):
    """Hypothesis: the recording of a queue shows each part as a box of its width whose centre is its front
    minus half its width at every period end, over the zone's box (compared by content: recordings carry
    random chunk ids)."""
    result = read_h5(stage_file)
    groups = result["groups"]
    path = write_recording(tmp_path / "queue.rrd", queue_recording(result))
    boxes = read_boxes(path)
    t, x = groups["queue_motion"]["datasets"]["t"], groups["queue_motion"]["datasets"]["x"]
    index, centres, half = boxes["queue/parts"]
    np.testing.assert_allclose(index, t, rtol=0, atol=1e-9)
    np.testing.assert_allclose(centres[:, :, 0], x - 0.025, rtol=0, atol=1e-6)   # stored as float32
    np.testing.assert_allclose(half[:, :, 0], 0.025, rtol=1e-6)
    assert boxes["queue/zone"][1][0, 0, 0] == pytest.approx(0.525, rel=1e-6)
    series = read_recording(path)
    np.testing.assert_array_equal(series["front/part_1"][1], x[:, 1])
    # the events: one log line at the end of each period with events, naming each part's counts
    events = groups["queue_motion"]["datasets"]["events"]
    log = read_logs(path)["queue/events"]
    busy = [k for k in range(events.shape[0]) if np.any(events[k])]
    np.testing.assert_allclose(log.times, t[1:][busy], rtol=0, atol=1e-9)
    kinds = list(groups["queue_motion"]["attrs"]["event_kinds"])
    assert kinds == list(QUEUE_EVENTS) and len(log.texts) == len(busy) > 0
    row = events[busy[0]]
    assert log.texts[0] == f"period {busy[0] + 1}: " + "; ".join(
        f"part {i}: " + ", ".join(f"{c} {kind}" for c, kind in zip(counts, kinds) if c)
        for i, counts in enumerate(row) if counts.any())


@pytest.mark.parametrize(("call", "error", "message"), [
    (lambda: queue_parts(0, ZONE, distance=0.2, spacing=0.0), ValueError, "n"),
    (lambda: queue_parts(2, ZONE, distance=0.2, spacing=-0.1), ValueError, "spacing"),
    (lambda: queue_parts(2, ZONE, distance=0.0, spacing=0.0), ValueError, "distance"),
    (lambda: queue_parts(2, sa.Uniform(), distance=0.2, spacing=0.0), TypeError, "zone must be a StopZone"),
    (lambda: queue_parts(2, ZONE, distance=0.2, spacing=0.0, masses=[1.0]), ValueError, "masses"),
    (lambda: run_queue(sa.FourierProfile(1.0, [0.0], [1.0]), ZONE, []), TypeError, "PiecewiseConstantProfile"),
    (lambda: run_queue(PROFILE, sa.StopZone(x_mu=0.5, w=0.05, c_mu=2.0), []), ValueError, "max|y''|"),
    (lambda: run_queue(PROFILE, ZONE, [Part(0.0, width=0.05)], restitution=1.5), ValueError, "restitution"),
    (lambda: run_queue(PROFILE, ZONE, [Part(0.0, width=0.05)], settle=0.0), ValueError, "settle"),
    (lambda: spread_factors(3, 1.0), ValueError, "spread"),
    (lambda: queue_study(PROFILE, ZONE, n_max=2, spacings=[], restitutions=[0.0], spreads=[0.0], distance=0.2),
     ValueError, "spacings"),
    (lambda: pooled_rest(PROFILE, ZONE, [0.1, 0.1]), ValueError, "no position holds"),
    (lambda: aligned_times("run", 1e-3), TypeError, "QueueRun"),
    (lambda: Recording(np.arange(3.0), {}, boxes={"q": Boxes(np.zeros((2, 1)), np.ones(1), 1.0)}), ValueError,
     "shape"),
])
def test_bad_settings_are_refused_by_name(call, error, message):
    """Hypothesis: a bad setting is refused before any simulation, with a message naming it."""
    with pytest.raises(error, match=message.replace("|", r"\|")):
        call()


def test_spread_factors_keep_the_front_part_nominal():
    """Hypothesis: the spread pattern keeps the front part's factor 1 and the others in [1 - s, 1 + s]."""
    k = spread_factors(6, 0.2)
    assert k[-1] == 1.0 and np.all(np.abs(k - 1) <= 0.2) and not math.isclose(k[0], 1.0)


@pytest.mark.parametrize("name", ["parts_queue", "parts_motion"])
def test_figures_show_the_result(repo, stage_file, update_figure_refs, name):
    """Hypothesis: the figures draw the numbers of the result they are given: those of
    tests/figure_refs/<name>.json (the shrunk stage of this module), and panel (a) marks the front part of
    one and of two parts at the result's end positions in widths past x_mu (0.8 and 1.6, eq. 41 and the
    pooled rest)."""
    result = read_h5(stage_file)
    fig = (queue_figure if name == "parts_queue" else motion_figure)(result)
    if name == "parts_queue":
        front = [line for line in fig.axes[0].lines if line.get_label() == "front part"][0]
        np.testing.assert_allclose(front.get_ydata(), [0.8, 1.6], rtol=0, atol=1e-9)
    assert_data_matches(repo, fig, name, update_figure_refs)


def test_figure_comparison_catches_a_change(repo, stage_file):
    """Hypothesis: the figure check can fail: the front part's end 1 % further is reported."""
    result = read_h5(stage_file)
    result["groups"]["queue"]["datasets"]["x_end"] = result["groups"]["queue"]["datasets"]["x_end"] * 1.01
    diffs = compare_figure_data(figure_data(queue_figure(result)),
                                load_reference(repo / "tests/figure_refs/parts_queue.json"), rtol=RTOL, atol=ATOL)
    assert any(d.startswith("figure.axes[0].lines") for d in diffs), diffs


@pytest.mark.parametrize("name", ["parts_queue", "parts_motion"])
def test_figures_meet_the_print_standard(stage_file, name):
    """Hypothesis (docs/explanation/figures.md): the queue figures print at a journal width (174 mm for four
    panels lettered a-d, 84 mm for the trajectories), with no text below 7 pt, no parameter titles and no ASCII
    mathematics, and every part, line and marker in a colour of the Okabe-Ito palette or black."""
    result = read_h5(stage_file)
    fig = (queue_figure if name == "parts_queue" else motion_figure)(result)
    assert print_check(fig) == []
    assert round(fig.get_figwidth() * 25.4) == (174 if name == "parts_queue" else 84)
    if name == "parts_queue":
        assert [ax.get_title(loc="left") for ax in fig.axes] == ["a", "b", "c", "d"]
    from matplotlib.colors import to_hex
    palette = {c.lower() for c in LINE_COLORS} | {"#000000"}
    assert {to_hex(line.get_color()) for ax in fig.axes for line in ax.lines} <= palette


def test_queues_that_never_stop_are_hatched(stage_file):
    """Hypothesis (docs/explanation/queue.md, "Throughput of a real design"): a queue that runs out of periods
    before every part stops for good (status HORIZON) is drawn in the encoding "unsettled" of the figure
    standard, one hatched column at its N and none at a queue that rests, and the legend names it."""
    result = read_h5(stage_file)
    design = result["groups"]["design_queue"]["datasets"]
    design["status"] = np.array([0, HORIZON])
    fig = queue_figure(result)
    hatched = [p for p in fig.axes[3].patches if p.get_hatch() == SPECIAL["unsettled"]["hatch"]]
    assert len(hatched) == 1
    column = hatched[0].get_x(), hatched[0].get_x() + hatched[0].get_width()
    np.testing.assert_allclose(column, [1.6, 2.4], rtol=0, atol=1e-12)
    assert "not every part stops" in [t.get_text() for t in fig.legends[0].texts]
    design["status"] = np.array([0, 0])
    assert not [p for p in queue_figure(result).axes[3].patches if p.get_hatch()]
