"""Scale and speed infrastructure: a light `import selfalign`, the SLURM workflow profile,
and the benchmark functions (structure only; no timing is asserted)."""

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "benchmarks"))
import measure  # noqa: E402

SNAKEMAKE = [sys.executable, "-m", "snakemake"]
#: Modules that `import selfalign` must not load: they are imported where they are used.
HEAVY = ("rerun", "matplotlib", "h5py", "scipy", "snakemake", "yaml", "jsonschema", "numba", "llvmlite")


@pytest.mark.parametrize("statement", ["import selfalign",
                                       "from selfalign import Scene, StopZone, ThreePhaseProfile, steady_state",
                                       "from selfalign import SelfalignError, DesignSpecError, KernelError, "
                                       "FiniteJerkProfile, FrictionLaw"])
def test_import_selfalign_loads_no_heavy_module(statement):
    """`import selfalign` loads nothing but the package (its names load their module on first
    use), and the model and closed forms load numpy only: the compiled kernel (numba,
    llvmlite), plotting, recording, HDF5, scipy, YAML parsing and Snakemake load where they
    are used (the library imports fast)."""
    code = f"import sys; {statement}; print(' '.join(sorted(m for m in sys.modules if '.' not in m)))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    loaded = set(out.split())
    assert "selfalign" in loaded
    assert loaded.isdisjoint(HEAVY), sorted(loaded & set(HEAVY))


@pytest.fixture
def workdir(repo, tmp_path):
    """A copy of Snakefile + workflow/ (symlinks followed) and a PATH without any SLURM command."""
    shutil.copy(repo / "Snakefile", tmp_path / "Snakefile")
    shutil.copytree(repo / "workflow", tmp_path / "workflow")
    return tmp_path


def snakemake(workdir, *args, **env):
    """Snakemake in ``workdir`` with a PATH of the venv and a shell only: no SLURM command, even on a
    machine that has SLURM installed (as the CI machine does for the real-cluster test)."""
    tools = workdir / "path-without-slurm"
    tools.mkdir(exist_ok=True)
    for name in ("sh", "bash", "env", "which", "uname", "git"):
        if not (tools / name).exists() and shutil.which(name):
            (tools / name).symlink_to(shutil.which(name))
    path = os.path.dirname(sys.executable) + os.pathsep + str(tools)
    assert shutil.which("sbatch", path=path) is None and shutil.which("sinfo", path=path) is None
    environ = {k: v for k, v in os.environ.items() if not k.startswith(("SBATCH_", "SLURM_"))}
    proc = subprocess.run([*SNAKEMAKE, *args], cwd=workdir, capture_output=True, text=True, timeout=300,
                          env={**environ, "PATH": path, **env})
    return proc.returncode, proc.stdout + proc.stderr


def test_slurm_profile_dry_run_needs_no_slurm(workdir):
    """`snakemake -n --workflow-profile workflow/profiles/slurm` plans every job with the profile's
    resources on a machine without sbatch/sinfo; the partition comes from SBATCH_PARTITION and the
    plot rules form one group job."""
    rc, out = snakemake(workdir, "-n", "--workflow-profile", "workflow/profiles/slurm",
                        SBATCH_PARTITION="short")
    assert rc == 0, out
    assert "Using workflow specific profile workflow/profiles/slurm" in out
    assert "slurm_partition=short" in out and "runtime=10" in out and "cpus_per_task=1" in out
    assert "Group job plots" in out
    assert "sample_trajectory" in out and "run_benchmarks" not in out


def test_slurm_profile_heavy_rule_resources_and_unknown_rules(workdir):
    """set-resources reaches its rule (run_benchmarks: 2 cores, 4 GB); a rule name the workflow does
    not define, in set-resources or groups, is ignored rather than an error."""
    profile = workdir / "workflow/profiles/slurm/config.yaml"
    text = profile.read_text()
    text = text.replace("set-resources:\n", "set-resources:\n  no_such_rule:\n    runtime: 1\n")
    text = text.replace("groups:\n", "groups:\n  no_such_rule: plots\n")
    profile.write_text(text)
    rc, out = snakemake(workdir, "-n", "--workflow-profile", "workflow/profiles/slurm", "benchmarks")
    assert rc == 0, out
    assert "slurm_partition=," in out  # unset: the cluster's default partition
    assert "mem_mb=4000" in out and "cpus_per_task=2" in out and "runtime=30" in out


@pytest.mark.slow
def test_benchmarks_run_tiny_structure():
    """Every benchmark runs in a tiny configuration and the table has one row per measurement;
    the engine and the minimal compiled reference loop end in the same states
    (bit-identical on these scenes)."""
    report = measure.run(tiny=True)
    assert {"platform", "cpu", "cores", "python", "numpy"} <= set(report["machine"])
    (row,) = report["exact_vs_moreau"]
    assert row["tolerance"] == 1e-2 and row["exact_s"] > 0 and row["moreau_s"] > 0
    assert row["moreau_steps"] is None or row["moreau_error"] <= row["tolerance"]
    assert [r["case"] for r in report["single_trajectory"]] == [
        "uniform surface (quadratic arcs)", "transition zone (harmonic arcs)"]
    for r in report["single_trajectory"]:
        assert r["events"] == r["reference_events"] > 0 and r["max_end_difference"] == 0.0
    sweep = report["batched_sweep"]
    assert [r["unit"] for r in sweep] == ["events", "events", "steps"]
    assert all(r["count"] > 0 and r["trajectories"] == 64 for r in sweep)
    assert all(r["max_end_difference"] == 0.0 and r["reference_per_s"] > 0 for r in sweep[:2])
    assert [r["case"] for r in report["several_parts"]] == [
        "Fig. 18, uniform", "Fig. 18, stop zone", "backward slips, uniform", "backward slips, stop zone"]
    assert all(r["events"] > 0 and r["status"] in ("horizon", "rest") for r in report["several_parts"])
    assert report["simulate_latency"]["median_us"] > 0
    assert report["first_call"]["cold"] is None and report["first_call"]["cached"]["first_simulate_s"] > 0
    assert report["fig17"]["trajectories"] > 0 and report["fig17"]["events"] > 0
    assert report["design"]["found"] and report["design"]["command_s"] > 0 and report["design"]["warm_s"] > 0
    assert report["pipeline"] is None and report["max_rss_mb"] > 0
    table = measure.format_table(report)
    assert table.startswith(f"Machine: {report['machine']['cpu']}")
    # Against Siconos: per scene a row and one per step, and the figure's caption; or one row saying why not.
    s = report["siconos_parts"]
    siconos = 1 if "skipped" in s else 1 + sum(1 + len({r["steps_per_period"] for r in scene["rows"]})
                                               for scene in s["scenes"].values())
    # Against MuJoCo (planar motion): a row per scene and setting, or one row saying why not.
    m = report["mujoco_planar"]
    mujoco = 1 if "skipped" in m else len(m["rows"])
    assert table.count("\n| ") == 2 + 1 + 2 + 3 + 1 + 1 + 1 + 1 + 1 + siconos + mujoco + 1  # header, separator, rows
    json.dumps(report)  # the raw numbers are JSON as written by the workflow


@pytest.mark.slow
def test_full_pipeline_times_a_copy(tmp_path):
    """The pipeline benchmark runs `snakemake` in a copy and counts its outputs; the source tree
    gets no results/ or figures/."""
    repo = tmp_path / "repo"
    (repo / "workflow").mkdir(parents=True)
    (repo / "Snakefile").write_text(
        'rule all:\n    input: "figures/a.png", "results/s/a.h5"\n\n'
        'rule make:\n    output: "figures/{x}.png", "results/s/{x}.h5"\n'
        '    shell: "touch {output}"\n')
    result = measure.full_pipeline(repo, cores=1)
    assert result["figures"] == ["a.png"] and result["results"] == 1 and result["seconds"] > 0
    assert not (repo / "results").exists() and not (repo / "figures").exists()
    (repo / "Snakefile").write_text('rule all:\n    input: "missing"\n')
    with pytest.raises(RuntimeError, match="failed in the benchmark copy"):
        measure.full_pipeline(repo, cores=1)


@pytest.mark.slow
def test_run_all_script_prints_the_table(repo, tmp_path):
    """benchmarks/run_all.py --tiny --no-pipeline prints the table and writes the raw JSON."""
    raw = tmp_path / "bench.json"
    proc = subprocess.run([sys.executable, str(repo / "benchmarks/run_all.py"), "--tiny", "--no-pipeline",
                           "--json", str(raw)], capture_output=True, text=True, timeout=120, check=True)
    assert proc.stdout.startswith("Machine: ") and "| benchmark | result |" in proc.stdout
    assert json.loads(raw.read_text())["pipeline"] is None
