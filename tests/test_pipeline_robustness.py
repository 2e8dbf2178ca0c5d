"""The pipeline loses nothing (docs/explanation/robustness.md).

Snakemake runs in a temporary copy of ``Snakefile`` + ``workflow/`` (as in
tests/test_workflow.py), on a small fixed set of targets from two stages so that each
run takes seconds: a run killed at a random (seeded) moment leaves only complete result
files and the documented command finishes the rest; a malformed scene or config stops the
run before any job, naming the file and the key; two runs give identical HDF5 files (up to
the datasets marked as measurements).
"""

import os
import random
import signal
import subprocess
import time

import numpy as np
import pytest
from conftest import SNAKEMAKE, copy_workflow
from conftest import run_snakemake as snakemake

from selfalign.io.hdf5 import measured_datasets, read_h5, reproducible_bytes

#: A few jobs of the trajectory and simulation stages (a full run takes minutes).
TARGETS = ["results/trajectory/fig07.h5", "results/trajectory/polynomial.h5",
           "results/simulation/fig09_case1.h5", "results/simulation/fig09_case4.h5",
           "results/simulation/stop_zone.h5", "results/simulation/polynomial.h5"]


def result_files(workdir):
    return sorted(p.relative_to(workdir).as_posix() for p in (workdir / "results").rglob("*.h5"))


def datasets_of(content, prefix=""):
    """Every dataset of a read_h5 result, nested groups included, by path."""
    found = {prefix + name: np.asarray(v) for name, v in content["datasets"].items()}
    for name, group in content["groups"].items():
        found.update(datasets_of(group, f"{prefix}{name}/"))
    return found


def assert_complete(path):
    """A result file opens and holds data (an interrupted write would not)."""
    content = read_h5(path)
    assert content["attrs"]["selfalign_version"], path
    data = datasets_of(content)
    assert any(values.size for values in data.values()), path


@pytest.mark.slow
def test_killed_run_leaves_complete_files_and_the_rerun_finishes(workdir):
    """SIGKILL to the whole process group of `snakemake -c1` while jobs are running — a
    seeded random moment up to 0.3 s after the first result appears, so that later jobs are
    still to come however fast the machine is: every results/**/*.h5 that exists opens and
    is complete (atomic writes, no half-written file under a result name), and
    `snakemake --unlock` followed by `snakemake -c2 --rerun-incomplete` (docs/explanation/robustness.md) builds the
    rest."""
    extra_delay = random.Random(7).uniform(0.0, 0.3)
    proc = subprocess.Popen([*SNAKEMAKE, "-c1", *TARGETS], cwd=workdir, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, start_new_session=True)
    deadline = time.monotonic() + 120
    while not (workdir / "results").exists() or not result_files(workdir):
        assert proc.poll() is None, "snakemake ended before writing any result"
        assert time.monotonic() < deadline, "no result appeared within 120 s"
        time.sleep(0.02)
    time.sleep(extra_delay)
    os.killpg(proc.pid, signal.SIGKILL)
    proc.wait(timeout=30)
    time.sleep(0.2)  # let killed children disappear before reading their directory
    survivors = result_files(workdir) if (workdir / "results").exists() else []
    assert len(survivors) < len(TARGETS), "the run finished before the kill"
    for name in survivors:
        assert_complete(workdir / name)

    rc, out = snakemake(workdir, "--unlock")
    assert rc == 0, out
    rc, out = snakemake(workdir, "-c2", "--rerun-incomplete", *TARGETS)
    assert rc == 0, out
    assert result_files(workdir) == sorted(TARGETS)
    for name in TARGETS:
        assert_complete(workdir / name)


@pytest.mark.slow
def test_identical_inputs_give_identical_files(repo, tmp_path):
    """Two runs of the same targets in two fresh copies give byte-identical HDF5 files once the
    data of the datasets marked as measurements (``stats/cpu_time``) are zeroed in place: no time
    stamps or host names anywhere; and the datasets themselves are bit-identical but for those."""
    runs = []
    for copy in ("a", "b"):
        work = tmp_path / copy
        work.mkdir()
        copy_workflow(repo, work)
        rc, out = snakemake(work, "-c2", *TARGETS)
        assert rc == 0, out
        runs.append(work)
    a, b = runs
    for name in TARGETS:
        assert reproducible_bytes(a / name) == reproducible_bytes(b / name), name
        x, y = datasets_of(read_h5(a / name)), datasets_of(read_h5(b / name))
        assert x.keys() == y.keys(), name
        measured = set(measured_datasets(a / name))
        assert measured == ({"stats/cpu_time"} if name.startswith("results/simulation/") else set()), name
        for key in x.keys() - measured:
            assert x[key].dtype == y[key].dtype and x[key].shape == y[key].shape, (name, key)
            assert x[key].tobytes() == y[key].tobytes(), (name, key)


@pytest.mark.parametrize("old, new, key", [
    ("dt: 0.05", "dt: .nan", "profile.dt"),
    ("horizon: {periods: 3}", "horizon: {periods: 0}", "horizon.periods"),
])
def test_malformed_scene_stops_before_any_job(workdir, old, new, key):
    """A scene with a non-finite or out-of-range value stops the run at parse time with one
    message naming the scene file and the key; nothing is written."""
    scene = workdir / "workflow/scenes/polynomial.yaml"
    assert old in scene.read_text()
    scene.write_text(scene.read_text().replace(old, new))
    rc, out = snakemake(workdir, "-c2", *TARGETS)
    assert rc != 0
    assert f"workflow/scenes/polynomial.yaml: {key}" in out, out
    assert not (workdir / "results").exists()


@pytest.mark.parametrize("old, new, keys", [
    ("dpi: 300", "dpi: -300", ("figures.dpi", "['figures']['dpi']")),
    ("scenes_dir: workflow/scenes", "scenez_dir: workflow/scenes", ("scenez_dir",)),
])
def test_malformed_config_stops_before_any_job(workdir, old, new, keys):
    """A config value out of range, or a misspelt key, stops the run before any job with a
    message naming the config file and the key; nothing is written."""
    config = workdir / "workflow/config/config.yaml"
    assert old in config.read_text()
    config.write_text(config.read_text().replace(old, new))
    rc, out = snakemake(workdir, "-c2", *TARGETS)
    assert rc != 0
    assert "workflow/config/config.yaml" in out, out
    assert any(key in out for key in keys), out
    assert not (workdir / "results").exists()


def test_bad_command_line_override_is_named(workdir):
    """A bad value given with --config is reported as that override (not as the
    config file, which is fine), before any job."""
    rc, out = snakemake(workdir, "-c2", *TARGETS, "--config", "figures={dpi: -1}")
    assert rc != 0
    assert "override --config figures.dpi" in out, out
    assert "workflow/config/config.yaml" not in out.split("invalid config:")[1].splitlines()[0], out
    assert not (workdir / "results").exists()


def test_bad_solver_option_in_a_scene_stops_before_any_job(workdir):
    """A scene's solver options are checked when the scene is loaded, so a bad one
    stops the run (here: a Moreau step that needs 1e300 steps per period) before any job,
    naming the scene file, instead of failing inside the simulation job."""
    scene = workdir / "workflow/scenes/polynomial.yaml"
    text = scene.read_text()
    assert "solver:" not in text
    scene.write_text(text + "solver: {method: moreau, options: {h: 1.0e-300}}\n")
    rc, out = snakemake(workdir, "-c2", *TARGETS)
    assert rc != 0
    assert "workflow/scenes/polynomial.yaml: solver: option h = 1e-300 needs" in out, out
    assert not (workdir / "results").exists()


def test_config_naming_a_missing_scene_stops_before_any_job(workdir):
    """A config that names a scene without a file stops the run before any job, naming the
    missing scene file."""
    config = workdir / "workflow/config/config.yaml"
    config.write_text(config.read_text().replace("scenes: [fig07,", "scenes: [no_such_scene, fig07,", 1))
    rc, out = snakemake(workdir, "-c2", *TARGETS)
    assert rc != 0
    assert "workflow/scenes/no_such_scene.yaml" in out, out
    assert not (workdir / "results").exists()
