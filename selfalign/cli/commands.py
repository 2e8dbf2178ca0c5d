"""The subcommands of ``selfalign`` (docs/reference/cli.md), on click.

Each command checks its input, calls the library (the same calls as the workflow
scripts and docs/tutorials/first-simulation.md) and prints text or JSON.  Bad input,
a bad scene or a value the library refuses ends the command with one line on
stderr and exit code 2 (:func:`reported`); ``--debug`` prints the traceback first.
"""

from __future__ import annotations

import functools
import json
import math
import sys
import tempfile
import traceback
from dataclasses import asdict
from pathlib import Path

import click
import numpy as np

from ..analysis.classification import CASE_LABELS, classify
from ..analysis.design import design
from ..analysis.floquet import floquet
from ..analysis.positioning import MAX_PERIODS, positioning
from ..analysis.steady_state import steady_state
from ..io.design_report import design_report
from ..io.design_result import design_content
from ..io.design_spec import load_design_spec
from ..io.hdf5 import atomic_path, write_h5
from ..io.recording import write_recording
from ..io.scene_files import load_scene
from ..io.simulation_result import simulation_recording, trajectory_content
from ..model.friction import Uniform
from ..model.profiles import ThreePhaseProfile
from ..model.scene import METHODS, Scene
from ..model.units import SIScale
from ..solvers.driver import simulate as simulate_scene
from ..solvers.outcomes import Status
from .equations import markdown as equation_markdown

#: ctx.meta key set by --debug (ctx.meta is shared by the group and its subcommands).
DEBUG = "selfalign.debug"


class CommandError(click.ClickException):
    """Bad input found by the library: one line, exit code 2 (like a usage error)."""

    exit_code = 2

    def __init__(self, message: str, ctx: click.Context):
        super().__init__(message)
        self.ctx = ctx


def _set_debug(ctx: click.Context, _param, value: bool) -> None:
    if value:
        ctx.meta[DEBUG] = True


debug_option = click.option("--debug", is_flag=True, expose_value=False, callback=_set_debug,
                            help="Print the traceback of an error (default: one line).")


def reported(command):
    """Turn the library's ValueError (SceneError, DesignSpecError, NonPhysicalProfile) and OSError into one
    line and exit code 2; after --debug, print the traceback first."""

    @functools.wraps(command)
    def run(*args, **kwargs):
        try:
            return command(*args, **kwargs)
        except (ValueError, OSError) as exc:
            ctx = click.get_current_context()
            if ctx.meta.get(DEBUG):
                traceback.print_exc(file=sys.stderr)
            raise CommandError(str(exc), ctx) from exc

    return run


def output_path(_ctx, param, value: Path | None) -> Path | None:
    """An output file in a directory that exists and takes new files (checked before the run, not
    after it: a probe file is created there and removed; an unnamed one where the OS allows)."""
    if value is None:
        return value
    if not value.parent.is_dir():
        raise click.BadParameter(f"directory {str(value.parent)!r} does not exist", param=param)
    try:
        with tempfile.TemporaryFile(dir=value.parent):
            pass
    except OSError as exc:
        raise click.BadParameter(f"cannot write into directory {str(value.parent)!r} ({exc.strerror})",
                                 param=param) from None
    return value


class Count(click.ParamType):
    """A count >= 1, also written as an integral float (``1e6``); its upper bound is the library's,
    which names the limit."""

    name = "integer"

    def convert(self, value, param, ctx):
        if isinstance(value, int):
            number = value
        else:
            try:
                number = int(value)
            except ValueError:
                try:
                    real = float(value)
                except ValueError:
                    real = math.nan
                if not (math.isfinite(real) and real.is_integer()):
                    self.fail(f"{value!r} is not an integer", param, ctx)
                number = int(real)
        if number < 1:
            self.fail(f"{value!r} is not >= 1", param, ctx)
        return number


@click.group(invoke_without_command=True, no_args_is_help=False,
             epilog="Equation and section numbers refer to Hunnekens et al., Nonlinear Dyn. 65:109-129 (2011).")
@debug_option
@click.pass_context
def selfalign(ctx: click.Context) -> None:
    """Vibrational self-alignment of a rigid object exploiting friction."""
    if ctx.invoked_subcommand is None:
        click.echo(ctx.get_help())


@selfalign.command(short_help="Simulate a scene file (Sects. 3, 4.1).")
@click.argument("scene_file", metavar="SCENE.yaml", type=click.Path(dir_okay=False, path_type=Path))
@click.option("-o", "--output", type=click.Path(dir_okay=False, path_type=Path), callback=output_path,
              help="Write the result as HDF5 (the layout of results/simulation/<scene>.h5).")
@click.option("--method", type=click.Choice(METHODS),
              help="Solver (Sect. 4.1); default: the scene's. Another method than the scene's runs with its "
                   "default options.")
@click.option("--periods", type=Count(),
              help="Simulate exactly N periods instead of the scene's horizon.")
@click.option("--rerun", "rerun_file", type=click.Path(dir_okay=False, path_type=Path), callback=output_path,
              help="Write a rerun recording (.rrd) of the recorded series; the scene must record some.")
@debug_option
@reported
def simulate(scene_file: Path, output: Path | None, method: str | None, periods: int | None,
             rerun_file: Path | None) -> int:
    """Simulate a scene file (model of Sect. 3, solvers of Sect. 4.1) and print a summary."""
    scene = load_scene(scene_file)
    if method is not None and method != scene.method:
        scene = scene.replace(method=method, solver_options={})
    if periods is not None:
        scene = scene.replace(periods=periods, until="periods")
    if rerun_file is not None and not scene.record.series:
        raise ValueError(f"{scene_file}: --rerun needs recorded series; add record.series to the scene")
    traj = simulate_scene(scene)
    click.echo(summary(scene, traj))
    content = trajectory_content(traj, scene)
    if output is not None:
        write_h5(output, *content)
        click.echo(f"wrote {output}")
    if rerun_file is not None:
        write_recording(rerun_file, simulation_recording(dict(zip(("datasets", "attrs", "groups"), content))))
        click.echo(f"wrote {rerun_file}")
    return 0 if traj.success else 1


def summary(scene: Scene, traj) -> str:
    """One paragraph: method, status and message, end state, and the mean velocity where it says
    something (a free run on a uniform surface; it tends to vbar, eq. 10, once the motion is steady)."""
    dt = float(scene.profile.dt)
    t_end = traj.period_end * dt + traj.tau_end
    si = scene.si
    x_si = f" ({_values(si.to_si(traj.x_end, 'length'), '.6g')} m)" if si else ""
    text = (f"{scene.name}: {traj.method} solver, status {Status(traj.status).value} ({traj.message}); "
            f"x_end = {_values(traj.x_end, '.10g')}{x_si}, v_end = {_values(traj.v_end, '.6g')} at t = {t_end:.6g} "
            f"({traj.period_end} periods of dt = {dt:.6g} and {traj.tau_end:.6g})")
    elapsed = t_end - scene.phase * dt
    if isinstance(scene.surface, Uniform) and elapsed > 0:
        start = scene.x0 if scene.parts is None else np.array([part.x0 for part in scene.parts])
        mean = (traj.x_end - start) / elapsed
        mean_si = f" ({_values(si.to_si(mean, 'velocity'), '.6g')} m/s)" if si else ""
        text += f"; mean velocity (x_end - x0) / (t_end - t0) = {_values(mean, '.6g')}{mean_si}"
    return text + "."


def _values(value, spec: str) -> str:
    """A number in the format ``spec``, or for several parts a bracketed list of them (rear-most first)."""
    if np.ndim(value) == 0:
        return format(float(value), spec)
    return "[" + ", ".join(format(float(v), spec) for v in np.asarray(value)) + "]"


@selfalign.command(short_help="Validate scene files.")
@click.argument("scene_files", metavar="SCENE.yaml...", nargs=-1, required=True,
                type=click.Path(dir_okay=False, path_type=Path))
@debug_option
def check(scene_files: tuple[Path, ...]) -> int:
    """Validate scene files (schema, physics of Sect. 3-4, solver options): one line per file,
    "path: ok" or "path: problem"; exit code 1 if any file has a problem."""
    problems = 0
    for path in scene_files:
        try:
            load_scene(path)
        except ValueError as exc:  # SceneError names the file already
            problems += 1
            message = str(exc)
            click.echo(message if message.startswith(f"{path}:") else f"{path}: {message}")
        else:
            click.echo(f"{path}: ok")
    return 1 if problems else 0


#: Quantity kind (:data:`SIScale.DIMENSIONS`) of each reported number that has one.
KINDS = {
    "dt": "time", "dy": "length", "y2": "acceleration", "y3": "acceleration", "w": "length",
    "vbar": "velocity", "v0": "velocity", "v_max": "velocity",
    "stick_start": "time", "stick_time": "time", "forward_start": "time", "forward_time": "time",
    "backward_start": "time", "backward_time": "time",
    "dx_period": "length", "x_mu": "length", "x_stick_min": "length", "overshoot_min": "length",
    "overshoot_max": "length", "dx_d": "length", "x_d": "length",
}
SI_UNITS = {"time": "s", "length": "m", "velocity": "m/s", "acceleration": "m/s^2"}


def profile_options(command):
    """--dt --dy --y2 --y3 of the three-phase profile (Sect. 4.4.3) and --si MU G L."""
    options = [
        click.option("--dt", type=float, required=True, help="Period of the table motion."),
        click.option("--dy", type=float, required=True, help="Stroke of the table."),
        click.option("--y2", type=float, required=True, help="Deceleration (magnitude of y'') of the second phase."),
        click.option("--y3", type=float, required=True, help="Acceleration y'' of the third phase."),
        click.option("--si", type=(float, float, float), metavar="MU G L",
                     help="Give lengths in m, times in s, accelerations in m/s^2: friction coefficient MU, "
                          "gravity G [m/s^2] and length scale L [m] (a scene's si block, Sect. 3.2). "
                          "Results are reported dimensionless and in SI."),
    ]
    for option in reversed(options):
        command = option(command)
    return command


def to_dimensionless(si: SIScale | None, **values: float) -> dict[str, float]:
    return {key: si.to_dimensionless(value, KINDS[key]) if si else value for key, value in values.items()}


def three_phase_profile(dt, dy, y2, y3, si) -> tuple[ThreePhaseProfile, SIScale | None]:
    """The dimensionless profile of the --dt --dy --y2 --y3 options and the --si scale (None without)."""
    scale = SIScale(*si) if si else None
    return ThreePhaseProfile(**to_dimensionless(scale, dt=dt, dy=dy, y2=y2, y3=y3)), scale


def finite_or_none(value):
    """JSON has no NaN or infinity: null stands for them (e.g. f where vbar = 0)."""
    if isinstance(value, list):
        return [finite_or_none(v) for v in value]
    return value if isinstance(value, (int, str)) or math.isfinite(value) else None


def emit(values: dict, si: SIScale | None, as_json: bool) -> None:
    """Print ``values`` (dimensionless) as JSON or as "name = value" lines, with SI values added."""
    in_si = {key: si.to_si(value, KINDS[key]) for key, value in values.items() if si and key in KINDS}
    if as_json:
        out = {key: finite_or_none(value) for key, value in values.items()}
        if si:
            out["si"] = {"scale": si.params(), **{key: finite_or_none(value) for key, value in in_si.items()}}
        click.echo(json.dumps(out, indent=2))
        return
    for key, value in values.items():
        text = f"{value:.10g}" if isinstance(value, float) else str(value)
        if key in in_si:
            text += f" ({in_si[key]:.6g} {SI_UNITS[KINDS[key]]})"
        click.echo(f"{key} = {text}")


@selfalign.command(short_help="The equation index: each equation of the paper and its function.")
@click.option("-o", "--output", type=click.Path(dir_okay=False, path_type=Path), callback=output_path,
              help="Write the Markdown page to this file (atomically) instead of printing it.")
@debug_option
@reported
def equations(output: Path | None) -> int:
    """Print the equation index (docs/reference/equations.md): every numbered equation of the paper the
    package implements and the one function implementing it, then the unnumbered formulas."""
    text = equation_markdown()
    if output is None:
        click.echo(text, nl=False)
    else:
        with atomic_path(output) as tmp:
            tmp.write_text(text, encoding="utf-8")
    return 0


@selfalign.command("compile", short_help="Compile the solvers now, ahead of jobs that would each compile them.")
@debug_option
@reported
def compile_command() -> int:
    """Compile every entry point of the compiled solvers into numba's cache (selfalign.solvers.warmup), one
    tiny run each, and print each one's time.  Run it once on a machine (or a node of the CPU type a
    cluster's jobs run on) before a sweep or a first `snakemake -c2`: jobs that start together on an empty
    cache would each compile the same code; afterwards every process loads it (well under a second each)."""
    from ..solvers.jit import cache_root
    from ..solvers.warmup import WARMUPS, warm_up

    for name, seconds in warm_up():
        click.echo(f"{seconds:7.2f} s  {WARMUPS[name][0]}")
    click.echo(f"numba cache: {cache_root()}")
    return 0


@selfalign.command("steady-state", short_help="Steady state, case, f and Floquet multipliers (Sects. 4.4.3, 5.1, 6.1).")
@profile_options
@click.option("--json", "as_json", is_flag=True, help="Print JSON (null for NaN and infinity).")
@debug_option
@reported
def steady_state_command(dt, dy, y2, y3, si, as_json) -> None:
    """Steady state of the three-phase profile (Sect. 4.4.3) on a uniform surface: case of Table 1
    (Sect. 5.1), vbar (eq. 10), f = 1 / (c vbar^2) (eq. 11, c = 1e4), the motion's phases and the
    Floquet multipliers (Sect. 6.1)."""
    profile, scale = three_phase_profile(dt, dy, y2, y3, si)
    state = asdict(steady_state(profile))
    case = classify(profile)
    stability = floquet(profile)
    values = {"dt": profile.dt, "dy": profile.dy, "y2": profile.y2, "y3": profile.y3,
              "case": case, "case_label": CASE_LABELS[case],
              **{key: value for key, value in state.items() if key != "case"},
              "floquet_multipliers": [float(m) for m in stability.multipliers]}
    emit(values, scale, as_json)


@selfalign.command("positioning", short_help="Positioning accuracy in a stop zone (Sects. 7.1, 7.2).")
@profile_options
@click.option("--w", type=float, required=True, help="Body width = transition width of the zone (eq. 7).")
@click.option("--c-mu", type=float, required=True, help="Friction ratio of the stop zone, > 1 (eq. 7).")
@click.option("--n-entries", type=Count(), default=64, show_default=True,
              help="Steady-state entries sampled over one period (Sect. 7.1).")
@click.option("--offset", type=float, default=0.5, show_default=True,
              help="Where in its spacing each entry is sampled, in [0, 1).")
@click.option("--max-periods", type=Count(), default=MAX_PERIODS, show_default=True,
              help="Period budget; entries without an outcome by then count as undecided.")
@click.option("--json", "as_json", is_flag=True, help="Print JSON (null for NaN and infinity).")
@debug_option
@reported
def positioning_command(dt, dy, y2, y3, si, w, c_mu, n_entries, offset, max_periods, as_json) -> None:
    """Positioning accuracy of one three-phase profile entering a stop zone (Sect. 7.1-7.2, one
    point of Fig. 17, the entries of Fig. 18): Delta_x_d (eq. 39), x_d, x_stick_min (eq. 41)
    and the fractions of entries that accumulate, stop, never stop or stay undecided."""
    profile, scale = three_phase_profile(dt, dy, y2, y3, si)
    result = positioning(profile, w=to_dimensionless(scale, w=w)["w"], c_mu=c_mu, n_entries=n_entries,
                         offset=offset, max_periods=max_periods)
    scalars = ("case", "vbar", "v0", "x_mu", "x_stick_min", "overshoot_min", "overshoot_max", "dx_d", "x_d",
               "frac_accumulate", "frac_stop", "frac_never_stop", "frac_undecided", "accumulation")
    values = {"dt": profile.dt, "dy": profile.dy, "y2": profile.y2, "y3": profile.y3, "w": result.w,
              "c_mu": result.c_mu, "n_entries": n_entries, **{key: getattr(result, key) for key in scalars}}
    emit(values, scale, as_json)


@selfalign.command("design", short_help="A guaranteed self-aligning design from a machine's limits (Sects. 2, 7).")
@click.argument("spec_file", metavar="SPEC.yaml", type=click.Path(dir_okay=False, path_type=Path))
@click.option("-o", "--output", type=click.Path(dir_okay=False, path_type=Path), callback=output_path,
              help="Write the result as HDF5 (the layout of results/design/<spec>.h5, SI units).")
@click.option("--json", "as_json", is_flag=True, help="Print the chosen design as JSON (SI units; null for NaN).")
@debug_option
@reported
def design_command(spec_file: Path, output: Path | None, as_json: bool) -> int:
    """Search the three-phase profiles (Sect. 4.4.3), and the fastest table motions where the spec's
    profile.families asks for them, inside the actuator's limits of a design spec
    (SI units) for the least process time or the largest mu margin, and certify the choice: at
    every mu sample every steady-state entry into the strip ends at rest (or accumulates, eq. 41
    and Sect. 7.3), simulated with the batched exact solver, or Moreau where the spec's effects
    (Stribeck friction, y'' ramps) need it.  Exit code 1 if no design meets the spec; the report
    then says which constraint binds.  The output names the chosen design's family and, with both
    families searched, compares them (time to first arrival and to rest, simulated)."""
    result = design(load_design_spec(spec_file))
    if as_json:
        click.echo(json.dumps(design_summary(result), indent=2))
    else:
        click.echo(design_report(result))
    if output is not None:
        write_h5(output, *design_content(result))
        click.echo(f"wrote {output}")
    return 0 if result.found else 1


def design_summary(result) -> dict:
    """The chosen design's numbers in SI (JSON: null for NaN)."""
    out = {"name": result.spec.name, "found": result.found, "explanation": result.explanation,
           "family": result.family}
    if result.verification is not None:
        if result.motion is None:
            times = result.times
            out.update({"t1_s": float(times.t1), "t2_s": float(times.t2), "t3_s": float(times.t3)})
        else:
            out.update({"breaks_s": result.motion.breaks.tolist(), "accels_m_s2": result.motion.accels.tolist()})
        out.update({
            "period_s": result.period, "frequency_hz": result.frequency, "stroke_m": result.stroke,
            "y2_m_s2": result.y2, "y3_m_s2": result.y3, "c_mu": result.c_mu,
            "case": result.case, "case_label": result.case_label, "vbar_m_s": result.vbar,
            "vbar_min_m_s": result.vbar_min, "t_arrive_s": result.t_arrive, "t_rest_s": result.t_rest,
            "t_worst_s": result.t_worst,
            "x_d_m": result.x_d, "error_m": result.error, "margin": result.margin,
            "guaranteed": bool(result.verification.guaranteed[0]),
            "mu_samples": result.verification.mu.tolist(),
            "x_stick_min_m": result.verification.x_stick_min[0].tolist(),
            "dx_d_m": result.verification.dx_d[0].tolist(),
            "frac_accumulate": result.verification.frac_accumulate[0].tolist(),
            "effects": result.spec.effects(), "method": result.verification.method,
        })
    if result.gain is not None:
        out["gain"] = {key: ({k: finite_or_none(v) if isinstance(v, float) else v for k, v in value.items()}
                             if isinstance(value, dict) else finite_or_none(value))
                       for key, value in result.gain.items()}
    out["assumptions"] = list(result.assumptions)
    return {key: finite_or_none(value) if isinstance(value, (float, list)) and key != "assumptions" else value
            for key, value in out.items()}
