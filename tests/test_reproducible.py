"""Results are reproducible (docs/reference/results.md): measured values never identify a result.

Hypotheses:

* two runs of one scene give one rerun recording id (a hash of what the recording shows,
  :func:`selfalign.io.recording.content_id`) and recordings equal by content; rerun itself
  stamps random chunk ids and a start time into every file, so the recordings are compared as
  read back, not as bytes;
* two writes of one result give HDF5 files that are byte-identical once the data of the
  datasets marked ``measurement = True`` are zeroed in place
  (:func:`selfalign.io.hdf5.reproducible_bytes`); every CPU or wall-clock time, and every
  number computed from one, is such a dataset (never an attribute);
* a write killed with SIGKILL leaves its temporary file, named for its process; the next
  write to the same target removes it, and leaves the temporary file of a live writer alone.
"""

import os
import re
import signal
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest
from conftest import REPO, copy_workflow, run_small_pipeline
from rerun.chunk import RrdReader

from selfalign import load_scene, simulate
from selfalign.analysis.accuracy import StudySettings, study
from selfalign.io import hdf5, quantities
from selfalign.io.hdf5 import (
    measured_datasets,
    read_dataset_attrs,
    read_h5,
    remove_stale_temporaries,
    reproducible_bytes,
    write_h5,
)
from selfalign.io.recording import content_id, read_documents, read_logs, read_recording
from selfalign.io.simulation_result import simulation_recording, trajectory_content

#: Names of measured values: CPU and wall-clock times and what is computed from them.
MEASURED_NAME = re.compile(r"cpu|seconds|wall|per_second|speed_ratio")
#: The accuracy study on settings that take a fraction of a second.
TINY = StudySettings(moreau_steps_per_period=(10, 1000, 3), ivp_rtol=(1e-3, 1e-5, 2), fit_min_steps_per_period=10,
                     min_timing=1e-3)


def selfalign_cli(*args, cwd):
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))}
    return subprocess.run([sys.executable, "-m", "selfalign", *args], cwd=cwd, env=env, capture_output=True,
                          text=True, timeout=300)


def recording_ids(path) -> list[str]:
    return [entry.recording_id for entry in RrdReader(path).recordings()]


def assert_same_recording_content(a, b):
    """Series, markers, logs and documents of two rrd files are equal, bit for bit."""
    first, second = read_recording(a), read_recording(b)
    assert first.keys() == second.keys()
    for name, (times, values) in first.items():
        assert times.tobytes() == second[name][0].tobytes() and values.tobytes() == second[name][1].tobytes(), name
    logs = [{k: (v.times.tobytes(), v.texts, v.levels) for k, v in read_logs(p).items()} for p in (a, b)]
    assert logs[0] == logs[1]
    assert read_documents(a) == read_documents(b)


def test_two_runs_of_the_cli_give_one_recording_and_one_result(repo, tmp_path):
    """`selfalign simulate stop_zone.yaml --rerun r.rrd -o r.h5` twice (two processes, so two CPU
    times): the same recording id, recordings equal by content, and result files equal up to the
    one measured dataset, stats/cpu_time."""
    for run in ("a", "b"):
        out = selfalign_cli("simulate", str(repo / "workflow/scenes/stop_zone.yaml"), "--rerun", f"{run}.rrd",
                            "-o", f"{run}.h5", cwd=tmp_path)
        assert out.returncode == 0, out.stderr
    a, b = recording_ids(tmp_path / "a.rrd"), recording_ids(tmp_path / "b.rrd")
    assert a == b and len(a) == 1
    assert_same_recording_content(tmp_path / "a.rrd", tmp_path / "b.rrd")
    assert measured_datasets(tmp_path / "a.h5") == ["stats/cpu_time"]
    assert reproducible_bytes(tmp_path / "a.h5") == reproducible_bytes(tmp_path / "b.h5")
    # the measured value is still there, read back as it was stored
    for run in ("a", "b"):
        assert float(read_h5(tmp_path / f"{run}.h5")["groups"]["stats"]["datasets"]["cpu_time"]) > 0


def test_measured_values_do_not_enter_the_recording_id(repo):
    """The recording of a result is the same whatever the CPU time stored with it."""
    scene = load_scene(repo / "workflow/scenes/stop_zone.yaml")
    datasets, attrs, groups = trajectory_content(simulate(scene), scene)
    ids = set()
    for cpu_time in (0.0, 1.0, 1e9):
        changed = {**groups, "stats": {**groups["stats"], "datasets": {"cpu_time": np.float64(cpu_time)}}}
        ids.add(content_id(simulation_recording({"datasets": datasets, "attrs": attrs, "groups": changed})))
    assert len(ids) == 1


def test_reproducible_bytes_zero_only_the_measured_data(tmp_path):
    """Two files that differ only in a measured value have the same reproducible bytes; a change of
    any other stored number is still seen (here one ulp of one sample of t)."""
    t = np.linspace(0.0, 1.0, 5)
    written = [write_h5(tmp_path / f"{i}.h5", {}, {}, {"stats": {"attrs": {"events": 3},
                                                                 "datasets": {"cpu_time": np.float64(cpu)}},
                                                       "series": {"datasets": {"t": times}}})
               for i, (cpu, times) in enumerate([(0.25, t), (7.5, t), (0.25, np.nextafter(t, 2.0))])]
    raw = [path.read_bytes() for path in written]
    assert raw[0] != raw[1]
    assert reproducible_bytes(written[0]) == reproducible_bytes(written[1])
    assert reproducible_bytes(written[0]) != reproducible_bytes(written[2])
    with h5py.File(written[1]) as f:  # only the 8 bytes of the value were zeroed
        offset = f["stats/cpu_time"].id.get_offset()
    assert reproducible_bytes(written[1])[offset:offset + 8] == bytes(8)
    assert raw[1][:offset] == reproducible_bytes(written[1])[:offset]


def test_accuracy_study_is_reproducible_apart_from_its_marked_cpu_times(repo, tmp_path):
    """The work-precision study of one scene run twice: files equal up to the CPU times and the
    numbers computed from them, which are exactly the datasets marked as measurements."""
    scene = load_scene(repo / "workflow/scenes/accuracy_steady.yaml")
    paths = [write_h5(tmp_path / f"{run}.h5", *study(scene, TINY, progress="quiet")) for run in ("a", "b")]
    assert measured_datasets(paths[0]) == sorted(
        ["exact/cpu_time", "exact/events_run_cpu_time", "exact_events_per_second", "ivp/cpu_time",
         "moreau/cpu_time", "moreau_cpu_at_target", "speed_ratio_at_target"])
    assert reproducible_bytes(paths[0]) == reproducible_bytes(paths[1])


def test_every_time_quantity_is_a_marked_measurement():
    """Every documented dataset named for a CPU or wall-clock time (or a rate or ratio of one) is a
    measurement, and the kinds of measured values cannot be declared otherwise; a measurement
    says so in its description."""
    named = {key for key in quantities.QUANTITIES if MEASURED_NAME.search(key.rsplit("/", 1)[-1])}
    assert {"stats/cpu_time", "moreau/cpu_time", "ivp/cpu_time", "exact/cpu_time", "design_seconds"} <= named
    for key, found in quantities.QUANTITIES.items():
        assert found.measurement == (key in named or found.kind in quantities.MEASURED_KINDS), key
        attrs = found.attrs()
        assert attrs.get(quantities.MEASUREMENT_ATTR, False) is found.measurement, key
        assert attrs["description"].endswith(quantities.MEASUREMENT_NOTE) is found.measurement, key
    for kind in quantities.MEASURED_KINDS:
        with pytest.raises(ValueError, match=f"kind '{kind}' is measured: pass measurement=True"):
            quantities.Quantity(kind, "a time")


KILLED_WRITER = """
import sys, time
from pathlib import Path
import h5py, numpy as np
from selfalign.io.hdf5 import atomic_write

def writer(tmp):
    with h5py.File(tmp, "w") as f:
        f["t"] = np.zeros(100_000)
        f.flush()
        print(tmp, flush=True)
        time.sleep(300)

atomic_write(Path(sys.argv[1]), writer)
"""


def test_next_write_removes_the_temporary_file_of_a_killed_writer(tmp_path):
    """Two processes write out.h5 and stop halfway; one is killed with SIGKILL (its temporary file
    stays: nothing can remove it then).  The next write to out.h5 removes that file, keeps the
    live writer's, and leaves a complete result; once that writer is killed too, the write after
    leaves nothing but out.h5."""
    target = tmp_path / "out.h5"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))}
    writers, temporaries = [], []
    try:
        for _ in range(2):
            proc = subprocess.Popen([sys.executable, "-c", KILLED_WRITER, str(target)], stdout=subprocess.PIPE,
                                    text=True, env=env)
            writers.append(proc)
            temporaries.append(Path(proc.stdout.readline().strip()))
        for proc, tmp in zip(writers, temporaries):
            assert tmp.parent == tmp_path and tmp.is_file(), tmp
            assert re.fullmatch(rf"\.out\.h5\.[A-Za-z0-9-]+\.{proc.pid}\.[0-9a-f]+\.tmp", tmp.name), tmp.name
        killed, alive = writers
        killed.kill()
        killed.wait(timeout=30)
        assert killed.returncode == -signal.SIGKILL and temporaries[0].exists()

        write_h5(target, {"t": [1.0, 2.0]})
        assert sorted(p.name for p in tmp_path.iterdir()) == sorted([target.name, temporaries[1].name])
        assert read_h5(target)["datasets"]["t"].tolist() == [1.0, 2.0]

        alive.kill()
        alive.wait(timeout=30)
        write_h5(target, {"t": [3.0]})
        assert [p.name for p in tmp_path.iterdir()] == [target.name]
    finally:
        for proc in writers:
            if proc.poll() is None:
                proc.kill()
                proc.wait(timeout=30)
            proc.stdout.close()


def test_stale_temporaries_of_other_targets_and_hosts_are_kept(tmp_path):
    """Only the temporary files of the target being written, left by processes of this host that no
    longer run, are removed: a file of another target, another host or this process stays."""
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True,
                          text=True, check=True)
    pid = int(dead.stdout)
    target, host = tmp_path / "out.h5", hdf5._host()
    ours = tmp_path / f".out.h5.{host}.{pid}.00ff.tmp"
    kept = [tmp_path / f".other.h5.{host}.{pid}.00ff.tmp", tmp_path / f".out.h5.elsewhere-{host}.{pid}.00ff.tmp",
            tmp_path / f".out.h5.{host}.{os.getpid()}.00ff.tmp"]
    for path in (ours, *kept):
        path.write_bytes(b"partial")
    assert remove_stale_temporaries(target) == [ours]
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(p.name for p in kept)


@pytest.fixture(scope="session")
def second_small_pipeline(tmp_path_factory):
    """A second run of the small pipeline (conftest ``run_small_pipeline``) in a fresh copy, apart
    from the first.  Session-scoped and named first by its test, so that it is set up before
    ``small_pipeline``: under pytest-xdist it runs while another process builds the shared first run."""
    workdir = copy_workflow(REPO, tmp_path_factory.mktemp("second_small_pipeline"))
    _, rc, out = run_small_pipeline(REPO, workdir)
    assert rc == 0, out
    return workdir


@pytest.mark.exhaustive
def test_two_pipeline_runs_give_the_same_results(second_small_pipeline, small_pipeline):
    """Every stage run twice (the small pipeline, every rule that writes HDF5 at least once): every
    HDF5 result is byte-identical up to its marked measurements, every rerun recording has the same
    id and content; no attribute of any result is named for a time measurement (measured values
    are marked datasets), and every dataset so named is marked.  A second run of the whole pipeline
    (~2 min of CPU on an empty compiled-code cache): marked exhaustive, so CI runs it and the default
    suite checks the same claim on one stage
    (tests/test_pipeline_robustness.py::test_identical_inputs_give_identical_files)."""
    first, rc, out = small_pipeline[0], small_pipeline[2], small_pipeline[3]
    assert rc == 0, out
    files = sorted(p.relative_to(first) for p in (first / "results").rglob("*.h5"))
    assert files == sorted(p.relative_to(second_small_pipeline)
                           for p in (second_small_pipeline / "results").rglob("*.h5"))
    marked = set()
    for name in files:
        assert reproducible_bytes(first / name) == reproducible_bytes(second_small_pipeline / name), name
        for dataset, meta in read_dataset_attrs(first / name).items():
            if MEASURED_NAME.search(dataset.rsplit("/", 1)[-1]):
                assert meta.get(quantities.MEASUREMENT_ATTR) is True, (name, dataset)
        with h5py.File(first / name) as f:
            f.visititems(lambda path, item: marked.update(f"{name}:{path}" for key in item.attrs
                                                          if MEASURED_NAME.search(key)))
            marked.update(f"{name}:/{key}" for key in f.attrs if MEASURED_NAME.search(key))
    assert not marked, sorted(marked)
    recordings = sorted(p.relative_to(first) for p in (first / "results").rglob("*.rrd"))
    assert recordings
    for name in recordings:
        assert recording_ids(first / name) == recording_ids(second_small_pipeline / name), name
        assert_same_recording_content(first / name, second_small_pipeline / name)
    assert not list((first / "results").rglob(".*.tmp"))

