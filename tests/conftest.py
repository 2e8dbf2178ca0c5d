"""Shared test options.

``--update-figure-refs`` rewrites the figure references (tests/figure_refs/*.json
and the committed figures/*.png) from the current code instead of comparing
against them; use it only after an intended change of a figure and review the diff.
"""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[1]


def pytest_addoption(parser):
    parser.addoption("--update-figure-refs", action="store_true", default=False,
                     help="rewrite tests/figure_refs/*.json and figures/*.png instead of comparing")


def pytest_collection_modifyitems(config, items):
    """Tests marked ``slurm`` start daemons as root and take minutes: they run only when the ``-m``
    expression names them (``.ci/run`` runs ``pytest -q -m slurm``), so the README's test command
    and e.g. ``-m 'not slow'`` leave them out."""
    if "slurm" in config.getoption("markexpr"):
        return
    slurm = [item for item in items if item.get_closest_marker("slurm")]
    if slurm:
        config.hook.pytest_deselected(items=slurm)
        items[:] = [item for item in items if not item.get_closest_marker("slurm")]


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


def copy_workflow(repo: Path, dest: Path) -> Path:
    """A runnable copy of the workflow in ``dest``; the scene-schema symlink becomes a plain file."""
    shutil.copy(repo / "Snakefile", dest / "Snakefile")
    shutil.copytree(repo / "workflow", dest / "workflow")
    return dest


@pytest.fixture
def workdir(repo, tmp_path):
    return copy_workflow(repo, tmp_path)


def run_snakemake(workdir, *args):
    """Run snakemake in ``workdir`` with the package of this checkout (also where the installed
    one is another worktree's); return (exit code, stdout + stderr)."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))}
    proc = subprocess.run([*SNAKEMAKE, *args], cwd=workdir, capture_output=True,
                          text=True, timeout=300, env=env)
    return proc.returncode, proc.stdout + proc.stderr
