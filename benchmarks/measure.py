"""Benchmarks of the solvers and the workflow, measured in one run on one machine.

Used by ``benchmarks/run_all.py`` and the workflow's ``run_benchmarks`` rule
(README.md, "Benchmarks").  Every function returns plain dicts so the caller
formats them; :func:`run` collects them and :func:`format_table` prints the
one table of the README.  Nothing here asserts a timing.
"""

from __future__ import annotations

import os
import platform
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from selfalign.model.friction import StopZone, Uniform
from selfalign.model.profiles import ThreePhaseProfile
from selfalign.model.scene import Scene
from selfalign.solvers.driver import simulate

#: The Fig. 18 profile (case 1, stick-slip), used by every benchmark.
PROFILE = ThreePhaseProfile(1.05, 0.084, 2.2, 0.9)
#: A transition zone so wide that the mass stays inside it: a harmonic arc every
#: period and no steady state to fast-forward, so both solvers really integrate.
WIDE_ZONE = StopZone(-1000.0, 1e4, 2.0)

#: Floating-point operations of one quadratic-arc event of the batched exact solver
#: (selfalign/solvers/batch.py, ``_Batch._slip``): stop time and position (7), boundary
#: crossing by energy (9, one sqrt), crossing time (3), arc step x, v (7), start
#: acceleration (3), and the ~11 comparisons/selects that pick the event; a division
#: or a square root counts as one operation.
FLOPS_PER_EVENT = 40


def machine() -> dict:
    """Platform, CPU model (from /proc/cpuinfo where it exists), cores, Python and numpy."""
    model = platform.processor() or platform.machine()
    cpuinfo = Path("/proc/cpuinfo")
    if cpuinfo.exists():
        for line in cpuinfo.read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    return {"platform": platform.platform(), "cpu": model, "cores": os.cpu_count(),
            "python": platform.python_version(), "numpy": np.__version__}


def _best(func, repeat: int) -> float:
    """Best wall-clock time of `repeat` calls of func()."""
    best = float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        func()
        best = min(best, time.perf_counter() - start)
    return best


def exact_vs_moreau(periods: int = 50, tolerances=(1e-2, 1e-3, 1e-4),
                    steps=(100, 300, 1000, 3000, 10_000, 30_000, 100_000), repeat: int = 3) -> list[dict]:
    """Time to reach x_end within each tolerance: exact solver vs Moreau (DESIGN, "Solver contract").

    The scene is :data:`PROFILE` on :data:`WIDE_ZONE` for `periods` periods.  The exact
    solution is the reference; for Moreau the coarsest step h = dt / N (N from `steps`)
    whose |x_end - x_exact| <= tol is timed.  ``moreau_steps`` is None (and the time that
    of the finest N tried) when no N reaches tol.
    """
    scene = Scene(PROFILE, surface=WIDE_ZONE, periods=periods)
    reference = simulate(scene).x_end
    exact_time = _best(lambda: simulate(scene), repeat)
    errors = {}
    rows = []
    for tol in tolerances:
        found = None
        for n in steps:
            if n not in errors:
                errors[n] = abs(simulate(scene, method="moreau", h=PROFILE.dt / n).x_end - reference)
            if errors[n] <= tol:
                found = n
                break
        n = found or steps[-1]
        moreau_time = _best(lambda: simulate(scene, method="moreau", h=PROFILE.dt / n), repeat)
        rows.append({"tolerance": tol, "periods": periods, "moreau_steps": found, "moreau_error": errors[n],
                     "moreau_s": moreau_time, "exact_s": exact_time, "speedup": moreau_time / exact_time})
    return rows


def single_trajectory(periods: int = 20_000, repeat: int = 3) -> list[dict]:
    """Events per second of the exact solver's own event loop (no recording, no fast-forward)."""
    from selfalign.solvers.exact import ExactSolver

    cases = {"uniform surface (quadratic arcs)": Uniform(), "transition zone (harmonic arcs)": WIDE_ZONE}
    rows = []
    for name, surface in cases.items():
        events = ExactSolver(PROFILE, surface, record=False).advance(periods)
        seconds = _best(lambda: ExactSolver(PROFILE, surface, record=False).advance(periods), repeat)
        rows.append({"case": name, "events": int(events), "seconds": seconds, "events_per_s": events / seconds})
    return rows


def _sweep_grid(n: int):
    """An n x n grid of (y2'', y3'') with every profile physical (q <= 1) at dt = 1.05, dy = 0.084."""
    y2, y3 = np.meshgrid(np.linspace(2.0, 4.0, n), np.linspace(0.9, 3.0, n), indexing="ij")
    return y2.ravel(), y3.ravel()


def batched_sweep(n: int = 64, periods: int = 20, repeat: int = 2) -> list[dict]:
    """Throughput of the batched exact solver and the batched Moreau scheme on an n x n sweep.

    Numpy runs these on one core, so trajectory-events per second is per core.  For the
    exact solver, ``events_per_s_per_core`` is set next to what arithmetic alone would
    allow: :data:`FLOPS_PER_EVENT` divided into (a) the measured numpy elementwise rate at
    this batch size and (b) the measured single-core floating-point peak.
    """
    from selfalign.solvers.batch import solve_batch, three_phase_pieces

    from selfalign.solvers import moreau

    y2, y3 = _sweep_grid(n)
    breaks, accels = three_phase_pieces(PROFILE.dt, PROFILE.dy, y2, y3)
    rates = arithmetic_rates(y2.size)
    rows = []
    for name, zone in (("uniform surface", {}),
                       ("transition zone", {"x_mu": WIDE_ZONE.x_mu, "w": WIDE_ZONE.w, "c_mu": WIDE_ZONE.c_mu})):
        result = solve_batch(breaks, accels, 0.0, until="periods", periods=periods, **zone)
        seconds = _best(lambda: solve_batch(breaks, accels, 0.0, until="periods", periods=periods, **zone),
                        repeat)
        events = int(result.events.sum())
        rows.append({"solver": f"exact batch, {name}", "trajectories": y2.size, "periods": periods,
                     "unit": "events", "count": events, "seconds": seconds, "per_s_per_core": events / seconds,
                     "numpy_bound": rates["numpy_elementwise_flops"] / FLOPS_PER_EVENT,
                     "fma_bound": rates["peak_flops"] / FLOPS_PER_EVENT})
    profiles = [ThreePhaseProfile(PROFILE.dt, PROFILE.dy, a, b) for a, b in zip(y2, y3)]
    steps = moreau.solve_batch(profiles, Uniform(), 0.0, 0.0, periods=1).steps_per_period * periods * y2.size
    seconds = _best(lambda: moreau.solve_batch(profiles, Uniform(), 0.0, 0.0, periods=periods), repeat)
    rows.append({"solver": "Moreau batch (h = dt/1000), uniform surface", "trajectories": y2.size,
                 "periods": periods, "unit": "steps", "count": steps, "seconds": seconds,
                 "per_s_per_core": steps / seconds, "numpy_bound": None, "fma_bound": None})
    return rows


def arithmetic_rates(size: int, repeat: int = 5) -> dict:
    """Measured floating-point rates of this machine, operations per second on one core.

    ``numpy_elementwise_flops``: one numpy ufunc (multiply-add as two calls) on arrays of
    `size` elements, the way the batched solver computes.  ``peak_flops``: a float64
    matrix product on one BLAS thread (in a subprocess, so the thread count is fixed
    before numpy loads), close to the FMA peak of one core.
    """
    a, b, c = (np.random.default_rng(seed).random(size) for seed in (1, 2, 3))
    loops = max(1, 2_000_000 // size)

    def elementwise():
        for _ in range(loops):
            np.multiply(a, b, out=c)
            np.add(c, a, out=c)

    seconds = _best(elementwise, repeat)
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    code = ("import time, numpy as np; n = 768; a = np.random.rand(n, n); a @ a; best = 1e9\n"
            "for _ in range(5):\n    t = time.perf_counter(); a @ a; best = min(best, time.perf_counter() - t)\n"
            "print(2 * n ** 3 / best)")
    peak = float(subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                                check=True).stdout)
    return {"numpy_elementwise_flops": 2 * size * loops / seconds, "peak_flops": peak}


def full_pipeline(repo: Path, cores: int = 2, timeout: float = 900.0) -> dict:
    """Wall time and peak memory of ``snakemake -c<cores>`` from a clean results/ in a copy of the workflow.

    The copy holds ``Snakefile`` and ``workflow/`` (symlinks followed), so the repository's
    results and figures are untouched.  Peak memory is the largest resident set of any
    process the run started (``RUSAGE_CHILDREN``; Linux reports kB).
    """
    repo = Path(repo)
    with tempfile.TemporaryDirectory(prefix="selfalign-bench-") as tmp:
        work = Path(tmp)
        shutil.copy(repo / "Snakefile", work / "Snakefile")
        shutil.copytree(repo / "workflow", work / "workflow")
        start = time.perf_counter()
        proc = subprocess.run([sys.executable, "-m", "snakemake", f"-c{cores}"], cwd=work,
                              capture_output=True, text=True, timeout=timeout)
        seconds = time.perf_counter() - start
        if proc.returncode != 0:
            raise RuntimeError(f"snakemake -c{cores} failed in the benchmark copy:\n{proc.stderr[-2000:]}")
        figures = sorted(p.name for p in (work / "figures").glob("*.png"))
        results = sorted(str(p.relative_to(work)) for p in (work / "results").rglob("*.h5"))
    return {"cores": cores, "seconds": seconds, "figures": figures, "results": len(results),
            "children_max_rss_mb": resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024}


def run(repo: Path | None = None, tiny: bool = False, cores: int = 2) -> dict:
    """Every benchmark once; `tiny` shrinks all sizes (for tests), `repo` None skips the pipeline."""
    size = ({"periods": 5, "tolerances": (1e-2,), "steps": (100, 1000), "repeat": 1}, 200, 8, 2)
    full = ({"periods": 50}, 20_000, 64, 20)
    moreau_args, single_periods, grid, sweep_periods = size if tiny else full
    report = {"machine": machine(),
              "exact_vs_moreau": exact_vs_moreau(**moreau_args),
              "single_trajectory": single_trajectory(single_periods, repeat=1 if tiny else 3),
              "batched_sweep": batched_sweep(grid, sweep_periods, repeat=1 if tiny else 2),
              "pipeline": full_pipeline(repo, cores) if repo is not None else None}
    report["max_rss_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    return report


def format_table(report: dict) -> str:
    """The report as one Markdown table, headed by the machine it was measured on."""
    m = report["machine"]
    lines = [f"Machine: {m['cpu']}, {m['cores']} cores, {m['platform']}, Python {m['python']}, "
             f"numpy {m['numpy']}", "", "| benchmark | result |", "| --- | --- |"]
    for r in report["exact_vs_moreau"]:
        moreau_h = (f"h = dt/{r['moreau_steps']}" if r["moreau_steps"] else "not reached, finest")
        lines.append(f"| x_end to {r['tolerance']:.0e} ({r['periods']} periods, transition zone) | exact "
                     f"{r['exact_s'] * 1e3:.2f} ms; Moreau {moreau_h} {r['moreau_s'] * 1e3:.1f} ms "
                     f"(error {r['moreau_error']:.1e}), {r['speedup']:.0f}x slower |")
    for r in report["single_trajectory"]:
        lines.append(f"| single trajectory, exact, {r['case']} | {r['events_per_s']:.3g} events/s "
                     f"({r['events']} events in {r['seconds']:.3f} s) |")
    for r in report["batched_sweep"]:
        text = (f"{r['per_s_per_core']:.3g} trajectory-{r['unit']}/s per core ({r['trajectories']} "
                f"trajectories x {r['periods']} periods in {r['seconds']:.3f} s)")
        if r["numpy_bound"] is not None:
            text += (f"; arithmetic alone ({FLOPS_PER_EVENT} flops/event): {r['numpy_bound']:.3g}/s at numpy's "
                     f"elementwise rate, {r['fma_bound']:.3g}/s at the FMA peak")
        lines.append(f"| sweep, {r['solver']} | {text} |")
    p = report["pipeline"]
    if p is not None:
        lines.append(f"| full pipeline `snakemake -c{p['cores']}`, clean results/ | {p['seconds']:.1f} s, "
                     f"{p['results']} result files, {len(p['figures'])} figures; largest process "
                     f"{p['children_max_rss_mb']:.0f} MB |")
    lines.append(f"| peak memory of the benchmark process (ru_maxrss) | {report['max_rss_mb']:.0f} MB |")
    return "\n".join(lines)
