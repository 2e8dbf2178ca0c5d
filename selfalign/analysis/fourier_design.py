"""Fig. 6 (Sect. 4.4.2): the shape of a Fourier table profile optimised for the objective f of
eq. (11) under the actuator constraints, and the best three-phase profile (Sect. 4.4.3) under the
same constraints, which it is compared with.

The steady state of a trial profile comes from the exact solver
(:func:`selfalign.analysis.steady_simulation.exact_steady_state`).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..model.profiles import FourierProfile, PolynomialProfile, ThreePhaseProfile, three_phase_times
from ..progress import Progress, resolve_mode
from .classification import decision_quantities
from .sqp import dot, minimise
from .steady_simulation import SimulatedSteadyState, exact_steady_state, objective, run_periods
from .steady_state import steady_state_grid

#: f reported in the caption of the paper's Fig. 6 (inconsistent with eq. 11, see docs/explanation/stability.md).
PAPER_FIG6_F = 56.0


#: Probe offset of x'(0), relative to the velocity swing, for the slope of the period map.
PROBE = 1e-7


#: Period budget of one steady state in the Fourier optimisation (beyond it: time average).
OPTIMISER_PERIODS = 5000


def fourier_projection(profile, order: int, samples: int = 4096) -> FourierProfile:
    """The first ``order`` harmonics of a periodic profile (FFT of ``samples`` samples)."""
    t = np.arange(samples) * profile.dt / samples
    spec = np.fft.rfft(profile.position(t)) * (2.0 / samples)
    return FourierProfile(profile.dt, spec.real[1:order + 1], -spec.imag[1:order + 1])


def fourier_start(dt: float, dy: float, order: int, forward_fraction: float = 0.8) -> FourierProfile:
    """Deterministic start of the optimisation: the polynomial profile of Sect. 4.2 (the
    paper's first table motion), truncated to ``order`` harmonics and scaled to stroke dy."""
    proj = fourier_projection(PolynomialProfile(dt, dy, forward_fraction), order)
    k = dy / proj.stroke
    return FourierProfile(dt, k * proj.cos_coeffs, k * proj.sin_coeffs)


@dataclass
class FourierOptimum:
    """Result of :func:`optimise_fourier`; ``history_f``: f at the start and after every iteration;
    ``restarts``: how often the SQP restarted its quasi-Newton model (:class:`~selfalign.analysis.sqp.SQPResult`)."""

    profile: FourierProfile
    start: FourierProfile
    vbar: float
    f: float
    v0: float
    history_f: np.ndarray
    iterations: int
    evaluations: int
    success: bool
    message: str
    seconds: float
    settings: dict = field(default_factory=dict)
    restarts: int = 0


def steady_vbar_gradient(profile_of, z, steady: SimulatedSteadyState, count: int, fd_step: float) -> np.ndarray:
    """d vbar / d z[:count] of the steady state ``steady`` of ``profile_of(z)`` by implicit
    differentiation (:func:`optimise_fourier`); entries from ``count`` on are 0."""
    k, v = max(int(steady.cycle[0]), 1), float(steady.v0[0])
    base = profile_of(z)
    p0, d0 = run_periods(base, v, k)
    delta = PROBE * base.velocity_swing
    pd, dd = run_periods(base, v + delta, k)
    p_v, d_v = (pd - p0) / delta, (dd - d0) / delta
    grad = np.zeros_like(z)
    for i in range(count):
        zi = z.copy()
        zi[i] += fd_step
        pi, di = run_periods(profile_of(zi), v, k)
        p_z, d_z = (pi - p0) / fd_step, (di - d0) / fd_step
        grad[i] = (d_z + d_v * p_z / (1.0 - p_v)) / (k * base.dt)
    return grad


def harmonic_rows(dt: float, dy: float, order: int, samples: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rows mapping the coefficients (a_1..a_N, b_1..b_N) in units of dy to y / dy, y' and y''
    at t_j = j dt / samples.  cos and sin of 2 pi k j / samples come from one table indexed by
    (k j) mod samples, so every row is exactly periodic and the same bits on every machine."""
    angle = 2.0 * math.pi / samples
    cos_table = np.array([math.cos(angle * i) for i in range(samples)])
    sin_table = np.array([math.sin(angle * i) for i in range(samples)])
    k = np.arange(1, order + 1)
    phase = np.multiply.outer(np.arange(samples), k) % samples
    cos, sin = cos_table[phase], sin_table[phase]
    w = 2.0 * math.pi * k / dt
    pos = np.hstack([cos, sin])
    vel = dy * np.hstack([-sin * w, cos * w])
    acc = dy * np.hstack([-cos * w**2, -sin * w**2])
    return pos, vel, acc


def optimise_fourier(dt: float, dy: float, yd_max: float, ydd_max: float, *, order: int = 12,
                     max_iter: int = 40, samples: int | None = None, fd_step: float = 1e-9,
                     first_step: float = 0.02, min_step: float = 1e-9,
                     forward_fraction: float = 0.8, progress: str = "auto") -> FourierOptimum:
    """Fig. 6 (Sect. 4.4.2): maximise vbar (i.e. minimise f, eq. 11) over the Fourier
    coefficients of y, by the BLAS-free SQP of :mod:`selfalign.analysis.sqp`.

    Variables z: the coefficients a_k, b_k (k = 1..order) in units of dy, and the
    lower bound m of y / dy.  Constraints, on ``samples`` equally spaced times
    (default 64 (order + 1), the exact solver's event grid): m <= y / dy <= m + 1,
    i.e. stroke <= dy, |y'| <= yd_max, |y''| <= ydd_max.  All are linear in z, so every
    iterate meets them exactly on the samples (between samples a peak may exceed its
    bound by ~(pi / samples per shortest period)^2 / 2 relative).  The stroke bound is
    an inequality: a dithering profile (docs/explanation/stability.md) may do better with a slightly smaller
    stroke.  The true stroke and peaks are reported in ``settings``.

    Objective: -vbar of the steady state the exact solver reaches from rest, x'(0) = 0
    at t = 0 (:func:`exact_steady_state`; the same start for every profile, as
    dithering profiles can have several steady motions).  Gradient: implicit
    differentiation of the steady state (:func:`steady_vbar_gradient`).  A trial profile
    whose motion does not settle within OPTIMISER_PERIODS periods gets its
    time-averaged vbar.  Start: :func:`fourier_start`, scaled down if needed to meet
    the velocity and acceleration bounds.  The first step has length ``first_step`` in
    z; the optimiser stops at a first-order point or a kink, when a step is shorter
    than ``min_step``, or after ``max_iter`` iterations.  ``progress`` reports the iterations
    and f (:mod:`selfalign.progress`; ``max_iter`` is the total, the optimiser usually stops before).

    Every operation on the path is elementwise numpy, Python floats or the compiled exact
    solver, never BLAS or LAPACK, so the optimum is the same bits under every BLAS kernel
    and thread count (tests/test_sqp.py runs it under two kernels and two thread counts).
    """
    for name, value in (("dt", dt), ("dy", dy), ("yd_max", yd_max), ("ydd_max", ydd_max),
                        ("fd_step", fd_step), ("first_step", first_step), ("min_step", min_step)):
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be finite and > 0, got {value!r}")
    if isinstance(order, bool) or not isinstance(order, int) or order < 1:
        raise ValueError(f"order must be an integer >= 1, got {order!r}")
    if isinstance(max_iter, bool) or not isinstance(max_iter, int) or max_iter < 1:
        raise ValueError(f"max_iter must be an integer >= 1, got {max_iter!r}")
    resolve_mode(progress)
    samples = 64 * (order + 1) if samples is None else int(samples)
    start_time = time.perf_counter()
    start = fourier_start(dt, dy, order, forward_fraction)
    n_coef = 2 * order
    pos, vel, acc = harmonic_rows(dt, dy, order, samples)
    ones, zeros = np.ones((samples, 1)), np.zeros((samples, 1))
    # A z <= b: m - y <= 0, y - m <= 1, -+ y' <= yd_max, -+ y'' <= ydd_max.
    A = np.vstack([np.hstack([-pos, ones]), np.hstack([pos, -ones]), np.hstack([-vel, zeros]),
                   np.hstack([vel, zeros]), np.hstack([-acc, zeros]), np.hstack([acc, zeros])])
    b = np.concatenate([np.zeros(samples), np.ones(samples), np.full(2 * samples, yd_max),
                        np.full(2 * samples, ydd_max)])

    def profile_of(z):
        return FourierProfile(dt, dy * z[:order], dy * z[order:n_coef])

    cache: dict[bytes, SimulatedSteadyState] = {}

    def steady(z):
        key = z.tobytes()
        if key not in cache:
            cache[key] = exact_steady_state(profile_of(z), max_periods=OPTIMISER_PERIODS, aperiodic="average")
        return cache[key]

    coeffs = np.concatenate([start.cos_coeffs, start.sin_coeffs]) / dy
    fit = min(1.0, yd_max / float(np.max(np.abs(dot(vel, coeffs)))),
              ydd_max / float(np.max(np.abs(dot(acc, coeffs)))))
    z0 = np.concatenate([fit * coeffs, [float(np.min(dot(pos, fit * coeffs)))]])
    with Progress(max_iter, "Fourier optimisation", unit="iterations", mode=progress) as bar:
        result = minimise(lambda z: -float(steady(z).vbar[0]),
                          lambda z: -steady_vbar_gradient(profile_of, z, steady(z), n_coef, fd_step),
                          z0, A, b, first_step=first_step, min_step=min_step, max_iter=max_iter,
                          callback=lambda z, f: bar.advance(note=f"f = {float(objective(-f)):.6g}"))
    best = profile_of(result.x)
    final = steady(result.x)
    vbar = float(final.vbar[0])
    settings = {"dt": float(dt), "dy": float(dy), "yd_max": float(yd_max), "ydd_max": float(ydd_max),
                "order": order, "max_iter": max_iter, "samples": samples, "fd_step": fd_step,
                "first_step": first_step, "min_step": min_step, "forward_fraction": float(forward_fraction),
                "stroke": best.stroke, "peak_velocity": best.peak_velocity,
                "peak_acceleration": best.peak_acceleration, "cycle": int(final.cycle[0])}
    return FourierOptimum(profile=best, start=start, vbar=vbar, f=float(objective(vbar)),
                          v0=float(final.v0[0]), history_f=np.array([objective(-h) for h in result.history]),
                          iterations=result.iterations, evaluations=len(cache), success=result.converged,
                          message=result.message, seconds=time.perf_counter() - start_time,
                          settings=settings, restarts=result.restarts)


def best_three_phase(dt: float, dy: float, ydd_max: float, yd_max: float, *, num: int = 401,
                     zooms: int = 3) -> ThreePhaseProfile:
    """The three-phase profile (Sect. 4.4.3) with the smallest f (closed form, eq. 11) among
    y2'', y3'' <= ydd_max and peak table speed max|y'| <= yd_max, by a grid search over
    (y2'', y3'') refined ``zooms`` times around the best point."""
    lo2 = lo3 = ydd_max / num
    hi2 = hi3 = ydd_max
    best = None
    for _ in range(zooms + 1):
        a2, a3 = np.linspace(lo2, hi2, num), np.linspace(lo3, hi3, num)
        y2, y3 = np.meshgrid(a2, a3, indexing="ij")
        ss = steady_state_grid(dt, dy, y2, y3)
        qty = decision_quantities(dt, dy, y2, y3)
        times = three_phase_times(dt, dy, y2, y3)
        peak = np.maximum(times.yd_ini, qty["swing"] - times.yd_ini)
        vbar = np.where((ss.case > 0) & (peak <= yd_max), ss.vbar, -np.inf)
        i, j = np.unravel_index(np.argmax(vbar), vbar.shape)
        if not np.isfinite(vbar[i, j]):
            raise ValueError(f"no feasible three-phase profile with dt={dt}, dy={dy}, y'' <= {ydd_max}")
        best = (a2[i], a3[j])
        d2, d3 = 2 * (hi2 - lo2) / (num - 1), 2 * (hi3 - lo3) / (num - 1)
        lo2, hi2 = max(a2[i] - d2, lo2), min(a2[i] + d2, ydd_max)
        lo3, hi3 = max(a3[j] - d3, lo3), min(a3[j] + d3, ydd_max)
    return ThreePhaseProfile(dt, dy, *best)


def time_shift(profile: FourierProfile, shift: float) -> FourierProfile:
    """The Fourier profile t -> y(t + shift) (same steady state, other phase)."""
    arg = profile.omega * shift
    c, s = np.cos(arg), np.sin(arg)
    a, b = profile.cos_coeffs, profile.sin_coeffs
    return FourierProfile(profile.dt, a * c + b * s, b * c - a * s)


def align_to(profile: FourierProfile, reference, samples: int = 4096) -> FourierProfile:
    """``profile`` shifted in time (by a multiple of dt / samples) so that its table velocity
    y' best matches that of ``reference`` (largest circular cross-correlation)."""
    t = np.arange(samples) * profile.dt / samples
    corr = np.fft.ifft(np.fft.fft(profile.velocity(t)) * np.conj(np.fft.fft(reference.velocity(t)))).real
    return time_shift(profile, float(np.argmax(corr)) * profile.dt / samples)


def steady_motion(profile, v0: float, periods: int = 3, samples_per_period: int = 400) -> dict:
    """Mass and table over ``periods`` periods from the steady state x'(0) = v0, x(0) = 0
    (exact solver): ``t``, ``v`` (x', relative), ``y`` (table), ``x_abs`` = x + y."""
    from ..model.scene import Record, Scene
    from ..solvers.driver import simulate

    scene = Scene(profile, x0=0.0, v0=float(v0), periods=int(periods), method="exact",
                  record=Record(series=("x", "v", "y"), samples_per_period=samples_per_period))
    traj = simulate(scene)
    t, x, v, y = (np.asarray(traj.series[k], dtype=float) for k in ("t", "x", "v", "y"))
    return {"t": t, "v": v, "y": y, "x_abs": x + y}
