import copy
import json

import numpy as np
from figcheck import compare_figure_data, compare_pixels, figure_data, load_reference, save_reference
from matplotlib.figure import Figure


def make_figure(scale=1.0, label="part", nan=True):
    t = np.linspace(0.0, 2.0, 41)
    x = scale * np.sin(np.pi * t)
    if nan:
        x[5] = np.nan
    fig = Figure(figsize=(4, 3))
    fig.suptitle("run")
    ax, ax2 = fig.subplots(1, 2)
    ax.plot(t, x, label=label)
    ax.plot(t, t, "--", label="table")
    ax.fill_between(t, x - 0.1, x + 0.1, alpha=0.3, label="band")
    ax.scatter(t[::10], x[::10])
    ax.bar([0.5, 1.5], [0.2, 0.4])
    ax.text(0.1, 0.2, "stick")
    ax.set(title="position", xlabel="t", ylabel="x", yscale="linear", xlim=(0, 2))
    grid = np.arange(12.0).reshape(3, 4)
    ax2.pcolormesh(np.ma.masked_greater(grid, 10))
    ax2.imshow(grid, extent=(0, 4, 0, 3))
    ax2.set_xscale("log")
    return fig


def test_identical_figures_match():
    data = figure_data(make_figure())
    assert compare_figure_data(figure_data(make_figure()), data) == []
    assert compare_figure_data(copy.deepcopy(data), data) == []


def test_content_is_extracted():
    data = figure_data(make_figure())
    ax, ax2 = data["axes"]
    assert data["suptitle"] == "run"
    assert (ax["title"], ax["xlabel"], ax["ylabel"], ax["xlim"]) == ("position", "t", "x", [0.0, 2.0])
    assert ax2["xscale"] == "log"
    assert [line["label"] for line in ax["lines"]] == ["part", "table"]
    assert np.isnan(ax["lines"][0]["y"][5]) and len(ax["lines"][0]["x"]) == 41
    kinds = [c["type"] for c in ax["collections"]]
    assert kinds[1] == "PathCollection" and "Poly" in kinds[0]
    assert len(ax["collections"][1]["offsets"]) == 5
    assert [p["type"] for p in ax["patches"]] == ["Rectangle", "Rectangle"]
    assert ax["texts"] == [{"text": "stick", "position": [0.1, 0.2]}]
    mesh = ax2["collections"][0]
    assert np.isnan(mesh["array"][2][3]) and mesh["array"][0][1] == 1.0
    assert ax2["images"][0]["extent"] == [0.0, 4.0, 0.0, 3.0]


def test_one_percent_change_in_line_data_is_detected():
    diffs = compare_figure_data(figure_data(make_figure(scale=1.01)), figure_data(make_figure()))
    assert any(d.startswith("figure.axes[0].lines[0].y:") for d in diffs)
    assert any("collections[0].paths" in d for d in diffs)


def test_change_within_tolerance_is_accepted():
    actual, reference = figure_data(make_figure(scale=1 + 1e-9)), figure_data(make_figure())
    assert compare_figure_data(actual, reference) == []
    assert compare_figure_data(actual, reference, rtol=0, atol=1e-12) != []


def test_changed_label_is_detected():
    diffs = compare_figure_data(figure_data(make_figure(label="object")), figure_data(make_figure()))
    assert diffs == ["figure.axes[0].lines[0].label: 'object' != reference 'part'"]


def test_nan_against_number_and_shape_are_detected():
    reference = figure_data(make_figure())
    actual = figure_data(make_figure(nan=False))
    assert any("lines[0].y: 1 of 41 values differ; at [5]: " in d for d in compare_figure_data(actual, reference))
    actual = copy.deepcopy(reference)
    actual["axes"][0]["lines"][1]["x"].append(3.0)
    assert compare_figure_data(actual, reference) == [
        "figure.axes[0].lines[1].x: shape (42,) != reference (41,)"]
    del actual["axes"][0]["lines"][1]
    assert compare_figure_data(actual, reference) == ["figure.axes[0].lines: 1 entries, reference has 2"]


def test_reference_file_round_trip_is_strict_json(tmp_path):
    data = figure_data(make_figure())
    data["texts"].append({"text": "extremes", "position": [float("inf"), float("-inf")]})
    path = save_reference(data, tmp_path / "ref.json")

    def reject(token):
        raise ValueError(f"non-standard JSON token {token}")
    json.loads(path.read_text(), parse_constant=reject)
    loaded = load_reference(path)
    assert compare_figure_data(loaded, data) == []
    assert loaded["texts"][-1]["position"] == [float("inf"), float("-inf")]


def test_compare_pixels(tmp_path):
    paths = {}
    for name, scale in [("a", 1.0), ("b", 1.0), ("c", 1.5)]:
        paths[name] = tmp_path / f"{name}.png"
        make_figure(scale=scale).savefig(paths[name], dpi=50)
    assert compare_pixels(paths["a"], paths["b"], tol=0.1) is None
    rms = compare_pixels(paths["c"], paths["a"], tol=0.1)
    assert rms is not None and rms > 0.1
    assert compare_pixels(paths["c"], paths["a"], tol=rms * 2) is None
