"""The workflow on a real SLURM cluster.  `.ci/slurm/start-cluster.sh` turns this
Debian machine into a one-node cluster (it needs root); the Fig. 17 sweep in shards, its gathering,
the Fig. 18 map it is drawn with and the figure then run through `--executor slurm` with the
project's profile.  Deselected unless `-m` names the marker (conftest.py); `.ci/run` runs it last,
as root: `pytest -q -m slurm`."""

import collections
import os
import re
import subprocess
import time
from pathlib import Path

import pytest
import yaml
from conftest import REPO, SNAKEMAKE, copy_workflow

pytestmark = pytest.mark.slurm

START_CLUSTER = REPO / ".ci/slurm/start-cluster.sh"
SLURMCTLD_LOG = Path("/var/log/slurm/slurmctld.log")
TARGET = "figures/fig17.png"
SHARDS = 4
#: A 21 x 21 grid with 16 entries per setting: about a second of work per shard, so the run's time
#: is SLURM's (job start-up and status polling), not the sweep's.
SMALL_SWEEP = {"stages": {"accumulation": {"positioning": {
    "y2": {"from": 0.5, "to": 2.5, "count": 21, "scale": "linear"},
    "y3": {"from": 0.5, "to": 2.5, "count": 21, "scale": "linear"},
    "n_entries": 16,
    "shards": SHARDS,
}}}}
#: What a cluster without an accounting database needs (.ci/slurm/README.md): squeue as the status
#: command (sacct fails and Snakemake would wait forever) and status checks from 1 s on.
SLURM_OPTIONS = ("--workflow-profile", "workflow/profiles/slurm", "--slurm-status-command", "squeue",
                 "--slurm-init-seconds-before-status-checks", "1", "--slurm-jobname-prefix", "selfalignci")
#: Seconds before a hanging Snakemake gets SIGINT (it ignores SIGTERM).
TIMEOUT = 900


@pytest.fixture(scope="module")
def cluster():
    """The one-node cluster, started or reused; a machine that cannot run it fails the test and
    says what is missing (start-cluster.sh's ERROR line and its log tails)."""
    try:
        proc = subprocess.run(["bash", str(START_CLUSTER)], capture_output=True, text=True, timeout=600)
    except (OSError, subprocess.TimeoutExpired) as exc:
        pytest.fail(f"cannot start the SLURM cluster with {START_CLUSTER}: {exc}")
    if proc.returncode != 0:
        errors = [line for line in proc.stderr.splitlines() if "ERROR" in line]
        pytest.fail(f"cannot start the SLURM cluster: {errors[0] if errors else 'exit ' + str(proc.returncode)}"
                    f"\n{proc.stderr[-4000:]}", pytrace=False)


def run_target(workdir: Path, *options) -> tuple[str, float]:
    """Fig. 17 with the small sweep in a copy of the workflow in ``workdir``; (log, wall time in s)."""
    workdir.mkdir()
    copy_workflow(REPO, workdir)
    (workdir / "small_sweep.yaml").write_text(yaml.safe_dump(SMALL_SWEEP))
    env = {k: v for k, v in os.environ.items() if not k.startswith(("SBATCH_", "SLURM_"))}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), os.environ.get("PYTHONPATH")]))
    start = time.monotonic()
    proc = subprocess.run(["timeout", "-s", "INT", "-k", "60", str(TIMEOUT), *SNAKEMAKE, TARGET,
                           "--configfile", "small_sweep.yaml", *options],
                          cwd=workdir, capture_output=True, text=True, env=env)
    wall = time.monotonic() - start
    log = proc.stdout + proc.stderr
    assert proc.returncode == 0, f"snakemake {' '.join(options)} exited {proc.returncode} after {wall:.0f} s:\n" \
                                 f"{log[-4000:]}"
    return log, wall


def finished_rules(log: str) -> collections.Counter:
    return collections.Counter(re.findall(r"Finished jobid: \S+ \(Rule: (\w+)\)", log))


def outputs(workdir: Path) -> dict[str, bytes]:
    """Every result file and figure by its path relative to ``workdir``."""
    files = [*(workdir / "results").rglob("*.h5"), *(workdir / "figures").rglob("*.png")]
    return {str(f.relative_to(workdir)): f.read_bytes() for f in files}


def test_fig17_slice_runs_as_slurm_batch_jobs_with_the_local_results(cluster, tmp_path):
    """With the SLURM profile every job of the slice (the sweep's shards, its gathering, the Fig. 18
    map, the plot group) is a batch job of this run that SLURM reports COMPLETED and slurmctld
    logged as a batch submission; no job runs locally; and every .h5 result and the png are the
    same bytes as `snakemake -c2` of the same target and config writes."""
    slurm_log, slurm_wall = run_target(tmp_path / "slurm", *SLURM_OPTIONS)
    local_log, local_wall = run_target(tmp_path / "local", "-c2")
    print(f"SLURM run {slurm_wall:.0f} s, local run {local_wall:.0f} s")

    rules = finished_rules(local_log)
    assert rules["compute_positioning_shard"] == SHARDS
    assert {"gather_positioning", "compute_stick_map", "plot_fig17"} <= set(rules)
    assert finished_rules(slurm_log) == rules
    assert "localrule " not in slurm_log  # how Snakemake announces a job it runs itself

    submitted = re.findall(r"has been submitted with SLURM jobid (\d+)", slurm_log)
    run_id = re.search(r"SLURM run ID: (\S+)", slurm_log).group(1)
    squeue = subprocess.run(["squeue", "--states=all", "--noheader", "--name", run_id, "--format", "%i|%T|%k"],
                            capture_output=True, text=True, check=True).stdout.split()
    jobs = {job: (state, comment) for job, state, comment in (line.split("|") for line in squeue)}
    assert sorted(jobs) == sorted(submitted)
    assert {state for state, _ in jobs.values()} == {"COMPLETED"}
    for rule, count in rules.items():  # the plugin's comment: rule_<rule>[_wildcards_...] or rule_<group>_<rule>
        assert sum(rule in comment for _, comment in jobs.values()) == count, (rule, jobs)
    batch_jobs = set(re.findall(r"_slurm_rpc_submit_batch_job: JobId=(\d+)", SLURMCTLD_LOG.read_text()))
    assert set(submitted) <= batch_jobs

    on_slurm, local = outputs(tmp_path / "slurm"), outputs(tmp_path / "local")
    assert TARGET in local and "results/accumulation/fig17.h5" in local and "results/accumulation/fig18.h5" in local
    assert sorted(on_slurm) == sorted(local)
    assert [name for name in local if on_slurm[name] != local[name]] == []
