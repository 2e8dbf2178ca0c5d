"""The classification stage of the workflow (Figs. 4-6, 8, 10, 11): sharded (y2'', y3'') maps,
the design rules of Sect. 5.2 checked on the maps the stage computes, Fig. 8 drawn from the
decision tree, and the stage's Snakemake plan."""

import shutil
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import yaml
from figcheck import figure_data
from matplotlib.colors import to_rgb

from selfalign.analysis.classification import CASE_LABELS, DECISION_TREE, Decision, DecisionTree
from selfalign.io.hdf5 import read_h5, write_h5
from selfalign.plots.classification import figure_08, question_text, tree_layout
from selfalign.plots.style import CASE_COLORS, print_check
from selfalign.stages.classification import MAP_FIELDS, gather_map, map_shard
from selfalign.stages.common import shard_rows

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def stage():
    return yaml.safe_load((REPO / "workflow/config/config.yaml").read_text())["stages"]["classification"]


def axes(spec):
    return (np.linspace(spec[k]["from"], spec[k]["to"], spec[k]["count"]) for k in ("y2", "y3"))


@pytest.fixture(scope="module")
def maps(stage):
    """The closed-form maps of Figs. 10, 11 on the stage's own axes (no simulation)."""
    out = {}
    for name, spec in stage["maps"].items():
        y2, y3 = axes(spec)
        shard = map_shard(spec["dt"], spec["dy"], y2, y3, slice(0, y2.size), simulate=False)
        out[name], _ = gather_map(spec["dt"], spec["dy"], y2, y3, [shard])
    return out


@pytest.mark.parametrize("rows, shards", [(161, 4), (7, 3), (5, 5), (3, 4), (1, 1)])
def test_shard_rows_partition_the_map(rows, shards):
    """Shards are contiguous row blocks that cover every row once, sizes within one (a shard
    may be empty when there are more shards than rows)."""
    parts = [shard_rows(rows, shards, i) for i in range(shards)]
    covered = np.concatenate([np.arange(rows)[p] for p in parts])
    np.testing.assert_array_equal(covered, np.arange(rows))
    sizes = [p.stop - p.start for p in parts]
    assert max(sizes) - min(sizes) <= 1
    with pytest.raises(ValueError, match="shard index"):
        shard_rows(rows, shards, shards)
    with pytest.raises(ValueError, match="shards must be an integer >= 1"):
        shard_rows(rows, 0, 0)


def test_gathered_map_is_identical_for_one_and_four_shards(tmp_path):
    """The gathered HDF5 datasets (case, vbar, f, vbar_simulated and the axes) are
    bit-for-bit the same whether the map is computed in 1 or in 4 shards (the stage's steps,
    through HDF5 files)."""
    dt, dy = 0.072, 0.021
    y2, y3 = np.linspace(20.0, 1500.0, 10), np.linspace(20.0, 300.0, 9)
    gathered = {}
    for shards in (1, 4):
        paths = []
        for i in range(shards):
            rows = shard_rows(y2.size, shards, i)
            paths.append(write_h5(tmp_path / f"{shards}_{i}.h5", map_shard(dt, dy, y2, y3, rows)))
        data, attrs = gather_map(dt, dy, y2, y3, [read_h5(p)["datasets"] for p in paths])
        gathered[shards] = read_h5(write_h5(tmp_path / f"map{shards}.h5", data, attrs))
    one, four = gathered[1], gathered[4]
    assert set(one["datasets"]) == {"y2", "y3", *MAP_FIELDS} == set(four["datasets"])
    for name, values in one["datasets"].items():
        np.testing.assert_array_equal(four["datasets"][name], values)
        assert four["datasets"][name].dtype == values.dtype
    assert one["attrs"] == four["attrs"] and one["attrs"]["dt"] == dt and one["attrs"]["dy"] == dy
    assert one["datasets"]["case"].shape == (10, 9) and one["datasets"]["case"].dtype == np.int8


def test_maps_show_every_case_and_boundary(maps):
    """Sect. 5.2: the chosen axes of Fig. 10 show cases 0 (no profile), 3 and 4 with both
    boundaries of the slip-slip band, which separates general stick-slip from case 0; those of
    Fig. 11 cases 0, 1, 2, 3, 5 with all four corners around y2'' = y3'' = 1 (no slip-slip
    exists there)."""
    def neighbours(case):
        pairs = set()
        for a, b in ((case[1:], case[:-1]), (case[:, 1:], case[:, :-1])):
            diff = a != b
            pairs |= {tuple(sorted(p)) for p in zip(a[diff].tolist(), b[diff].tolist())}
        return pairs
    assert set(np.unique(maps["fig10"]["case"])) == {0, 3, 4}
    assert neighbours(maps["fig10"]["case"]) == {(0, 4), (3, 4)}
    assert set(np.unique(maps["fig11"]["case"])) == {0, 1, 2, 3, 5}
    assert {(1, 3), (2, 3), (2, 5), (1, 5), (0, 1), (0, 2), (0, 5)} <= neighbours(maps["fig11"]["case"])


def test_slip_slip_is_much_worse_than_the_neighbouring_stick_slip(maps):
    """Sect. 5.2 (Fig. 10): f increases dramatically from general stick-slip into slip-slip.
    On every y2'' row of the Fig. 10 map that crosses the 3/4 boundary the largest f of case
    4 exceeds 10x the largest f of case 3 (and case 3 stays below the paper's colour limit
    f = 1.6e-3), and the best f of the map is a case-3 point next to case 4."""
    d = maps["fig10"]
    rows = 0
    for case, f in zip(d["case"], d["f"]):
        if (case == 3).any() and (case == 4).any():
            rows += 1
            assert f[case == 4].max() > 10 * f[case == 3].max()
    assert rows > 100
    assert d["f"][d["case"] == 3].max() < 1.6e-3
    i, j = np.unravel_index(np.nanargmin(d["f"]), d["f"].shape)
    assert d["case"][i, j] == 3 and 4 in d["case"][max(i - 1, 0):i + 2, max(j - 1, 0):j + 2]


def test_design_rules_on_the_small_acceleration_map(maps):
    """Sect. 5.2 (Fig. 11) and Table 1: case 1 moves forward (vbar > 0), case 2 backward
    (vbar < 0), case 5 not at all (vbar = 0, f = inf); among forward-moving points the
    smallest f is a case 1 point ("case 1 solutions seem preferable")."""
    d = maps["fig11"]
    case, vbar, f = d["case"], d["vbar"], d["f"]
    assert np.all(vbar[case == 1] > 0) and np.all(vbar[case == 2] < 0)
    assert np.all(vbar[case == 5] == 0) and np.all(np.isinf(f[case == 5]))
    forward = np.where(vbar > 0, f, np.inf)
    assert case.flat[np.argmin(forward)] == 1


def test_fig08_is_drawn_from_the_decision_tree():
    """Fig. 8 walks the tree that classifies the maps: every decision's question, every case
    of Table 1, one yes/no label per edge and one arrow per edge appear, leaves in their map
    colour; the layout puts every child one level below its parent; the chart is two columns
    wide (174 mm) with no text below 7 pt (the figure standard)."""
    fig = figure_08()
    assert print_check(fig) == [] and round(fig.get_figwidth() * 25.4) == 174
    ax_texts = [t for t in fig.axes[0].texts]
    texts = [t.get_text() for t in ax_texts]
    arrows = [t for t in ax_texts if t.get_text() == "" and t.arrow_patch is not None]
    for node_id, attrs in DECISION_TREE.nodes():
        if attrs["kind"] == "decision":
            assert any(t.replace("\n", " ").startswith(question_text(attrs["label"]).rstrip("?")) for t in texts)
        else:
            box = next(t for t in ax_texts if t.get_text().startswith(f"case {attrs['case']}\n"))
            assert box.get_bbox_patch().get_facecolor()[:3] == pytest.approx(to_rgb(CASE_COLORS[attrs["case"]]))
    edges = DECISION_TREE.edges()
    assert len(arrows) == len(edges)
    assert sorted(t for t in texts if t in ("yes", "no")) == sorted(label for *_, label in edges)
    pos = tree_layout(DECISION_TREE)
    assert all(pos[child][1] == pos[parent][1] + 1 for parent, child, _ in edges)
    assert len(CASE_LABELS) == sum(1 for _, a in DECISION_TREE.nodes() if a["kind"] == "case")


def test_fig08_changes_with_the_tree():
    """The figure cannot disagree with the code: swapping the branches of one decision
    swaps the drawn boxes (different figure data)."""
    node = DECISION_TREE["restick"]
    swapped = DecisionTree(DECISION_TREE.root, [replace(node, yes=node.no, no=node.yes) if n == "restick"
                                                 else DECISION_TREE[n] for n, _ in DECISION_TREE.nodes()])
    assert isinstance(node, Decision)
    assert figure_data(figure_08(swapped)) != figure_data(figure_08())


@pytest.fixture
def workdir(tmp_path):
    """A runnable copy of the workflow (results are not needed for a dry run)."""
    shutil.copy(REPO / "Snakefile", tmp_path / "Snakefile")
    shutil.copytree(REPO / "workflow", tmp_path / "workflow")
    return tmp_path


def test_dry_run_plans_one_job_per_shard(workdir):
    """The shard count is a config value: with `shards: 3` the stage plans 3 shard jobs per map,
    gathered into fig10.h5 and fig11.h5, checked by verify_maps, and every figure."""
    config = workdir / "workflow/config/config.yaml"
    text = config.read_text()
    assert text.count("        shards: 1\n") == 2
    config.write_text(text.replace("        shards: 1\n", "        shards: 3\n"))
    proc = subprocess.run([sys.executable, "-m", "snakemake", "-n", "-c1", "--quiet", "rules"], cwd=workdir,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    out = proc.stdout + proc.stderr
    counts = dict(line.split()[:2] for line in out.splitlines() if len(line.split()) == 2
                  and line.split()[1].isdigit())
    assert counts["compute_map_shard"] == "6" and counts["gather_map"] == "2"
    for rule in ("verify_maps", "optimise_fourier", "plot_fig08", "plot_fig10", "plot_fig11"):
        assert counts[rule] == "1"
    assert counts["compute_sweep"] == "2"
