"""Shared test options.

``--update-figure-refs`` rewrites the figure references (tests/figure_refs/*.json
and the committed figures/*.png) from the current code instead of comparing
against them; use it only after an intended change of a figure and review the diff.
"""

import fcntl
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

REPO = Path(__file__).resolve().parents[1]


def pytest_addoption(parser):
    parser.addoption("--update-figure-refs", action="store_true", default=False,
                     help="rewrite tests/figure_refs/*.json and figures/*.png instead of comparing")


#: Markers whose tests run only when the ``-m`` expression names them.
OPT_IN_MARKERS = ("slurm", "exhaustive")
#: Markers whose tests run only when the ``-m`` expression names some marker of OPT_IN_MARKERS or this one
#: (a claim checked with a larger budget that passes through BLAS runs with ``-m exhaustive``).
DEFAULT_OUT_MARKERS = ("blas",)


def pytest_collection_modifyitems(config, items):
    """Tests marked ``slurm`` start daemons as root and take minutes; tests marked ``exhaustive``
    repeat a claim with a far larger budget (a wider search, the whole pipeline run twice; minutes
    each); tests marked ``blas`` check results that pass through BLAS/LAPACK, which ``.ci/run`` runs
    under four BLAS configurations (the machine's own kernel, as the README's command would, and a
    kernel every x86-64 CPU runs, each with 1 and 2 threads).  The first two run only when the ``-m``
    expression names their marker, the ``blas`` tests when it names any of the three (``.ci/run`` runs
    ``pytest -q -m slurm``, ``-m exhaustive`` and ``-m blas``; an exhaustive test of a result that
    passes through BLAS runs with ``-m exhaustive``), so the README's test command and e.g.
    ``-m 'not slow'`` leave them all out.  Files holding a slow test run first."""
    expression = config.getoption("markexpr")
    named = [marker for marker in OPT_IN_MARKERS + DEFAULT_OUT_MARKERS if marker in expression]
    out = [marker for marker in OPT_IN_MARKERS if marker not in named] + ([] if named else list(DEFAULT_OUT_MARKERS))
    for marker in out:
        opted = [item for item in items if item.get_closest_marker(marker)]
        if opted:
            config.hook.pytest_deselected(items=opted)
            items[:] = [item for item in items if not item.get_closest_marker(marker)]
    # Files with a test marked slow first: the README's command hands whole files to two processes in
    # this order (pytest-xdist, --dist loadfile), so the long ones start at once and the two end together.
    slow_files = {item.path for item in items if item.get_closest_marker("slow")}
    items.sort(key=lambda item: item.path not in slow_files)


@pytest.fixture
def update_figure_refs(request) -> bool:
    return request.config.getoption("--update-figure-refs")


@pytest.fixture(scope="session")
def repo() -> Path:
    return REPO


def random_three_phase(count, seed, *, accelerations, strokes, complete):
    """``count`` random feasible three-phase settings from the generator seeded with ``seed``.  Per
    draw: dt uniform in [0.3, 2], y2'' and y3'' log-uniform in ``accelerations`` (lo, hi), dy the
    fraction uniform in ``strokes`` (lo, hi) of the largest stroke dt^2 / (8 (1/y2'' + 1/y3''))
    (q <= 1); then ``complete(rng, dt, dy, y2, y3)`` draws the rest from the same generator
    and returns the item, or None to discard the draw."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < count:
        dt = rng.uniform(0.3, 2.0)
        y2, y3 = np.exp(rng.uniform(np.log(accelerations[0]), np.log(accelerations[1]), 2))
        dy = dt * dt / (8 * (1 / y2 + 1 / y3)) * rng.uniform(*strokes)
        item = complete(rng, dt, dy, y2, y3)
        if item is not None:
            out.append(item)
    return out


SNAKEMAKE = [sys.executable, "-m", "snakemake"]


def assert_batch_member_is(res, i: int, traj) -> None:
    """Member ``i`` of a simulate_batch result ended as the scalar trajectory ``traj`` did, bit
    for bit: status, reason, end time, event count and end state."""
    assert res.statuses()[i] is traj.status and res.reason[i] == traj.reason, i
    assert (res.period_end[i], res.tau_end[i], res.event_count[i]) == (traj.period_end, traj.tau_end,
                                                                       traj.stats["events"]), i
    assert (res.x_end[i], res.v_end[i]) == (traj.x_end, traj.v_end), i


def copy_workflow(repo: Path, dest: Path) -> Path:
    """A runnable copy of the workflow in ``dest``; the scene-schema symlink becomes a plain file."""
    shutil.copy(repo / "Snakefile", dest / "Snakefile")
    shutil.copytree(repo / "workflow", dest / "workflow")
    return dest


@pytest.fixture
def workdir(repo, tmp_path):
    return copy_workflow(repo, tmp_path)


#: Seconds a snakemake run may take before the test gives up on it (a hang guard, not a claim).
SNAKEMAKE_TIMEOUT = 300
#: The same for a run of the whole small pipeline: on an empty compiled-code cache its jobs compile
#: the kernel's entry points first (about 250 s of CPU against 100 s on a full cache).
PIPELINE_TIMEOUT = 900


def run_snakemake(workdir, *args, timeout=SNAKEMAKE_TIMEOUT):
    """Run snakemake in ``workdir`` with the package of this checkout (also where the installed
    one is another worktree's); return (exit code, stdout + stderr)."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))}
    proc = subprocess.run([*SNAKEMAKE, *args], cwd=workdir, capture_output=True,
                          text=True, timeout=timeout, env=env)
    return proc.returncode, proc.stdout + proc.stderr


def small_config(repo: Path) -> dict:
    """The workflow config shrunk so that every stage runs in seconds: one scene per costly
    stage, one sweep, 3 x 3 grids, one shard (job start-up, ~1 s, dominates)."""
    config = yaml.safe_load((repo / "workflow/config/config.yaml").read_text())
    s = config["stages"]

    def axis(lo, hi, count=3):
        return {"from": lo, "to": hi, "count": count, "scale": "linear"}

    # Trajectory and simulation scenes (milliseconds each) stay: the figures read them.
    # One accuracy scene of each family: one part under the paper's model and under static/kinetic friction,
    # several parts, planar motion (figures accuracy_cost, accuracy_effects, accuracy_parts, accuracy_planar).
    s["accuracy"].update(scenes=["accuracy_steady", "accuracy_static", "accuracy_parts_zone", "accuracy_planar"],
                         fit_min_steps_per_period=10,
                         min_timing=0.001, moreau_steps_per_period={"from": 10, "to": 1000, "count": 3, "scale": "log"},
                         ivp_rtol={"from": 1.0e-3, "to": 1.0e-5, "count": 2, "scale": "log"})
    s["stability"].update(scenes=["fig09_case1"], moreau_steps=[100], moreau_eps=[1.0e-3])
    s["stability"]["grids"] = {"fig17": {**s["stability"]["grids"]["fig17"], "y2": axis(0.3, 6.0),
                                         "y3": axis(0.3, 6.0), "moreau_steps": 100}}
    s["convergence"].update(scenes=["fig13"], v20={"fig13": 0.3})
    c = s["classification"]
    c["polynomial"]["moreau_steps_per_period"] = 100
    c["sweeps"]["fig04"]["dt"] = axis(0.1, 1.4)  # fig05 is required in the config but not run
    c["fourier"].update(order=3, max_iter=2)
    for m in c["maps"].values():
        m.update(y2=axis(m["y2"]["from"], m["y2"]["to"]), y3=axis(m["y3"]["from"], m["y3"]["to"]), shards=1)
    a = s["accumulation"]
    a["positioning"].update(y2=axis(2.0, 2.4), y3=axis(1.0, 1.4), n_entries=4, max_periods=200, shards=1)
    a["portraits"]["n_entries"] = 4
    a["stick_map"]["points"] = 5
    s["design"]["designs"] = s["design"]["designs"][-1:]
    s["effects"]["static_friction"].update(y2=axis(2.0, 2.4), y3=axis(1.0, 1.4), n_entries=4, ratios=[1.0, 1.3],
                                           settings=[[2.3, 1.3]], sweep_entries=4,
                                           excess={"from": 0.1, "to": 0.3, "count": 2, "scale": "log"})
    s["effects"]["stribeck"].update(v_s={"from": 1.0e-3, "to": 1.0, "count": 2, "scale": "log"},
                                    steps_per_period=200, steady={**s["effects"]["stribeck"]["steady"],
                                                                  "settings": [[2.0, 0.5]]},
                                    stopping={"settings": [[2.3, 1.3]], "n_entries": 2, "max_periods": 200})
    j = s["finite_jerk"]
    j["ramp_fractions"] = [0.0, 0.05]
    for plane in j["steady"].values():
        plane.update(y2=axis(plane["y2"]["from"], plane["y2"]["to"]), y3=axis(plane["y3"]["from"], plane["y3"]["to"]))
    j["stopping"].update(y2=axis(2.0, 2.4), y3=axis(1.0, 1.4), n_entries=2, max_periods=200)
    # The comparison and one sweep point each at a = 300 and Fig. 6's stroke, one Fourier order of a few
    # iterations.
    s["optimal_motion"].update(accel_max=300.0, orders=[4], max_iter=3, truncation_orders=[4, 12],
                               accel_sweep=axis(300.0, 300.0, 1), fourier_accel_max=[300.0],
                               stroke_sweep=axis(0.021, 0.021, 1), fourier_stroke_max=[0.021])
    # Queues of one and two parts; the SI queue on the one design the small run designs.
    s["parts"].update(n_max=2, spacings=[0.05], restitutions=[0.0], spreads=[0.0], max_periods=200,
                      motion={"n": 2, "spacing": 0.05, "restitution": 0.0},
                      design={**s["parts"]["design"], "spec": s["design"]["designs"][-1], "n_max": 2,
                              "max_periods": 50})
    # The planar study on 2 x 2 maps, two scales, two angles and a few entries, by Moreau's scheme (its own
    # tests run the exact solvers; here the stage's rules, files and figures are checked).
    p = s["planar"]
    p.update(method="moreau", solver_options={"steps_per_period": 500}, offsets=2, ratios=[0.0, 0.5],
             harmonic_ratios=[0.0, 0.5], low_scales=[0.4],
             limit={**p["limit"], "scales": [8.0, 16.0]})
    p["alignment"].update(angles=[0.0, 40.0], starts=2, lateral=[0.0, 0.05],
                          corner={**p["alignment"]["corner"], "starts": 1, "lateral": [-0.1, 0.1]})
    return config


def run_small_pipeline(repo: Path, workdir: Path) -> tuple[list[str], int, str]:
    """Run the whole pipeline (every stage, every figure) on :func:`small_config` in ``workdir``, a
    fresh copy of the workflow: (result files every stage must have written, snakemake's exit code,
    its output)."""
    config = small_config(repo)
    (workdir / "workflow/config/config.yaml").write_text(yaml.safe_dump(config, sort_keys=False))
    s = config["stages"]
    targets = [f"results/{stage}/{name}.h5" for stage in ("trajectory", "simulation", "accuracy", "stability",
                                                          "convergence") for name in s[stage]["scenes"]]
    targets += [f"results/stability/grid_{g}.h5" for g in s["stability"]["grids"]]
    targets += [f"results/classification/{n}.h5" for n in ("fig04", "fig06", "verify_maps")]
    targets += [f"results/accumulation/{n}.h5" for n in ("fig16", "fig17", "fig18")]
    targets += [f"results/design/{name}.h5" for name in s["design"]["designs"]]
    targets += ["results/effects/static_friction.h5", "results/effects/stribeck.h5",
                "results/finite_jerk/finite_jerk.h5", "results/parts/queue.h5", "results/planar/planar.h5"]
    rc, out = run_snakemake(workdir, "-c2", timeout=PIPELINE_TIMEOUT)
    return targets, rc, out


@pytest.fixture(scope="session")
def small_pipeline(repo, tmp_path_factory):
    """A workflow copy in which the whole pipeline ran on :func:`small_config`
    (:func:`run_small_pipeline`): (workdir, result files every stage must have written, snakemake's
    exit code, its output).  Shared by the result-metadata, report and reproducibility tests, so
    that a clean checkout (no ``results/``) tests them; its users only read the copy.

    Under pytest-xdist the processes of one session share a single run: the first to ask builds it
    in the session's common temporary directory while holding a lock on a file there, and records
    the exit code and output; the others wait for the lock and read the same run."""
    if "PYTEST_XDIST_WORKER" not in os.environ:
        workdir = copy_workflow(repo, tmp_path_factory.mktemp("small_pipeline"))
        return (workdir, *run_small_pipeline(repo, workdir))
    shared = tmp_path_factory.getbasetemp().parent
    workdir, record = shared / "small_pipeline", shared / "small_pipeline.json"
    with open(shared / "small_pipeline.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not record.exists():
            shutil.rmtree(workdir, ignore_errors=True)  # left by a process killed while it ran
            workdir.mkdir()
            targets, rc, out = run_small_pipeline(repo, copy_workflow(repo, workdir))
            partial = record.with_suffix(".tmp")
            partial.write_text(json.dumps({"targets": targets, "rc": rc, "out": out}))
            partial.replace(record)
        run = json.loads(record.read_text())
    return workdir, run["targets"], run["rc"], run["out"]
