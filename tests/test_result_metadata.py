"""Every result file describes itself (docs/reference/results.md): each dataset carries
``units`` and ``description`` (coded ones a ``legend``, SI scenes the SI unit), each file its
provenance (package version, git commit, the scene or config that made it), and write_h5
refuses a dataset nobody documented.
"""

import re
from pathlib import Path

import numpy as np
import pytest
import yaml

import selfalign
from selfalign import load_scene
from selfalign.io import quantities
from selfalign.io.hdf5 import (
    COMMIT_ATTR,
    SOURCE_ATTRS,
    VERSION_ATTR,
    read_dataset_attrs,
    read_h5,
    source_commit,
    write_h5,
)
from selfalign.solvers.outcomes import EventKind
from selfalign.stages.trajectory import profile_samples


def test_write_h5_refuses_an_undocumented_dataset(tmp_path):
    """A dataset name missing from the registry, at the root or in a group, stops the write
    with an error naming the dataset, and no file is left behind."""
    for content, path in [(({"t": [1.0], "flux": [2.0]},), "/flux"),
                          (({}, {}, {"series": {"datasets": {"t": [0.0], "flux": [1.0]}}}), "/series/flux")]:
        with pytest.raises(ValueError, match=f"dataset '{path}' has no units and description"):
            write_h5(tmp_path / "a.h5", *content)
        assert not list(tmp_path.iterdir())


def test_group_overrides_and_patterns_pick_the_scoped_quantity():
    """A dataset is looked up by '<group>/<name>' first (patterns like entry_*/t included), then
    by its name: `status` is a code in a Fig. 16 setting group but text in the accuracy groups."""
    assert quantities.quantity("/y2_2.3_y3_1.3/status").kind == "code"
    assert quantities.quantity("/moreau/status").kind == "text"
    assert quantities.quantity("/y2_2.3_y3_1.3/entry_1/t").description.startswith("time t of the entry")
    assert quantities.quantity("/t").description == "time t of each sample"


def test_legend_round_trips_and_values_are_unchanged(tmp_path):
    """Coded datasets keep their numpy values and dtype through write_h5/read_h5, and their
    `legend` attribute reads back as code -> name (event kinds, modes)."""
    kinds = np.array([0, 1, 2, 4, 3], dtype=np.int8)
    modes = np.array([-1, 0, 1, 0, 1], dtype=np.int8)
    path = write_h5(tmp_path / "e.h5", {}, {"scene": "name: x\n"},
                    {"events": {"datasets": {"kind": kinds, "mode": modes}}})
    back = read_h5(path)["groups"]["events"]["datasets"]
    assert back["kind"].dtype == np.int8 and back["kind"].tobytes() == kinds.tobytes()
    assert back["mode"].dtype == np.int8 and back["mode"].tobytes() == modes.tobytes()
    attrs = read_dataset_attrs(path)
    assert attrs["events/kind"]["legend"] == {str(int(k)): k.name for k in EventKind}
    assert attrs["events/mode"]["legend"] == {"-1": "backward slip", "0": "stick", "1": "forward slip"}
    assert attrs["events/kind"]["units"] == "1 (code; see legend)"


def test_si_scene_datasets_state_their_si_unit(repo, tmp_path):
    """A scene with an SI scale gives each dataset of one dimension `si_units` and `si_factor` =
    the SI value of one model unit (SIScale.unit); a dimensionless scene gives neither."""
    scene = load_scene(repo / "workflow/scenes/si_example.yaml")
    attrs = read_dataset_attrs(write_h5(tmp_path / "si.h5", *profile_samples(scene)))
    for name, kind, symbol in [("t", "time", "s"), ("y", "length", "m"), ("yd", "velocity", "m/s"),
                               ("ydd", "acceleration", "m/s^2")]:
        assert attrs[name]["si_units"] == symbol
        assert attrs[name]["si_factor"] == pytest.approx(scene.si.unit(kind), rel=1e-15)
    assert attrs["ydd"]["si_factor"] == pytest.approx(scene.si.mu * scene.si.g)  # L / T^2 = mu g
    plain = read_dataset_attrs(write_h5(tmp_path / "plain.h5",
                                        *profile_samples(load_scene(repo / "workflow/scenes/fig07.yaml"))))
    assert not any("si_units" in a for a in plain.values())


def test_provenance_config_is_yaml_and_reserved_names_are_refused(tmp_path):
    """`config` is stored as YAML text that loads back to the same mapping; passing the
    attributes write_h5 sets itself is refused."""
    config = {"map": {"dt": 0.072, "y2": {"from": 20.0, "to": 1500.0, "count": 3, "scale": "linear"}}}
    got = read_h5(write_h5(tmp_path / "c.h5", {"y2": [1.0]}, config=config))["attrs"]
    assert yaml.safe_load(got["config"]) == config
    assert got[VERSION_ATTR] == selfalign.__version__ and got[COMMIT_ATTR] == source_commit()
    for reserved in (VERSION_ATTR, COMMIT_ATTR):
        with pytest.raises(ValueError, match=f"'{reserved}'"):
            write_h5(tmp_path / "d.h5", {}, {reserved: "x"})
    with pytest.raises(ValueError, match="'config'"):
        write_h5(tmp_path / "d.h5", {}, {"config": "x"}, config=config)


def test_source_commit_names_this_checkout(repo):
    """In a git checkout the commit is HEAD's 40 hex digits, with -dirty when tracked files differ."""
    if not (repo / ".git").exists():
        pytest.skip("not running from a git checkout")
    assert re.fullmatch(r"[0-9a-f]{40}(-dirty)?", source_commit())


def writer_scripts(repo: Path) -> dict[str, str]:
    """Rule name -> script for every rule whose script writes a result with write_h5."""
    scripts = {}
    for smk in (repo / "workflow/rules").glob("*.smk"):
        for rule in re.split(r"^rule ", smk.read_text(), flags=re.M)[1:]:
            script = re.search(r"^    script:\s*\n\s*\"\.\./scripts/(\w+\.py)\"", rule, flags=re.M)
            if script and "write_h5(" in (repo / "workflow/scripts" / script[1]).read_text():
                scripts[rule.split(":", 1)[0]] = script[1]
    return scripts


def test_every_result_of_a_small_pipeline_run_is_self_describing(repo, small_pipeline):
    """A run of every stage on a shrunk config (every rule that writes HDF5 runs at least once)
    leaves no dataset without units and description, no coded integer dataset without a
    legend, and no file without version, commit and the scene or config it was made from."""
    workdir, targets, rc, out = small_pipeline
    assert rc == 0, out
    ran = set(re.findall(r"^(?:local)?rule (\w+):", out, flags=re.M))
    missing = set(writer_scripts(repo)) - ran
    assert not missing, f"rules writing HDF5 that the run did not cover: {sorted(missing)}"

    files = sorted((workdir / "results").rglob("*.h5"))
    assert not [t for t in targets if not (workdir / t).is_file()], out
    assert len(files) > len(targets)  # the shards too
    for path in files:
        attrs = read_h5(path)["attrs"]
        name = path.relative_to(workdir)
        assert attrs[VERSION_ATTR] == selfalign.__version__, name
        assert attrs[COMMIT_ATTR] == source_commit(), name
        sources = [key for key in SOURCE_ATTRS if isinstance(attrs.get(key), str) and yaml.safe_load(attrs[key])]
        assert len(sources) == 1, (name, sources)
        for dataset, meta in read_dataset_attrs(path).items():
            assert meta.get("units") and meta.get("description"), (name, dataset, meta)
            if meta["units"].startswith("1 (code"):
                assert meta["legend"], (name, dataset)
