"""The accumulation stage of the workflow: the Fig. 17 sweep computed in shards
(rules compute_positioning_shard, gather_positioning) and gathered into
results/accumulation/fig17.h5."""

from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import run_snakemake

from selfalign.io.hdf5 import read_h5, write_h5
from selfalign.stages.accumulation import FIG17_FIELDS, fig17_content, fig17_shard, gather_fig17
from selfalign.stages.common import shard_rows

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def stage():
    return yaml.safe_load((REPO / "workflow/config/config.yaml").read_text())["stages"]["accumulation"]


def setting(stage, entries=4, max_periods=200):
    """The stage's own setting with few entries and periods, and a coarse 5 x 4 grid over its axes
    (y2'' up to 2.5 reaches accumulation, never-stop and undecided entries)."""
    p, zone = stage["positioning"], stage["zone"]
    kw = dict(dt=p["dt"], dy=p["dy"], w=zone["w"], c_mu=zone["c_mu"], n_entries=entries,
              max_periods=max_periods, levels=p["levels"])
    return (np.linspace(p["y2"]["from"], p["y2"]["to"], 5), np.linspace(p["y3"]["from"], p["y3"]["to"], 4), kw)


def shards_of(y2, y3, shards, kw, interleaved=True):
    """The shards of the sweep in memory, as read_h5 would return them."""
    return [dict(zip(("datasets", "attrs"), fig17_shard(y2, y3, shard_rows(y2.size, shards, i, interleaved=interleaved),
                                                        **kw))) for i in range(shards)]


@pytest.mark.parametrize("rows, shards", [(101, 2), (7, 3), (5, 5), (3, 4), (1, 1)])
def test_interleaved_shard_rows_partition_the_sweep(rows, shards):
    """Interleaved shards take every shards-th row: together they cover every row once, sizes
    within one (a shard may be empty when there are more shards than rows)."""
    parts = [shard_rows(rows, shards, i, interleaved=True) for i in range(shards)]
    covered = np.concatenate([np.arange(rows)[p] for p in parts])
    np.testing.assert_array_equal(np.sort(covered), np.arange(rows))
    sizes = [np.arange(rows)[p].size for p in parts]
    assert max(sizes) - min(sizes) <= 1
    with pytest.raises(ValueError, match="shard index"):
        shard_rows(rows, shards, shards, interleaved=True)


@pytest.mark.parametrize("interleaved", [True, False])
def test_gathered_fig17_is_identical_for_one_and_four_shards(stage, tmp_path, interleaved):
    """The gathered fig17.h5 datasets (every field, the axes and levels) and attributes are
    bit-for-bit the same whether the sweep is computed in 1 or in 4 shards (interleaved as in
    the workflow, or contiguous), through HDF5 files as in the stage; 4 shards of 5 rows
    include an empty one in neither layout but uneven ones in both."""
    y2, y3, kw = setting(stage)
    gathered = {}
    for shards in (1, 4):
        paths = []
        for i in range(shards):
            rows = shard_rows(y2.size, shards, i, interleaved=interleaved)
            paths.append(write_h5(tmp_path / f"{shards}_{i}.h5", *fig17_shard(y2, y3, rows, **kw)))
        data, attrs = gather_fig17(y2, y3, [read_h5(p) for p in paths])
        gathered[shards] = read_h5(write_h5(tmp_path / f"fig17_{shards}.h5", data, attrs))
    one, four = gathered[1], gathered[4]
    assert set(one["datasets"]) == {"y2", "y3", "levels", *FIG17_FIELDS} == set(four["datasets"])
    for name, values in one["datasets"].items():
        assert four["datasets"][name].dtype == values.dtype
        assert four["datasets"][name].tobytes() == values.tobytes(), name
    assert one["attrs"] == four["attrs"] and one["attrs"]["events"] > 0
    assert "row_start" not in one["attrs"]
    # The coarse grid reaches the zone's outcomes, so the comparison is not one of empty arrays.
    d = one["datasets"]
    assert d["case"].shape == (5, 4) and d["level_sticks"].shape == (5, 4, len(stage["positioning"]["levels"]))
    assert np.nanmax(d["frac_accumulate"]) > 0 and np.nanmax(d["frac_never_stop"]) > 0


def test_fig17_content_equals_the_gathered_shards(stage):
    """fig17_content (the unsharded library call) gives the datasets and attributes of the
    workflow's two interleaved shards gathered."""
    y2, y3, kw = setting(stage, entries=2, max_periods=50)
    data, attrs = fig17_content(y2, y3, **kw)
    sharded, sattrs = gather_fig17(y2, y3, shards_of(y2, y3, 2, kw))
    assert attrs == sattrs
    for name, values in data.items():
        np.testing.assert_array_equal(sharded[name], values)


def test_gather_rejects_missing_repeated_or_mismatched_shards(stage):
    """A gather that would silently drop or duplicate rows, or mix settings, is refused."""
    y2, y3, kw = setting(stage, entries=2, max_periods=50)
    parts = shards_of(y2, y3, 2, kw, interleaved=False)
    with pytest.raises(ValueError, match="exactly once"):
        gather_fig17(y2, y3, parts[:1])
    with pytest.raises(ValueError, match="exactly once"):
        gather_fig17(y2, y3, [parts[0], parts[0]])
    other = shards_of(y2, y3, 2, {**kw, "c_mu": 3.0}, interleaved=False)[1]
    with pytest.raises(ValueError, match="another setting"):
        gather_fig17(y2, y3, [parts[0], other])
    with pytest.raises(ValueError, match="no shards"):
        gather_fig17(y2, y3, [])


def planned_jobs(workdir, *targets):
    """{rule: job count} of a dry run for ``targets``."""
    rc, out = run_snakemake(workdir, "-n", "-c1", *targets, "--quiet", "rules")
    assert rc == 0, out
    return {line.split()[0]: int(line.split()[1]) for line in out.splitlines()
            if len(line.split()) == 2 and line.split()[1].isdigit() and line.split()[0] != "total"}


@pytest.mark.slow
def test_changing_one_study_reruns_that_study_only(workdir):
    """Each rule gets only its own settings, so changing the Fig. 18 map's point count
    reruns the Fig. 18 map alone (not the Fig. 17 shards), and changing the Fig. 17 entries
    reruns the Fig. 17 shards and their gather alone.  Run on a tiny sweep in a copy of the
    workflow."""
    config_file = workdir / "workflow/config/config.yaml"
    config = yaml.safe_load(config_file.read_text())
    accumulation = config["stages"]["accumulation"]
    for axis in ("y2", "y3"):
        accumulation["positioning"][axis]["count"] = 3
    accumulation["positioning"].update(n_entries=2, max_periods=20)
    accumulation["stick_map"]["points"] = 5
    config_file.write_text(yaml.safe_dump(config))
    targets = ["results/accumulation/fig17.h5", "results/accumulation/fig18.h5"]
    rc, out = run_snakemake(workdir, "-c2", *targets)
    assert rc == 0, out
    assert planned_jobs(workdir, *targets) == {}

    accumulation["stick_map"]["points"] = 7
    config_file.write_text(yaml.safe_dump(config))
    assert planned_jobs(workdir, *targets) == {"compute_stick_map": 1}

    accumulation["stick_map"]["points"] = 5
    accumulation["positioning"]["n_entries"] = 3
    config_file.write_text(yaml.safe_dump(config))
    assert planned_jobs(workdir, *targets) == {"compute_positioning_shard": 2, "gather_positioning": 1}
