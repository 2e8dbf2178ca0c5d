"""Benchmarks of the solvers and the workflow, measured in one run on one machine.

Used by ``benchmarks/run_all.py`` and the workflow's ``run_benchmarks`` rule
(docs/explanation/performance.md).  Every function returns plain dicts so the caller
formats them; :func:`run` collects them and :func:`format_table` prints the
one table of docs/explanation/performance.md.  Nothing here asserts a timing.
"""

from __future__ import annotations

import itertools
import os
import platform
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import mujoco_planar
import numpy as np
import reference
import siconos_parts
import yaml

from selfalign.analysis.positioning import MEMORY_LIMIT, positioning_bytes, positioning_grid
from selfalign.model.friction import StopZone, Uniform
from selfalign.model.parts import Part
from selfalign.model.profiles import ThreePhaseProfile
from selfalign.model.scene import Scene
from selfalign.solvers.driver import simulate, simulate_batch
from selfalign.solvers.exact import piecewise_rows
from selfalign.solvers.parts_exact import simulate_parts
from selfalign.solvers.records import EXACT_PIECEWISE
from selfalign.solvers.tables import ProfileTable

#: The Fig. 18 profile (case 1, stick-slip), used by every benchmark.
PROFILE = ThreePhaseProfile(1.05, 0.084, 2.2, 0.9)
#: A transition zone so wide that the mass stays inside it: a harmonic arc every
#: period and no steady state to fast-forward, so both solvers really integrate.
WIDE_ZONE = StopZone(-1000.0, 1e4, 2.0)
#: A profile of Fig. 16 (dt = 1, y3'' = 1.3 > 1): slips forward and backward in every period.
BACKWARD = ThreePhaseProfile(1.0, 0.084, 2.3, 1.3)

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


def _reference_inputs(surface):
    """(w, c_mu, xi offset) of the reference loop for a surface: positions relative to x_mu."""
    if isinstance(surface, StopZone):
        return surface.w, surface.c_mu, -surface.x_mu
    return 1.0, 1.0, 0.0


def single_trajectory(periods: int = 200_000, repeat: int = 3) -> list[dict]:
    """Events per second of one exact trajectory (nothing recorded, no fast-forward), through
    the engine's driver and through the minimal compiled loop of :mod:`reference` on the same
    scene, in the same process; ``max_end_difference``: |x_end engine - x_end reference|."""
    cases = {"uniform surface (quadratic arcs)": Uniform(), "transition zone (harmonic arcs)": WIDE_ZONE}
    rows = []
    for name, surface in cases.items():
        def engine():
            return simulate_batch(PROFILE, 0.0, surface=surface, until="periods", periods=periods,
                                  fast_forward=False)

        w, c_mu, shift = _reference_inputs(surface)

        def minimal():
            return reference.run(PROFILE.breaks, PROFILE.accels, w, c_mu, shift, 0.0, periods)

        result, (xi, _, ref_events) = engine(), minimal()
        events = int(result.event_count[0])
        seconds, ref_seconds = _best(engine, repeat), _best(minimal, repeat)
        rows.append({"case": name, "zone": isinstance(surface, StopZone), "periods": periods, "events": events,
                     "seconds": seconds, "events_per_s": events / seconds, "reference_events": int(ref_events),
                     "reference_events_per_s": ref_events / ref_seconds,
                     "max_end_difference": abs(float(result.x_end[0]) - (xi - shift))})
    return rows


def _sweep_profiles(n: int):
    """An n x n grid of three-phase profiles (y2'' in [2, 4], y3'' in [0.9, 3], all physical) at
    the dt, dy of :data:`PROFILE`."""
    y2, y3 = np.meshgrid(np.linspace(2.0, 4.0, n), np.linspace(0.9, 3.0, n), indexing="ij")
    return [ThreePhaseProfile(PROFILE.dt, PROFILE.dy, a, b) for a, b in zip(y2.ravel(), y3.ravel())]


def batched_sweep(n: int = 64, horizons: tuple = (20, 200), repeat: int = 3) -> list[dict]:
    """Trajectory-events per second of one batch call over an n x n sweep (one core: the
    batch is a loop over members), next to the reference loop over the same members, and
    trajectory-steps per second of the Moreau batch (h = dt/1000).  The profile table is
    built once from arrays, as a sweep does (:func:`~selfalign.solvers.exact.piecewise_rows`),
    so that the time is the batch call's, not that of making 4096 profile objects.  The
    exact batch runs for each number of periods in ``horizons`` (the short one shows the
    fixed cost per member, the long one the cost per event); Moreau for the first."""
    profiles = _sweep_profiles(n)
    breaks = np.array([p.breaks for p in profiles])
    accels = np.array([p.accels for p in profiles])
    table = ProfileTable(piecewise_rows(breaks, accels), EXACT_PIECEWISE)
    rows = []
    for (name, surface), periods in itertools.product((("uniform surface", Uniform()),
                                                        ("transition zone", WIDE_ZONE)), horizons):
        def engine():
            return simulate_batch(table, 0.0, surface=surface, until="periods", periods=periods,
                                  fast_forward=False)

        w, c_mu, shift = _reference_inputs(surface)
        start = np.full(len(profiles), shift)

        def minimal():
            return reference.run_batch(breaks, accels, w, c_mu, start, np.zeros(len(profiles)), periods)

        result, (xi, _, ref_events) = engine(), minimal()
        events = int(result.event_count.sum())
        seconds, ref_seconds = _best(engine, repeat), _best(minimal, repeat)
        rows.append({"solver": f"exact batch, {name}", "trajectories": len(profiles), "periods": periods,
                     "unit": "events", "count": events, "seconds": seconds, "per_s_per_core": events / seconds,
                     "reference_per_s": int(ref_events.sum()) / ref_seconds,
                     "max_end_difference": float(np.max(np.abs(result.x_end - (xi - shift))))})

    periods = horizons[0]

    def moreau():
        return simulate_batch(profiles, 0.0, until="periods", periods=periods, method="moreau",
                              steps_per_period=1000, fast_forward=False)

    moreau()
    steps = 1000 * periods * len(profiles)
    seconds = _best(moreau, repeat)
    rows.append({"solver": "Moreau batch (h = dt/1000), uniform surface", "trajectories": len(profiles),
                 "periods": periods, "unit": "steps", "count": steps, "seconds": seconds,
                 "per_s_per_core": steps / seconds, "reference_per_s": None, "max_end_difference": None})
    return rows


def parts_chain(count: int, seed: int = 1) -> list:
    """``count`` parts in a row from x = 0 (seeded): widths 0.02-0.08, masses 0.5-2, friction factors 0.8-1.6,
    start velocities within +-0.3; each touches the one behind it with probability 1/2, else lies up to 0.05
    ahead of it."""
    rng = np.random.default_rng(seed)
    parts, front = [], 0.0
    for _ in range(count):
        width = rng.uniform(0.02, 0.08)
        front += width + (0.0 if rng.random() < 0.5 else rng.uniform(0.0, 0.05))
        parts.append(Part(front, rng.uniform(-0.3, 0.3), width=width, mass=rng.uniform(0.5, 2.0),
                          friction_factor=rng.uniform(0.8, 1.6)))
    return parts


def several_parts(count: int = 100, periods: int = 1000, repeat: int = 1) -> list[dict]:
    """Events per second of the exact solver of several parts (``simulate_parts``, plastic contacts) on a chain
    of ``count`` parts (:func:`parts_chain`) over ``periods`` periods, on a uniform surface and with a stop
    zone (x_mu 0.5 ahead of the front part, w = 0.05, c_mu = 2.5) that the chain runs into, under the Fig. 18
    profile (forward slips: the chain soon moves as a few pushed clusters) and under :data:`BACKWARD` (slips
    both ways: contacts close and open every period)."""
    parts = parts_chain(count)
    zone = StopZone(parts[-1].x0 + 0.5, 0.05, 2.5)
    cases = {"Fig. 18, uniform": (PROFILE, Uniform()), "Fig. 18, stop zone": (PROFILE, zone),
             "backward slips, uniform": (BACKWARD, Uniform()), "backward slips, stop zone": (BACKWARD, zone)}
    rows = []
    for name, (profile, surface) in cases.items():
        def solve():
            return simulate_parts(profile, parts, surface=surface, periods=periods)

        result = solve()
        seconds = _best(solve, repeat)
        rows.append({"case": name, "zone": isinstance(surface, StopZone), "parts": count, "periods": periods,
                     "status": result.status.value,
                     "events": result.events, "impacts": result.impacts, "seconds": seconds,
                     "events_per_s": result.events / seconds})
    return rows


def simulate_latency(calls: int = 2000) -> dict:
    """Median wall time of ``sa.simulate`` of a 5-period scene (Fig. 18 profile, uniform
    surface) after warm-up, over ``calls`` calls."""
    scene = Scene(PROFILE, periods=5)
    simulate(scene)
    times = np.empty(calls)
    for i in range(calls):
        start = time.perf_counter()
        simulate(scene)
        times[i] = time.perf_counter() - start
    return {"calls": calls, "median_us": float(np.median(times)) * 1e6,
            "p90_us": float(np.percentile(times, 90)) * 1e6}


FIRST_CALL = ("import time; t0 = time.perf_counter(); import selfalign as sa; "
              "p = sa.ThreePhaseProfile(1.05, 0.084, 2.2, 0.9); t1 = time.perf_counter(); "
              "sa.simulate(sa.Scene(p, periods=5)); t2 = time.perf_counter(); "
              "sa.simulate(sa.Scene(p, sa.StopZone(0.1, 0.05, 2.5), until='rest', max_periods=50)); "
              "print(t1 - t0, t2 - t1, time.perf_counter() - t2)")


def first_call(cold: bool = True) -> dict:
    """Seconds of ``import selfalign`` and of the first ``simulate`` in a fresh process: with
    an empty numba cache (the kernel compiles, ~20 s; skipped unless ``cold``) and with a
    filled one (the compiled kernel is loaded from disk: cache=True)."""
    out = {"cold": None}
    with tempfile.TemporaryDirectory(prefix="selfalign-cache-") as cache:
        env = dict(os.environ, SELFALIGN_CACHE_DIR=cache) if cold else dict(os.environ)
        for label in ("cold", "cached") if cold else ("cached",):
            proc = subprocess.run([sys.executable, "-c", FIRST_CALL], env=env, capture_output=True, text=True,
                                  check=True)
            imported, first, zone = (float(v) for v in proc.stdout.split())
            out[label] = {"import_s": imported, "first_simulate_s": first, "first_zone_simulate_s": zone}
    return out


def fig17_sweep(n: int = 201, entries: int = 128, processes: int = 2) -> dict:
    """Wall time of the Fig. 17 sweep (Sect. 7.2; dt = 1, dy = 0.084, w = 0.05, c_mu = 2.5,
    (y2'', y3'') in [0.5, 2.5]^2 on an n x n grid, ``entries`` steady-state entries per
    setting to their outcome, at most 1000 periods) over ``processes`` worker processes."""
    y = np.linspace(0.5, 2.5, n)
    y2, y3 = np.meshgrid(y, y, indexing="ij")
    # In row shards that each fit positioning's memory limit, as the pipeline's shards do.
    shards = -(-positioning_bytes(y2.size * entries, 2) // MEMORY_LIMIT)
    rows = np.array_split(np.arange(n), shards)
    start = time.perf_counter()
    grids = [positioning_grid(1.0, 0.084, y2[r], y3[r], w=0.05, c_mu=2.5, n_entries=entries, levels=(0.99, 0.999),
                              processes=processes) for r in rows]
    seconds = time.perf_counter() - start
    moving = sum(int(g.moving.sum()) for g in grids)
    return {"n": n, "entries": entries, "processes": processes, "shards": shards, "moving": moving,
            "trajectories": moving * entries, "events": sum(int(g.events) for g in grids), "seconds": seconds}


#: The design spec of the worked example of docs/tutorials/design-station.md.
DESIGN_SPEC = Path(__file__).resolve().parent.parent / "workflow" / "designs" / "smd_steel_table.yaml"


def design_answer(spec: Path = DESIGN_SPEC, repeat: int = 3, families: list | None = None) -> dict:
    """Seconds to a design answer (target: <= 10 s on 2 cores): ``selfalign design SPEC``
    as a user runs it (a fresh process: start-up, imports, the cached kernel, the search and the
    guarantee's simulations) and ``sa.design`` in a warm process (best of ``repeat``).  ``families``:
    the spec's ``profile.families`` replaced (the tiny run searches the paper's family only, seconds
    instead of a minute)."""
    from selfalign import design, load_design_spec

    if families is not None:
        document = yaml.safe_load(spec.read_text())
        document.setdefault("profile", {})["families"] = list(families)
        copy = Path(tempfile.mkdtemp(prefix="selfalign-design-")) / spec.name
        copy.write_text(yaml.safe_dump(document, sort_keys=False))
        spec = copy
    start = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "selfalign", "design", str(spec)], capture_output=True, text=True)
    command = time.perf_counter() - start
    if proc.returncode not in (0, 1):  # 1: the spec has no design, which is an answer too
        raise RuntimeError(f"selfalign design {spec} failed:\n{proc.stderr[-2000:]}")
    loaded = load_design_spec(spec)
    result = design(loaded, progress="quiet")
    warm = _best(lambda: design(loaded, progress="quiet"), repeat)
    return {"spec": spec.stem, "command_s": command, "warm_s": warm, "found": bool(result.found)}


def siconos_work_precision(tiny: bool = False, figure: Path | None = None) -> dict:
    """Work-precision of several parts against Siconos on the accuracy stage's scenes of several parts
    (``siconos_parts.work_precision``: Siconos with theta = 1/2 and 1, ``moreau_parts`` at the same h, the
    exact solver; docs/explanation/siconos-parts.md), its figure written to ``figure`` (None: none) and its
    caption; ``{"skipped": reason}`` where Siconos cannot be run (a benchmark-only dependency)."""
    missing = siconos_parts.siconos_missing()
    if missing:
        return {"skipped": missing}
    report = (siconos_parts.work_precision(levels=(250, 500), shifts=1) if tiny
              else siconos_parts.work_precision())
    report["caption"] = siconos_parts.work_precision_caption(report)
    report["figure"] = None if figure is None else str(siconos_parts.plot_work_precision(report, figure))
    return report


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


def run(repo: Path | None = None, tiny: bool = False, cores: int = 2, figure: Path | None = None) -> dict:
    """Every benchmark once; `tiny` shrinks all sizes (for tests), `repo` None skips the pipeline, `figure`
    is where the work-precision figure against Siconos goes (None: not drawn)."""
    if tiny:
        moreau_args, single, sweep, latency, fig17 = ({"periods": 5, "tolerances": (1e-2,), "steps": (100, 1000),
                                                       "repeat": 1}, (200, 1), (8, (2,), 1), 20, (9, 8, 1))
        parts = (10, 5, 1)
    else:
        moreau_args, single, sweep, latency, fig17 = ({"periods": 50}, (200_000, 3), (64, (20, 200), 3), 2000,
                                                       (201, 128, 2))
        parts = (100, 1000, 1)
    report = {"machine": machine(),
              "exact_vs_moreau": exact_vs_moreau(**moreau_args),
              "single_trajectory": single_trajectory(*single),
              "batched_sweep": batched_sweep(*sweep),
              "several_parts": several_parts(*parts),
              "simulate_latency": simulate_latency(latency),
              "first_call": first_call(cold=not tiny),
              "fig17": fig17_sweep(*fig17),
              "design": design_answer(repeat=1, families=["three_phase"]) if tiny else design_answer(),
              "siconos_parts": siconos_work_precision(tiny, figure),
              "mujoco_planar": mujoco_planar.work_precision(tiny),
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
        lines.append(f"| one trajectory, exact, {r['case']} | {r['events_per_s']:.3g} events/s ({r['events']} "
                     f"events in {r['seconds']:.3f} s); minimal compiled loop {r['reference_events_per_s']:.3g}/s "
                     f"(engine at {r['events_per_s'] / r['reference_events_per_s']:.0%}; end states differ by "
                     f"{r['max_end_difference']:.1e}) |")
    for r in report["batched_sweep"]:
        text = (f"{r['per_s_per_core']:.3g} trajectory-{r['unit']}/s per core ({r['trajectories']} "
                f"trajectories x {r['periods']} periods in {r['seconds']:.3f} s)")
        if r["reference_per_s"] is not None:
            text += (f"; minimal compiled loop {r['reference_per_s']:.3g}/s (engine at "
                     f"{r['per_s_per_core'] / r['reference_per_s']:.0%}; end states differ by "
                     f"{r['max_end_difference']:.1e})")
        lines.append(f"| batch, {r['solver']} | {text} |")
    rows = report["several_parts"]
    # the cost per event against the single-part engine's on the same surface (its quadratic or zone arcs)
    alone = {r["zone"]: r["events_per_s"] for r in report["single_trajectory"]}
    lines.append(f"| several parts, exact, {rows[0]['parts']} parts x {rows[0]['periods']} periods | " + "; ".join(
        f"{r['case']}: {r['seconds']:.2f} s, {r['events_per_s']:.3g} events/s, {1e6 / r['events_per_s']:.2f} µs per "
        f"event ({alone[r['zone']] / r['events_per_s']:.0f}x the single-part engine's) "
        f"({r['events']} events, {r['impacts']} contact closings, ends {r['status']})" for r in rows) + " |")
    lat = report["simulate_latency"]
    lines.append(f"| `sa.simulate`, 5 periods, after warm-up | median {lat['median_us']:.1f} µs, 90th percentile "
                 f"{lat['p90_us']:.1f} µs ({lat['calls']} calls) |")
    cold, cached = report["first_call"]["cold"], report["first_call"]["cached"]
    compiled = f"empty numba cache (compiles): {cold['first_simulate_s']:.1f} s; " if cold else ""
    lines.append(f"| first `simulate` in a fresh process | {compiled}cached: {cached['first_simulate_s']:.2f} s; "
                 f"`import selfalign` {cached['import_s'] * 1e3:.0f} ms |")
    f = report["fig17"]
    lines.append(f"| Fig. 17 sweep {f['n']} x {f['n']} x {f['entries']} entries, {f['processes']} processes | "
                 f"{f['seconds']:.1f} s ({f['trajectories']} trajectories, {f['events'] / 1e6:.0f} M events, "
                 f"{f['events'] / f['seconds']:.3g} events/s) |")
    d = report["design"]
    lines.append(f"| design answer, `workflow/designs/{d['spec']}.yaml` | `selfalign design` (fresh process) "
                 f"{d['command_s']:.1f} s; `sa.design` in a warm process {d['warm_s']:.2f} s; design found: "
                 f"{d['found']} |")
    lines += _siconos_rows(report["siconos_parts"])
    lines += _mujoco_rows(report["mujoco_planar"])
    p = report["pipeline"]
    if p is not None:
        lines.append(f"| full pipeline `snakemake -c{p['cores']}`, clean results/ | {p['seconds']:.1f} s, "
                     f"{p['results']} result files, {len(p['figures'])} figures; largest process "
                     f"{p['children_max_rss_mb']:.0f} MB |")
    lines.append(f"| peak memory of the benchmark process (ru_maxrss) | {report['max_rss_mb']:.0f} MB |")
    return "\n".join(lines)


def _siconos_rows(s: dict) -> list[str]:
    """The rows of :func:`siconos_work_precision`: per scene its exact solver and fitted orders, per scene and
    step the errors and CPU times side by side with the ratios, and the figure's caption; or why it was
    skipped."""
    if "skipped" in s:
        return [f"| several parts against Siconos (work-precision) | skipped: {s['skipped']} |"]
    lines = []
    for name, scene in s["scenes"].items():
        label = {m: style[0] for m, style in siconos_parts.WORK_PRECISION_STYLE.items()}
        orders = ", ".join(f"{label[m]} {order:.2f}" for m, order in scene["orders"].items())
        lines.append(f"| several parts against Siconos, `{name}` ({scene['parts']} parts, e = "
                     f"{scene['restitution']:g}, {scene['periods']} periods) | exact solver "
                     f"{scene['reference_cpu'] * 1e3:.1f} ms; fitted orders: {orders} |")
        ratios = {r["steps_per_period"]: r for r in scene["ratios"]}
        by_step = {}
        for row in scene["rows"]:
            by_step.setdefault(row["steps_per_period"], {})[row["method"]] = row
        for n, rows in by_step.items():
            side = "; ".join(f"{label[m]} {row['error']:.2e} in {row['cpu']:.4f} s" for m, row in rows.items())
            lines.append(f"| `{name}`, h = dt/{n}: error, CPU | {side}; Siconos (theta = 1/2) / moreau_parts: CPU "
                         f"{ratios[n]['cpu_ratio']:.0f}x, error {ratios[n]['error_ratio']:.3f} |")
    where = f"`{s['figure']}`" if s["figure"] else "figure (not drawn)"
    lines.append(f"| {where} | {s['caption']} |")
    return lines


def _mujoco_rows(m: dict) -> list[str]:
    """The rows of ``mujoco_planar.work_precision``: per scene and MuJoCo setting its errors against the exact
    planar solver, its creep per period and its CPU time beside Moreau's and the exact solver's; or why it was
    skipped (docs/explanation/mujoco-planar.md)."""
    if "skipped" in m:
        return [f"| planar motion against MuJoCo | skipped: {m['skipped']} |"]
    lines = []
    for r in m["rows"]:
        mj, mo = r["mujoco"], r["moreau"]
        lines.append(f"| planar `{r['scene']}` against MuJoCo {m['mujoco_version']}, {r['setting']} settings, "
                     f"h = {r['h']:.1e}, {r['periods']} periods | MuJoCo: end error {mj['end_error']:.2e}, drift "
                     f"error {mj['drift_error']:.2e}, creep {mj['creep_per_period']:.2e} per period, "
                     f"{mj['cpu']:.3f} s; Moreau (same h): end error {mo['end_error']:.2e}, {mo['cpu']:.4f} s; exact "
                     f"{r['exact']['cpu']:.4f} s; MuJoCo / Moreau CPU {r['cpu_ratio_mujoco_to_moreau']:.0f}x |")
    return lines
