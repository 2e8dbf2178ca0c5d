"""The figures of the effects beyond the paper (finite jerk, docs/explanation/model.md) and of a design
(docs/tutorials/design-station.md) against the figure standard (selfalign.plots.style): every special value
in its one encoding (style.SPECIAL), the quantities in their maps, the chosen design marked in every panel.

The grids and the design result are made up here, in the layouts the stages write, so each encoding is
checked on cells whose values are known.
"""

import numpy as np
import pytest
from matplotlib.colors import ListedColormap, to_hex, to_rgba
from matplotlib.patches import PathPatch

from selfalign.analysis.finite_jerk import SteadyGrid, StoppingGrid
from selfalign.model.profiles import RAMPS_TOO_LONG
from selfalign.plots import style
from selfalign.plots.design import actuator_limits, figure_design
from selfalign.plots.finite_jerk import finite_jerk_figure, finite_jerk_stopping_figure

TAB_COLOURS = {to_hex(f"tab:{name}") for name in ("blue", "orange", "green", "red", "purple", "brown", "pink",
                                                   "gray", "olive", "cyan")}


def marked(ax, y2, y3, kind) -> np.ndarray:
    """[i_y2, i_y3]: the cells of ``ax`` whose centre lies in a patch drawn in the encoding ``kind``
    (its face colour and hatch, style.SPECIAL)."""
    encoding = style.SPECIAL[kind]
    centres = np.array([(a, b) for a in y2 for b in y3])
    inside = np.zeros(len(centres), dtype=bool)
    for patch in ax.patches:
        face = "none" if patch.get_facecolor()[3] == 0 else to_hex(patch.get_facecolor())
        wanted = "none" if encoding["facecolor"] == "none" else to_hex(encoding["facecolor"])
        if isinstance(patch, PathPatch) and (patch.get_hatch() or "") == encoding["hatch"] and face == wanted:
            inside |= patch.get_path().contains_points(centres)
    return inside.reshape(len(y2), len(y3))


def mesh_values(ax) -> np.ndarray:
    """[i_y2, i_y3] of the first QuadMesh of ``ax`` (map_mesh draws the transpose), NaN where masked."""
    mesh = next(c for c in ax.collections if type(c).__name__ == "QuadMesh")
    values = np.ma.filled(np.ma.asarray(mesh.get_array(), dtype=float), np.nan)
    rows, columns = (n - 1 for n in mesh.get_coordinates().shape[:2])
    return values.reshape(rows, columns).T


def panels(fig):
    return [ax for ax in fig.axes if ax.get_label() != "<colorbar>" and ax.axison]


def legend_texts(fig) -> str:
    return "\n".join(t.get_text() for ax in fig.axes if ax.get_legend() for t in ax.get_legend().texts)


@pytest.fixture(scope="module")
def steady():
    """Two ramp fractions over a 4 x 3 plane: v̄ < 0 (case 2), case 0, ramps too long at the second ramp."""
    y2, y3 = np.array([0.5, 1.0, 2.0, 3.0]), np.array([0.5, 1.0, 2.0])
    vbar = np.array([[[np.nan, -0.032, -0.001], [0.0, 0.01, -0.02], [0.02, 0.03, 0.01], [0.04, 0.02, 0.03]]] * 2)
    case = np.array([[[0, 2, 2], [5, 1, 3], [1, 3, 3], [1, 3, 3]]] * 2)
    case[1, 3, :] = RAMPS_TOO_LONG
    vbar[1, 3, :] = np.nan
    return {"fig11": SteadyGrid(np.array([0.0, 0.05]), y2, y3, vbar, case)}


def test_negative_mean_velocity_is_marked_not_painted_as_zero(steady):
    """Hypothesis (Sect. 5.1, Table 1: case 2 and 3 can walk backward): each cell with v̄ < 0 is drawn in
    the encoding "v_negative" and carries no colour of the v̄ map (which starts at 0), and the legend names
    it; the cells with no profile (case 0, ramps too long) are drawn as case 0 in both rows; one colour bar
    per plane (v̄) and none per case map."""
    grid = steady["fig11"]
    fig = finite_jerk_figure(steady)
    assert style.print_check(fig) == []
    maps = panels(fig)
    assert [ax.get_title(loc="left") for ax in maps] == list("abcd")
    for k, (ax_v, ax_c) in enumerate(zip(maps[:2], maps[2:])):
        backward = grid.vbar[k] < 0
        assert np.array_equal(marked(ax_v, grid.y2, grid.y3, "v_negative"), np.nan_to_num(backward))
        assert np.all(np.isnan(mesh_values(ax_v)[backward]))
        no_profile = (grid.case[k] == 0) | (grid.case[k] == RAMPS_TOO_LONG)
        for ax in (ax_v, ax_c):
            assert np.array_equal(marked(ax, grid.y2, grid.y3, "non_physical"), no_profile)
    assert sum(ax.get_label() == "<colorbar>" for ax in fig.axes) == 1
    assert style.SPECIAL["v_negative"]["label"] in legend_texts(fig)


@pytest.fixture(scope="module")
def stopping():
    """One ramp fraction over a 3 x 3 plane: every entry accumulates (Delta x_d = 0), none does, some do,
    some entries never stop (33 % at rest, Delta x_d of those only), and a setting that never reaches the zone."""
    y2, y3 = np.array([1.5, 2.0, 2.5]), np.array([1.0, 1.5, 2.0])
    acc = np.array([[[0.0, 0.25, np.nan], [1.0, 1.0, 0.0], [0.5, 0.0, 0.125]]])
    rest = np.array([[[1.0, 0.75, np.nan], [0.0, 0.0, 0.33], [0.5, 1.0, 0.25]]])
    dx_d = np.array([[[0.004, 0.003, np.nan], [0.0, 0.0, 0.002], [0.001, 0.005, 0.006]]])
    return StoppingGrid(np.array([0.0]), y2, y3, acc, rest, dx_d)


def test_stopping_shows_values_only_where_every_entry_ends_at_rest(stopping):
    """Hypothesis (Sect. 7.1, eq. 39: Delta x_d spans the entries that stop): Delta x_d and the fraction
    classes are shown only where every entry ends at rest; elsewhere both rows carry the encoding
    "unsettled"; Delta x_d = 0 exactly is drawn in "dx_zero"; Delta x_d in the map of style.QUANTITY_CMAPS
    ("cividis") and the fraction that accumulates as the three classes in style.FRACTION_COLORS."""
    fig = finite_jerk_stopping_figure(stopping)
    assert style.print_check(fig) == []
    ax_acc, ax_dx = panels(fig)
    y2, y3 = stopping.y2, stopping.y3
    unsettled = np.array([[False, False, False], [False, False, True], [False, False, True]])
    for ax in (ax_acc, ax_dx):
        assert np.array_equal(marked(ax, y2, y3, "unsettled"), unsettled)
    shown = mesh_values(ax_dx)
    assert np.all(np.isnan(shown[unsettled])) and np.array_equal(shown[~unsettled], stopping.dx_d[0][~unsettled],
                                                                    equal_nan=True)
    assert np.array_equal(marked(ax_dx, y2, y3, "dx_zero"), stopping.dx_d[0] == 0.0)
    dx_mesh = next(c for c in ax_dx.collections if type(c).__name__ == "QuadMesh")
    assert dx_mesh.get_cmap().name == style.QUANTITY_CMAPS["dx_d"]
    acc_mesh = next(c for c in ax_acc.collections if type(c).__name__ == "QuadMesh")
    assert isinstance(acc_mesh.get_cmap(), ListedColormap)
    assert [to_hex(c) for c in acc_mesh.get_cmap().colors] == list(style.FRACTION_COLORS)
    classes = mesh_values(ax_acc)
    assert classes[0].tolist()[:2] == [0.0, 1.0] and classes[1].tolist()[:2] == [2.0, 2.0]
    texts = legend_texts(fig)
    assert style.SPECIAL["dx_zero"]["label"] in texts and "not every entry stops" in texts


def design_result(y2: float, y3: float, found: bool = True) -> dict:
    """A design result in read_h5 layout (SI): a three-phase design at (y2'', y3'') on a map up to the
    acceleration limit 4 m/s^2, whose front's simulated members lie ten times past its spread, as for
    workflow/designs/cam_drive.yaml."""
    axis = np.linspace(0.5, 4.0, 8)
    physical = axis[:, None] + axis[None, :] > 3.0
    spec = {"max_acceleration": 4.0, "max_stroke": 0.01, "min_stroke": None, "period": [0.1, 0.3], "name": "test"}
    front = {"spread": np.array([1.0e-4, 8.0e-5, 6.0e-5]), "t_estimate": np.array([0.6, 1.0, 20.0]),
             "error": np.array([1.3e-3, 1.2e-3, np.nan]), "t_arrive": np.array([0.58, 0.61, np.nan]),
             "guaranteed": np.array([False, False, False])}
    margin = {"margin": np.array([0.3, 0.4]), "t_estimate": np.array([0.6, 1.0]), "y2": np.array([y2, 3.0]),
              "y3": np.array([y3, 2.0]), "period": np.array([0.25, 0.25]), "stroke": np.array([0.005, 0.005])}
    profile = {"y2": np.float64(y2), "y3": np.float64(y3), "period": np.float64(0.25), "stroke": np.float64(0.005),
               "c_mu": np.float64(3.0)}
    return {"attrs": {"found": found, "family": "three_phase", "spec": spec},
            "groups": {"front_time_error": {"datasets": front}, "front_time_margin": {"datasets": margin},
                       "performance": {"datasets": {"error": np.float64(1.3e-3), "t_arrive": np.float64(0.58),
                                                    "margin": np.float64(0.3)}},
                       "profile": {"datasets": profile},
                       "map": {"datasets": {"y2": axis, "y3": axis, "case": np.where(physical, 3, 0),
                                            "physical": physical, "screened": physical,
                                            "frac_accumulate": np.zeros((8, 8)), "sufficient": np.zeros((8, 8))}}}}


def test_design_figure_marks_the_chosen_design_and_its_actuator_limit():
    """Hypothesis (docs/tutorials/design-station.md): the chosen design is marked (a star) in panels a, b
    and c; on the acceleration limit (y2'' = 4 m/s^2, the map's edge) the legend says so, inside it it does
    not; panel a's error axis is chosen from the front (54-102 um as in cam_drive, not squashed by members
    at 1200-1300 um), which are drawn right of the break within the axes; no tab: colour; print size."""
    fig = figure_design(design_result(4.0, 2.0))
    assert style.print_check(fig) == []
    ax_a, ax_b, ax_c = fig.axes[:3]
    assert [ax.get_title(loc="left") for ax in (ax_a, ax_b, ax_c)] == ["a", "b", "c"]
    for ax in (ax_a, ax_b, ax_c):
        assert sum(line.get_marker() == "*" for line in ax.lines) == 1
    assert "on the acceleration limit 4 m/s$^2$" in legend_texts(fig)
    assert "limit" not in legend_texts(figure_design(design_result(3.0, 2.0)))
    left, right = ax_a.get_xlim()
    assert right < 2.0 * 100.0  # um: the front's largest spread is 100 um
    members = np.concatenate([line.get_xdata() for line in ax_a.lines if line.get_marker() == "o"])
    assert members.size == 2 and np.all((members > left) & (members < right))
    colours = {to_hex(line.get_color()) for ax in fig.axes for line in ax.lines}
    assert not colours & TAB_COLOURS


def test_actuator_limits_are_read_from_the_data():
    """The limits a design lies on come from its values against the spec, to BINDING (1e-6): the peak
    acceleration of an optimal motion's pieces, a free stroke at its largest value (1 mm less 4.5e-8
    relative, as smd_realistic's optimum), not a fixed stroke, and both ends of the period range."""
    spec = {"max_acceleration": 8.0, "max_stroke": 1e-3, "min_stroke": None, "period": [0.01, 0.1]}
    optimal = {"y2": 6.18, "y3": 2.24, "accels": np.array([-6.18, 8.0, 2.24]), "stroke": 0.99999995e-3,
               "period": 0.063}
    assert actuator_limits(spec, optimal) == ["acceleration limit 8 m/s$^2$", "stroke limit 1 mm"]
    assert actuator_limits({**spec, "min_stroke": 1e-3}, {**optimal, "accels": np.array([6.0])}) == []
    assert actuator_limits(spec, {"y2": 3.0, "y3": 2.0, "stroke": 5e-4, "period": 0.1}) == ["period limit 100 ms"]
    assert actuator_limits(spec, {"y2": 3.0, "y3": 2.0, "stroke": 5e-4, "period": 0.01}) == ["period limit 10 ms"]
    assert actuator_limits(spec, {"y2": 7.99, "y3": 2.0, "stroke": 9.9e-4, "period": 0.05}) == []


def test_fraction_classes_and_special_encodings_stay_distinct():
    """The check can fail: a map cell drawn with the v̄ < 0 hatch is not found as "unsettled" (the two
    hatches differ), and a grey cell of case 0 is not found as "dx_zero"."""
    from matplotlib.figure import Figure

    ax = Figure().subplots()
    y = np.array([0.0, 1.0])
    mask = np.array([[True, False], [False, False]])
    style.mark_cells(ax, y, y, mask, "v_negative")
    style.mark_cells(ax, y, y, mask, "non_physical")
    assert np.array_equal(marked(ax, y, y, "v_negative"), mask)
    assert not marked(ax, y, y, "unsettled").any() and not marked(ax, y, y, "dx_zero").any()
    assert to_rgba(style.SPECIAL["non_physical"]["facecolor"]) != to_rgba(style.SPECIAL["dx_zero"]["facecolor"])


def test_static_friction_maps_draw_case_0_as_case_0():
    """Hypothesis (Sect. 5.1, Appendix: no physical profile where q = 8 dy (1/y2'' + 1/y3'') / dt^2 > 1):
    draw("static_friction") marks exactly the settings of its plane with q > 1 in the encoding
    "non_physical" on every map, and leaves white (no data) the others the mass never reaches."""
    from selfalign.stages.figures import draw

    y2, y3 = np.array([0.5, 1.5, 2.5]), np.array([0.5, 1.5, 2.5])
    reached = np.array([[np.nan, np.nan, np.nan], [np.nan, 0.0, 1.0], [np.nan, 0.5, 1.0]])
    dx_d = np.where(reached == 1.0, 0.0, 1e-3 * np.isfinite(reached))
    maps = {"ratio": np.array([1.0, 1.1]), "frac_accumulate": np.array([reached, 0.0 * reached]),
            "frac_never_stop": np.zeros((2, 3, 3)), "frac_undecided": np.zeros((2, 3, 3)),
            "dx_d": np.array([np.where(np.isnan(reached), np.nan, dx_d), np.where(np.isnan(reached), np.nan, 1e-3)])}
    sweep = {"ratio": np.array([1.0, 1.1]), "y2": np.array([2.3]), "y3": np.array([1.3]),
             "dx_d": np.array([[0.0, 1e-3]]), "frac_accumulate": np.array([[1.0, 0.0]])}
    result = {"datasets": {"y2": y2, "y3": y3}, "attrs": {"dt": 1.0, "dy": 0.084},
              "groups": {"maps": {"datasets": maps}, "sweep": {"datasets": sweep}}}
    fig = draw("static_friction", [result])
    assert style.print_check(fig) == []
    q = 8 * 0.084 * (1 / y2[:, None] + 1 / y3[None, :])
    assert q[0, 0] > 1 and q[1, 1] < 1  # both kinds of cell are present
    for ax in panels(fig)[:2]:
        assert np.array_equal(marked(ax, y2, y3, "non_physical"), q > 1)
