"""Compiling the solvers ahead of a run (selfalign.solvers.warmup, ``selfalign compile``)."""

import os
import subprocess
import sys

import pytest
from click.testing import CliRunner

from selfalign.cli.commands import selfalign
from selfalign.solvers.warmup import WARMUPS, warm_up

#: Lists every compiled entry point of the kernel that has no entry in numba's cache on disk.
UNCACHED = """
from selfalign.solvers import jit
K = jit.kernel()
print(sorted(name for name in dir(K) if hasattr(getattr(K, name), "_cache") and jit._uncached(getattr(K, name))))
"""


def test_unknown_warm_up_is_refused_before_any_run():
    """A name that is not a warm-up is a ValueError listing the allowed ones, raised before any run."""
    with pytest.raises(ValueError, match=r"unknown warm-up 'exactly'; allowed: exact, exact_smooth, moreau"):
        warm_up(["moreau", "exactly"])


def test_compile_command_reports_every_warm_up():
    """``selfalign compile`` runs every warm-up and prints one line for each, then the cache's place."""
    result = CliRunner().invoke(selfalign, ["compile"])
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    assert [line.split(" s  ", 1)[1] for line in lines[:-1]] == [text for text, _ in WARMUPS.values()]
    assert lines[-1].startswith("numba cache: ")


@pytest.mark.exhaustive
def test_warm_up_leaves_every_entry_point_cached(tmp_path):
    """Hypothesis (module docstring of selfalign.solvers.warmup): after the warm-ups, on an empty cache,
    every compiled entry point of the kernel has its cache entry on disk, so no later process compiles.
    The check itself sees the entry points uncached on the empty cache."""
    env = {**os.environ, "SELFALIGN_CACHE_DIR": str(tmp_path)}

    def uncached():
        out = subprocess.run([sys.executable, "-c", UNCACHED], env=env, capture_output=True, text=True, timeout=120)
        assert out.returncode == 0, out.stderr
        return eval(out.stdout)

    before = uncached()
    assert {"members_piecewise", "recorded_moreau", "modes"} <= set(before), before
    warm = subprocess.run([sys.executable, "-m", "selfalign", "compile"], env=env, capture_output=True, text=True,
                          timeout=900)
    assert warm.returncode == 0, warm.stderr
    assert uncached() == []
