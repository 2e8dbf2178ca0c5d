"""The core install (`pip install selfalign`, no extras; docs/howto/install.md) runs the library: model,
solvers, analysis and io import and work without matplotlib, rerun, Snakemake or click, and the
layers that need one of them say which extra to install."""

import re
import subprocess
import sys
import textwrap
import tomllib

import pytest

#: Importable names of the extras' libraries (distributions rerun-sdk, snakemake-executor-plugin-slurm, ...).
EXTRA_MODULES = ("snakemake", "snakemake_executor_plugin_slurm", "matplotlib", "rerun", "click")
#: The layers the core install must run.
CORE_LAYERS = ("model", "solvers", "analysis", "io")
#: Prepended to every subprocess: a meta-path finder that refuses the extras' modules, as if the
#: core install had left them out (the shared venv has them installed).
REFUSE_EXTRAS = textwrap.dedent(f"""
    import importlib.abc, sys

    class RefuseExtras(importlib.abc.MetaPathFinder):
        def find_spec(self, name, path=None, target=None):
            if name.split(".")[0] in {EXTRA_MODULES!r}:
                raise ModuleNotFoundError(f"No module named {{name!r}} (refused: not in the core install)", name=name)
            return None

    sys.meta_path.insert(0, RefuseExtras())
""")

#: Imports every module of the core layers, then runs the core entry points on workflow inputs.
CORE_RUN = textwrap.dedent(f"""
    import pkgutil, tempfile
    from importlib import import_module
    from pathlib import Path

    import selfalign as sa

    imported = []
    for layer in {CORE_LAYERS!r}:
        package = import_module(f"selfalign.{{layer}}")
        imported.append(package.__name__)
        for info in pkgutil.walk_packages(package.__path__, f"{{package.__name__}}."):
            import_module(info.name)
            imported.append(info.name)

    scene = sa.load_scene("workflow/scenes/stop_zone.yaml")
    traj = sa.simulate(scene)
    assert traj.status == sa.Status.ACCUMULATION and len(traj.series["x"]) > 0, traj.message
    batch = sa.simulate_batch(scene.profile, x0=[0.0, 0.1], until="periods", periods=5)
    assert len(batch.x_end) == 2
    profile = scene.profile
    assert sa.steady_state(profile).vbar > 0
    assert len(sa.floquet(profile).multipliers) == 2
    assert sa.classify(profile) in range(6)
    assert sa.positioning(profile, w=0.05, c_mu=2.5, n_entries=4).frac_stop >= 0

    from selfalign.io.hdf5 import read_h5, write_h5
    from selfalign.io.simulation_result import trajectory_content, trajectory_from_result
    with tempfile.TemporaryDirectory() as tmp:
        write_h5(Path(tmp) / "r.h5", *trajectory_content(traj, scene))
        assert trajectory_from_result(read_h5(Path(tmp) / "r.h5")).x_end == traj.x_end

    loaded = sorted(m for m in sys.modules if m.split(".")[0] in {EXTRA_MODULES!r})
    assert not loaded, loaded
    print("\\n".join(imported))
""")


def run_without_extras(repo, code):
    return subprocess.run([sys.executable, "-c", REFUSE_EXTRAS + code], cwd=repo, capture_output=True,
                          text=True, timeout=600)


def test_core_layers_import_and_run_without_extras(repo):
    """With matplotlib, rerun, Snakemake and click unimportable, every module of model, solvers,
    analysis and io imports (io.recording too: only reading or writing a recording needs rerun),
    and simulate, simulate_batch, steady_state, floquet, classify, positioning and an HDF5 round
    trip of a workflow scene run: a top-level or core-path import of an extra fails this test."""
    proc = run_without_extras(repo, CORE_RUN)
    assert proc.returncode == 0, proc.stderr
    on_disk = {".".join(p.relative_to(repo).with_suffix("").parts).removesuffix(".__init__")
               for layer in CORE_LAYERS for p in (repo / "selfalign" / layer).rglob("*.py")}
    assert set(proc.stdout.split()) == on_disk


@pytest.mark.parametrize("code, message", [
    ("import selfalign.plots", "selfalign.plots needs matplotlib"),
    ("import selfalign.plots.classification", "selfalign.plots needs matplotlib"),
    ("import selfalign.stages.figures", "selfalign.plots needs matplotlib"),
    ("from selfalign.io.recording import read_recording; read_recording('none.rrd')",
     "reading a rerun recording needs rerun"),
])
def test_layers_of_an_extra_name_it(repo, code, message):
    """Importing a module that needs an extra the install lacks (or, for recordings, whose content
    types are core, reading or writing one) fails with one ImportError that names the extra to
    install (which also shows that the refusing finder takes effect)."""
    proc = run_without_extras(repo, code)
    extra = "rerun" if "rerun" in message else "plots"
    assert proc.stderr.splitlines()[-1] == (f"ImportError: {message}, which the core install leaves out: "
                                            f"pip install 'selfalign[{extra}]'"), proc.stderr


def requirement_names(project, group):
    """Distribution names a dependency group brings (``None``: the core), self-references such as
    "selfalign[plots]" resolved to the core plus those extras."""
    names, pending, seen = set(), [group], set()
    while pending:
        current = pending.pop()
        if current in seen:
            continue
        seen.add(current)
        for requirement in project["dependencies"] if current is None else project["optional-dependencies"][current]:
            name, extras = re.fullmatch(r"([\w.-]+)\s*(?:\[([^\]]*)\])?.*", requirement).groups()
            if name == project["name"]:
                pending += [None, *(e.strip() for e in extras.split(","))]
            else:
                names.add(name)
    return names


def test_core_dependencies_leave_the_extras_out(repo):
    """pyproject's core dependencies name no library of the plots, rerun and workflow extras, the
    workflow extra brings what its scripts need (matplotlib, rerun) and `test` brings every extra but `bench` (the
    benchmark-only peers, which CI installs on its own)."""
    project = tomllib.loads((repo / "pyproject.toml").read_text())["project"]
    core = requirement_names(project, None)
    extras = {name: requirement_names(project, name) - core for name in ("plots", "rerun", "workflow")}
    assert extras["plots"] == {"matplotlib"} and extras["rerun"] == {"rerun-sdk"}
    assert {"snakemake", "snakemake-executor-plugin-slurm", "matplotlib", "rerun-sdk"} <= extras["workflow"]
    everything = set().union(*(requirement_names(project, name) for name in project["optional-dependencies"]
                               if name != "bench"))
    assert requirement_names(project, "test") == everything
