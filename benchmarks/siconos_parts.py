"""Several parts on one table against Siconos: work-precision of Siconos' Moreau-Jean time-stepping and of
``selfalign.solvers.parts_moreau.moreau_parts`` against the exact event-driven solver.

Run from the repository top:  .venv/bin/python benchmarks/siconos_parts.py [--quick] [--json FILE]

Siconos (Debian's ``python3-siconos``) is installed for /usr/bin/python3 and built against that
interpreter's numpy 1.x; the project's environment has another interpreter and numpy 2.  The Siconos
part therefore runs in a process of its own, ``SICONOS_PYTHON benchmarks/siconos_worker.py``
(``SICONOS_PYTHON`` defaults to /usr/bin/python3), and the two exchange JSON: this script sends the
scenes (the profile's breaks and accelerations, the parts, e, the steps), the worker answers with the end
states and the process time of each run.  Nothing of ``selfalign`` imports Siconos.

The scenes (the Fig. 18 profile, ``ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)``, 10 periods):

* ``one part``: one part 0.05 wide at x = 0;
* ``two parts, e = 0`` and ``e = 0.5``: a part of friction factor 0.7 at x = 0 behind a part of factor 1
  at x = 0.06, both 0.05 wide: the rear one catches up and pushes the front one in every forward slip;
* ``chain of 10``: ten touching parts 0.0625 wide (a binary fraction: they touch exactly) with friction
  factors 0.7 ... 1.3 in a fixed shuffled order, e = 0: the chain splits and closes again every period;
* ``two parts, stop zone``: the two parts of the second scene (e = 0) walking into a stop zone
  (x_mu = 0.5, c_mu = 2.5, eqs. 7-9 over each part's own width).

The reference is the exact solver ``selfalign.solvers.parts_exact.simulate_parts``. The error is the largest
|x_i - x_i,ref| at the end. Where the profile's breaks and the parts' events fall inside a step changes a
first-order scheme's error by a factor of ten and more (one part at dt/1000: 1.6e-4 with 1000 steps per
period, 2.2e-3 with 1001 ... 1004), so at each level n every method runs on the grids n, n + 1, ..., n + 4,
and the table gives the largest error over them next to the error at n; the order of each method is the
least-squares slope of log(largest error) over log h. The CPU time is ``time.process_time`` of the solving
process around one run (Siconos: the model's construction and its time loop; moreau_parts: one call after a
first call that compiled it), without interpreter start or imports, the mean over the grids. Siconos runs
with theta = 1/2 and, as a variant on the scenes of one and two parts, theta = 1.

The work-precision comparison on the accuracy stage's scenes of several parts (``stages: accuracy: scenes``
of workflow/config/config.yaml whose scene file has ``parts:``, e.g. workflow/scenes/accuracy_parts.yaml):
Siconos with theta = 1/2 and theta = 1, ``moreau_parts`` at the same steps h = dt / n and the exact solver,
error (the largest |x_i - x_i,ref| at the end) against CPU time, with the ratios of Siconos to
``moreau_parts`` at each h, and a figure of it (:func:`work_precision`, :func:`plot_work_precision`; the
benchmark table of ``snakemake -c2 benchmarks`` carries it, benchmarks/measure.py).

Also measured: Newton's cradle in Siconos (three equal parts, e = 1, the front contact closed or 1e-12
open), and the chain of 10 with MoreauJeanOSI's contact threshold 0 (the default) and 1e-13.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import time
from pathlib import Path

import numpy as np

import selfalign as sa
from selfalign import load_scene
from selfalign.model.parts import Part
from selfalign.solvers.parts_exact import simulate_parts
from selfalign.solvers.parts_moreau import moreau_parts

REPO = Path(__file__).resolve().parent.parent
WORKER = Path(__file__).resolve().with_name("siconos_worker.py")
#: The interpreter that has Siconos.
SICONOS_PYTHON = os.environ.get("SICONOS_PYTHON", "/usr/bin/python3")
PROFILE = sa.ThreePhaseProfile(dt=1.05, dy=0.084, y2=2.2, y3=0.9)
PERIODS = 10
#: Steps per period of the work-precision table (h = dt / n).
LEVELS = (250, 500, 1000, 2000, 4000, 8000, 16000)
#: Grids per level: n, n + 1, ..., n + SHIFTS - 1 steps per period (:func:`measure`).
SHIFTS = 5
#: Moreau-Jean's theta: 0.5 makes its position update the paper's midpoint rule (docs/explanation/siconos-parts.md).
THETA = 0.5
#: Scenes of at most this many parts run Siconos with theta = 1 too (the chain of 10 does not: 30 s a run).
THETA_ONE_MAX_PARTS = 3
#: Steps per period of the work-precision comparison on the accuracy stage's scenes.
WORK_PRECISION_LEVELS = (250, 500, 1000, 2000, 4000, 8000, 16000)
#: Methods of the work-precision figure: label, marker, colour.
WORK_PRECISION_STYLE = {"siconos": ("Siconos, theta = 1/2", "o", "tab:green"),
                        "siconos, theta = 1": ("Siconos, theta = 1", "s", "tab:olive"),
                        "moreau_parts": ("moreau_parts (selfalign)", "^", "tab:blue")}


def _two_parts():
    return [Part(0.0, width=0.05, friction_factor=0.7), Part(0.06, width=0.05)]


def _chain(n=10, width=0.0625):
    factors = 0.7 + 0.6 * np.random.default_rng(0).permutation(n) / (n - 1)
    return [Part(i * width, width=width, friction_factor=float(factors[i])) for i in range(n)]


def _scene(parts, restitution=0.0, surface=None):
    return sa.Scene(PROFILE, surface or sa.Uniform(), parts=parts, restitution=restitution, periods=PERIODS)


#: name -> scene
SCENES = {
    "one part": _scene([Part(0.0, width=0.05)]),
    "two parts, e = 0": _scene(_two_parts()),
    "two parts, e = 0.5": _scene(_two_parts(), 0.5),
    "chain of 10": _scene(_chain()),
    "two parts, stop zone": _scene(_two_parts(), surface=sa.StopZone(x_mu=0.5, w=0.05, c_mu=2.5)),
}


def accuracy_scenes(config=REPO / "workflow" / "config" / "config.yaml") -> dict:
    """The scenes of the accuracy stage (``stages: accuracy: scenes`` of ``config``) that have several parts,
    name -> scene, loaded from their files in workflow/scenes."""
    import yaml

    names = yaml.safe_load(Path(config).read_text())["stages"]["accuracy"]["scenes"]
    loaded = {name: load_scene(REPO / "workflow" / "scenes" / f"{name}.yaml") for name in names}
    return {name: scene for name, scene in loaded.items() if scene.parts is not None}


def siconos_missing() -> str | None:
    """Why Siconos cannot be run here (a sentence), or None if ``SICONOS_PYTHON`` imports it."""
    try:
        done = subprocess.run([SICONOS_PYTHON, "-c", "import siconos.kernel, siconos.numerics"],
                              capture_output=True, text=True, timeout=120)
    except (OSError, subprocess.TimeoutExpired) as exc:
        return f"{SICONOS_PYTHON} cannot be started: {exc}"
    if done.returncode != 0:
        last = (done.stderr.strip().splitlines() or ["no message"])[-1]
        return f"{SICONOS_PYTHON} cannot import Siconos ({last}); install python3-siconos"
    return None


def job(parts, *, restitution, surface=None, periods=PERIODS, steps_per_period, theta=THETA,
        profile=PROFILE, activation_threshold=0.0) -> dict:
    """One run for the worker (benchmarks/siconos_worker.py): the scene in plain numbers."""
    return {"profile": {"breaks": [float(b) for b in profile.breaks], "accels": [float(a) for a in profile.accels],
                        "dt": float(profile.dt)},
            "parts": [{"x0": p.x0, "v0": p.v0, "width": p.width, "mass": p.mass, "friction_factor": p.friction_factor}
                      for p in parts],
            "surface": {"x_mu": surface.x_mu, "c_mu": surface.c_mu} if isinstance(surface, sa.StopZone) else None,
            "restitution": float(restitution), "periods": int(periods), "steps_per_period": int(steps_per_period),
            "theta": float(theta), "activation_threshold": float(activation_threshold)}


def run_siconos(runs: list[dict]) -> dict:
    """The worker's answer to ``runs`` (one process for all of them)."""
    done = subprocess.run([SICONOS_PYTHON, str(WORKER)], input=json.dumps({"runs": runs}), capture_output=True,
                          text=True, check=False)
    if done.returncode != 0:
        raise RuntimeError(f"the Siconos worker failed:\n{done.stderr[-2000:]}")
    return json.loads(done.stdout)


def reference(scene, repeats=3):
    """(end positions, CPU s: the fastest of ``repeats`` runs) of the exact solver on a scene."""
    best = float("inf")
    for _ in range(repeats):
        start = time.process_time()
        result = simulate_parts(scene.profile, scene.parts, surface=scene.surface, restitution=scene.restitution,
                                periods=scene.horizon_periods)
        best = min(best, time.process_time() - start)
    if result.status != "horizon":
        raise RuntimeError(f"the exact solver ended with {result.status}: {result.message}")
    return np.asarray(result.x_end), best


def fit_order(h, error) -> float:
    """Least-squares slope of log(error) over log(h) (NaN with fewer than two nonzero errors)."""
    h, error = np.asarray(h, dtype=float), np.asarray(error, dtype=float)
    keep = error > 0
    if keep.sum() < 2:
        return float("nan")
    return float(np.polyfit(np.log(h[keep]), np.log(error[keep]), 1)[0])


def measure(scenes=None, levels=LEVELS, shifts=SHIFTS) -> dict:
    """The work-precision table of every scene (module docstring); ``scenes``: name -> scene (default
    :data:`SCENES`), each of a piecewise-constant profile for a number of periods.

    At each level n every method runs with n, n + 1, ..., n + shifts - 1 steps per period: where the
    profile's breaks and the parts' events fall inside a step changes the error of a first-order scheme
    by a factor of ten and more (module docstring), so a row gives the largest error over those grids
    (``error``), the one at n itself (``error_n``), the mean CPU time of a run, and the largest difference
    of the end positions from moreau_parts' on the same grid (``to_moreau``).  The order is fitted to
    the largest errors."""
    moreau_parts(PROFILE, _two_parts(), periods=1)          # compiles the stepper
    scenes = SCENES if scenes is None else scenes
    report = {"profile": PROFILE.params(), "periods": PERIODS, "shifts": shifts, "scenes": {}}
    for name, scene in scenes.items():
        parts, e, surface, periods = scene.parts, scene.restitution, scene.surface, scene.horizon_periods
        x_ref, ref_cpu = reference(scene)
        grids = [n + j for n in levels for j in range(shifts)]
        ends = {"moreau_parts": [], "siconos": []}
        for n in grids:
            start = time.process_time()
            result = moreau_parts(scene.profile, parts, surface=surface, restitution=e, periods=periods,
                                  steps_per_period=n)
            ends["moreau_parts"].append((result.x_end, time.process_time() - start, {}))
        methods = {"siconos": THETA, "siconos, theta = 1": 1.0}
        if len(parts) > THETA_ONE_MAX_PARTS:
            del methods["siconos, theta = 1"]
        for method, theta in methods.items():
            answer = run_siconos([job(parts, restitution=e, surface=surface, periods=periods, steps_per_period=n,
                                      theta=theta, profile=scene.profile) for n in grids])
            report["siconos_version"] = answer["version"]
            ends[method] = [(np.asarray(got["x_end"]), got["cpu"],
                             {"gs_iterations": got["gs_iterations"], "residual": got["residual"]})
                            for got in answer["runs"]]
        rows = []
        for method, runs in ends.items():
            for i, n in enumerate(levels):
                block = runs[i * shifts:(i + 1) * shifts]
                ours = ends["moreau_parts"][i * shifts:(i + 1) * shifts]
                errors = [float(np.max(np.abs(x - x_ref))) for x, _, _ in block]
                to_moreau = [float(np.max(np.abs(x - y))) for (x, _, _), (y, _, _) in zip(block, ours)]
                rows.append({"method": method, "steps_per_period": n, "h": PROFILE.dt / n, "error": max(errors),
                             "error_n": errors[0], "cpu": float(np.mean([c for _, c, _ in block])),
                             "to_moreau": max(to_moreau),
                             "gs_iterations": max((extra.get("gs_iterations", 0) for _, _, extra in block)),
                             "residual": max((extra.get("residual", 0.0) for _, _, extra in block)),
                             "x_end": block[0][0].tolist()})
        orders = {m: fit_order(*zip(*[(r["h"], r["error"]) for r in rows if r["method"] == m])) for m in ends}
        report["scenes"][name] = {"reference_cpu": ref_cpu, "x_ref": x_ref.tolist(), "periods": periods,
                                  "restitution": e, "parts": len(parts), "rows": rows, "orders": orders}
    return report


def cradle(gap: float, h: float = 1e-3, steps: int = 4) -> dict:
    """Newton's cradle in Siconos: three equal parts 0.0625 wide, no friction, no table motion, the rear one
    at velocity 1 touching the middle one, the front one ``gap`` ahead of the middle one, e = 1; the
    velocities after ``steps`` steps of ``h``, and the model's simultaneous law
    (``selfalign.model.parts.impact_velocities``) for both contacts closed."""
    from selfalign.model.parts import IMPACT_WORK_ROWS, impact_velocities

    w = 0.0625
    parts = [{"x0": 0.0, "v0": 1.0}, {"x0": w, "v0": 0.0}, {"x0": 2 * w + gap, "v0": 0.0}]
    run = {"profile": {"breaks": [0.0, steps * h], "accels": [0.0], "dt": steps * h},
           "parts": [dict(p, width=w, mass=1.0, friction_factor=0.0) for p in parts], "surface": None,
           "restitution": 1.0, "periods": 1, "steps_per_period": steps, "theta": THETA}
    got = run_siconos([run])["runs"][0]
    law = np.empty(3)
    impact_velocities(np.array([1.0, 0.0, 0.0]), np.ones(3), 1.0, np.array([True, True]), law,
                      np.empty((IMPACT_WORK_ROWS, 3)))
    return {"gap": gap, "h": h, "siconos_v": got["v_end"], "simultaneous_law_v": law.tolist()}


def touching_chain(steps=(250, 500), threshold=1e-13) -> list[dict]:
    """The chain of 10 in Siconos with the default contact test (a contact is active if y + h/2 y' <= 0)
    and with the threshold ``threshold``: the largest difference of the end positions from moreau_parts'.
    Siconos computes a gap from the positions, so touching parts can be apart by an ulp, their contact
    inactive for a step; moreau_parts carries the gaps and touching parts stay touching exactly."""
    parts, e = SCENES["chain of 10"].parts, SCENES["chain of 10"].restitution
    found = []
    for n in steps:
        ours = moreau_parts(PROFILE, parts, restitution=e, periods=PERIODS, steps_per_period=n).x_end
        answer = run_siconos([job(parts, restitution=e, steps_per_period=n, activation_threshold=t)
                              for t in (0.0, threshold)])
        for t, got in zip((0.0, threshold), answer["runs"]):
            found.append({"steps_per_period": n, "activation_threshold": t,
                          "to_moreau": float(np.max(np.abs(np.asarray(got["x_end"]) - ours)))})
    return found


def format_table(report) -> str:
    """The report as one Markdown table per scene, with the fitted orders."""
    lines = []
    for name, scene in report["scenes"].items():
        orders = ", ".join(f"{m} {order:.2f}" for m, order in scene["orders"].items())
        lines += [f"**{name}** (exact solver: {scene['reference_cpu'] * 1e3:.1f} ms; fitted order: {orders})", "",
                  "| method | h | error (max over grids) | error at n | CPU s | to moreau_parts | GS iterations |",
                  "|---|---|---|---|---|---|---|"]
        for row in scene["rows"]:
            lines.append(f"| {row['method']} | dt/{row['steps_per_period']} | {row['error']:.2e} "
                         f"| {row['error_n']:.2e} | {row['cpu']:.3f} | {row['to_moreau']:.1e} "
                         f"| {row['gs_iterations'] or ''} |")
        lines.append("")
    return "\n".join(lines)


def work_precision(scenes=None, levels=WORK_PRECISION_LEVELS, shifts=SHIFTS) -> dict:
    """The work-precision comparison on the accuracy stage's scenes of several parts (default
    :func:`accuracy_scenes`): :func:`measure` (every method on the same grids n, ..., n + shifts - 1 per
    level: the largest error over them, the mean CPU time), and per scene and level the ratios of Siconos
    (theta = 1/2) to ``moreau_parts``: CPU time (``cpu_ratio``) and error (``error_ratio``)."""
    report = measure(accuracy_scenes() if scenes is None else scenes, levels, shifts=shifts)
    for scene in report["scenes"].values():
        ours = {row["steps_per_period"]: row for row in scene["rows"] if row["method"] == "moreau_parts"}
        scene["ratios"] = [{"steps_per_period": row["steps_per_period"],
                            "cpu_ratio": row["cpu"] / ours[row["steps_per_period"]]["cpu"],
                            "error_ratio": row["error"] / ours[row["steps_per_period"]]["error"]}
                           for row in scene["rows"] if row["method"] == "siconos"]
    return report


def work_precision_caption(report) -> str:
    """The caption of the figure of :func:`work_precision` (one paragraph)."""
    scenes = ", ".join(f"{name} ({scene['parts']} parts, e = {scene['restitution']:g}, {scene['periods']} periods)"
                       for name, scene in report["scenes"].items())
    levels = sorted({row["steps_per_period"] for scene in report["scenes"].values() for row in scene["rows"]})
    grids = (f"the largest over the grids n ... n + {report['shifts'] - 1} steps per period, against the mean CPU "
             f"time of one run" if report["shifts"] > 1 else "against the CPU time of one run")
    return (f"Work-precision of several parts on the accuracy stage's scenes ({scenes}): the largest end-position "
            f"error over the parts against the exact event-driven solver, {grids} (process time), log-log, one "
            f"panel per scene. Green circles: Siconos' Moreau-Jean time-stepping "
            f"with theta = 1/2; olive squares: theta = 1; blue triangles: moreau_parts; each at h = dt/n, "
            f"n = {levels[0]} ... {levels[-1]} (the same grids for the three). Dashed vertical "
            f"line: the CPU time of the exact solver, the reference. Siconos with theta = 1/2 takes the step "
            f"of moreau_parts (the same errors) at a larger CPU time; CPU times are this machine's and differ "
            f"from run to run.")


def plot_work_precision(report, path: Path) -> Path:
    """The figure of :func:`work_precision`, error against CPU time, written to ``path`` (PNG)."""
    from matplotlib.figure import Figure

    scenes = report["scenes"]
    fig = Figure(figsize=(5.0 * len(scenes) + 0.6, 4.6), layout="constrained")
    axes = fig.subplots(1, len(scenes), squeeze=False)[0]
    for ax, (name, scene) in zip(axes, scenes.items()):
        for method, (label, marker, color) in WORK_PRECISION_STYLE.items():
            rows = [row for row in scene["rows"] if row["method"] == method]
            if rows:
                ax.loglog([row["cpu"] for row in rows], [row["error"] for row in rows], marker=marker,
                          color=color, label=label, markersize=5, linewidth=1.0)
        ax.axvline(scene["reference_cpu"], color="k", linestyle="--", linewidth=1.0,
                   label="exact event-driven (reference)")
        ax.set_title(f"{name}: {scene['parts']} parts, e = {scene['restitution']:g}", fontsize="small")
        ax.set_xlabel("CPU time of one run [s]")
        ax.text(0.03, 0.03, "\n".join(f"order, {WORK_PRECISION_STYLE[m][0]}: {order:.2f}"
                                      for m, order in scene["orders"].items()),
                transform=ax.transAxes, ha="left", va="bottom", fontsize="x-small")
    axes[0].set_ylabel(r"end-position error, $\max_i |x_i - x_{i,\mathrm{ref}}|$")
    handles, labels = axes[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncols=4, frameon=False, fontsize="small")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=150)
    return path


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="steps dt/250 ... dt/1000 only")
    parser.add_argument("--scene", action="append", choices=tuple(SCENES), help="only this scene (repeatable)")
    parser.add_argument("--json", type=Path, default=REPO / "results" / "benchmarks" / "siconos_parts.json",
                        help="where to write the raw numbers (default results/benchmarks/siconos_parts.json)")
    args = parser.parse_args(argv)
    missing = siconos_missing()
    if missing:
        raise SystemExit(missing)
    report = measure({name: SCENES[name] for name in args.scene or SCENES}, LEVELS[:3] if args.quick else LEVELS)
    report["cradle"] = [cradle(gap) for gap in (0.0, 1e-12)]
    report["touching_chain"] = touching_chain()
    print(format_table(report))
    for case in report["cradle"]:
        print(f"Newton's cradle, e = 1, second gap {case['gap']:g}: Siconos"
              f" {np.round(case['siconos_v'], 12).tolist()}, "
              f"simultaneous law {np.round(case['simultaneous_law_v'], 12).tolist()}")
    for case in report["touching_chain"]:
        print(f"chain of 10, dt/{case['steps_per_period']}, contact threshold {case['activation_threshold']:g}: "
              f"Siconos - moreau_parts = {case['to_moreau']:.1e}")
    args.json.parent.mkdir(parents=True, exist_ok=True)
    args.json.write_text(json.dumps(report, indent=2))
    return report


if __name__ == "__main__":
    main()
