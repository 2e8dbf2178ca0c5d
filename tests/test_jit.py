"""The compiled-code loader (:mod:`selfalign.solvers.jit`): its cache key covers every module the
kernel is built from, and a compilation is announced before the wait."""

import ast
import logging
import os
import subprocess
import sys
from pathlib import Path

import pytest

from selfalign.solvers import jit

PACKAGE = Path(jit.__file__).resolve().parents[1]


def package_imports(relative: str) -> set[str]:
    """Modules of the package (paths relative to it) that the module ``relative`` imports."""
    path = PACKAGE / relative
    package = path.parent.relative_to(PACKAGE.parent).parts
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.level:
            base = list(package[: len(package) - node.level + 1])
            module = base + (node.module.split(".") if node.module else [])
        elif isinstance(node, ast.ImportFrom) and (node.module or "").startswith("selfalign"):
            module = node.module.split(".")
        else:
            continue
        for parts in [module + [alias.name] for alias in node.names]:
            while len(parts) > 1:
                candidate = PACKAGE.parent.joinpath(*parts).with_suffix(".py")
                if candidate.is_file():
                    found.add(str(candidate.relative_to(PACKAGE)))
                    break
                parts = parts[:-1]
    return found


def test_cache_key_covers_every_module_the_kernel_is_built_from():
    """numba checks only the time stamp of the file of a decorated function; the cache directory is
    keyed by the content of ``SOURCES`` instead, so an edit anywhere the kernel compiles from must be
    in it: the closure of the kernel's imports inside the package, and of the model modules whose formulas
    ``kernel()`` registers for the steppers it compiles (``REGISTRY_MODULES``), equals ``SOURCES``."""
    closure, todo = set(), ["solvers/engine/entries.py"] + [f"model/{name}.py" for name in jit.REGISTRY_MODULES]
    while todo:
        module = todo.pop()
        if module not in closure:
            closure.add(module)
            todo.extend(package_imports(module))
    assert "model/arcs.py" in closure and "solvers/records.py" in closure, closure
    assert closure == set(jit.SOURCES), f"missing from SOURCES: {sorted(closure - set(jit.SOURCES))}; " \
                                        f"not imported by the kernel: {sorted(set(jit.SOURCES) - closure)}"


def test_a_source_edit_moves_the_cache_directory(tmp_path, monkeypatch):
    """The cache directory is a digest of the sources: a changed byte in any of them gives another."""
    monkeypatch.setenv("SELFALIGN_CACHE_DIR", str(tmp_path))
    before = jit.cache_dir("0")
    original = Path.read_bytes

    def edited(self):
        data = original(self)
        return data + b"#" if self.name == "errors.py" else data

    monkeypatch.setattr(Path, "read_bytes", edited)
    assert jit.cache_dir("0") != before


def test_first_compile_is_announced_once(tmp_path):
    """On an empty cache the first solver call logs what compiles and where it is kept, before it
    compiles; a second call in the same process says nothing more."""
    code = ("import logging\n"
            "logging.basicConfig(level=logging.INFO, format='%(name)s|%(message)s')\n"
            "from selfalign.solvers import jit\n"
            "jit.kernel()\n"
            "K = jit.kernel()\n"
            "import numpy as np\n"
            "jit.call(K.modes, np.zeros(1), np.zeros(1), np.ones(1))\n"
            "jit.call(K.modes, np.zeros(1), np.zeros(1), np.ones(1))\n")
    env = {**os.environ, "SELFALIGN_CACHE_DIR": str(tmp_path)}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    lines = [line for line in out.stderr.splitlines() if line.startswith("selfalign.solvers.jit|compiling")]
    assert len(lines) == 1, out.stderr
    assert str(tmp_path) in lines[0] and "once per machine" in lines[0]
    again = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=300)
    assert again.returncode == 0 and "compiling" not in again.stderr, again.stderr


def test_no_announcement_once_compiled(monkeypatch):
    """An entry point that already ran in this process is not announced again (nothing compiles)."""
    K = jit.kernel()
    import numpy as np

    jit.call(K.modes, np.zeros(1), np.zeros(1), np.ones(1))
    seen = []
    monkeypatch.setattr(jit, "_announced", False)
    monkeypatch.setattr(jit.LOGGER, "info", lambda *a: seen.append(a))
    jit.call(K.modes, np.zeros(1), np.zeros(1), np.ones(1))
    assert K.modes.signatures and not seen
    assert logging.getLogger("selfalign.solvers.jit") is jit.LOGGER


@pytest.mark.slow
def test_cli_announces_the_first_compile_on_stderr(tmp_path):
    """A first ``selfalign simulate`` on an empty cache says on stderr that it compiles, before the
    result; the result itself (stdout) is unchanged by the announcement."""
    scene = Path(__file__).resolve().parents[1] / "workflow" / "scenes" / "stop_zone.yaml"
    env = {**os.environ, "SELFALIGN_CACHE_DIR": str(tmp_path)}
    cold = subprocess.run([sys.executable, "-m", "selfalign", "simulate", str(scene)], env=env,
                          capture_output=True, text=True, timeout=600)
    warm = subprocess.run([sys.executable, "-m", "selfalign", "simulate", str(scene)], env=env,
                          capture_output=True, text=True, timeout=600)
    assert cold.returncode == warm.returncode == 0, cold.stderr + warm.stderr
    assert cold.stderr.startswith("selfalign: compiling the event kernel"), cold.stderr
    assert "compiling" not in warm.stderr and cold.stdout == warm.stdout


def test_profile_rows_are_read_through_the_layout():
    """The engine reads a profile row only through the layout functions of
    :mod:`selfalign.solvers.records` (no column offsets computed in the engine), and those functions
    read back what the row builders wrote: break i, piece i's levels, jerk, y', y and end level of a
    piecewise-linear row, a Fourier row's coefficients, a Moreau row's step and impulses."""
    import re

    import numpy as np

    from selfalign.solvers import records as R

    engine = sorted((PACKAGE / "solvers" / "engine").glob("*.py"))
    assert len(engine) > 5
    inline = [f"{p.name}:{i + 1}" for p in engine for i, line in enumerate(p.read_text().splitlines())
              if re.search(r"\bDATA\b|row\[[a-z]\w*0 \+", line)]
    assert not inline, f"column offsets computed in the engine: {inline}"
    head = R.profile_header(2.0, 3.0, 4.0, 5.0)
    m = 3
    breaks, levels, jerks = np.arange(m + 1) * 0.5, np.arange(m) + 10.0, np.arange(m) + 20.0
    velocities, positions, ends = np.arange(m) + 30.0, np.arange(m) + 40.0, np.arange(m) + 50.0
    row = R.linear_row(head, breaks, levels, jerks, velocities, positions, ends)
    assert R.data_size(row) == -m and row[R.DT] == 2.0 and row[R.REST_ACC] == 5.0
    for i in range(m):
        assert row[R.col_break(i)] == breaks[i] and row[R.col_level(m, i)] == levels[i]
        assert (row[R.col_jerk(m, i)], row[R.col_start_velocity(m, i)], row[R.col_start_position(m, i)],
                row[R.col_end_level(m, i)]) == (jerks[i], velocities[i], positions[i], ends[i])
    assert row[R.col_break(m)] == breaks[m] and row.size == R.col_end_level(m, m)
    fourier = R.fourier_row(head, [1.0, 2.0], [3.0, 4.0], [5.0, 6.0])
    assert [fourier[R.col_fourier(2, j, 1)] for j in range(3)] == [2.0, 4.0, 6.0]
    moreau = R.moreau_row(head, 0.25, np.array([0.5, -0.75]))
    assert (R.data_size(moreau), moreau[R.MOREAU_STEP], moreau[R.MOREAU_LARGEST], moreau[R.col_impulse(1)]) == \
        (2, 0.25, 0.75, -0.75)
