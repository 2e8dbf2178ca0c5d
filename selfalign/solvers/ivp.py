"""Mode-switching integration with scipy.integrate.solve_ivp: the baseline a user would write.

The inclusion x'' + y''(t) in -mu_bar(x) Sign(x') (eqs. 6, 38) is integrated one smooth
piece at a time in the current mode (DESIGN):

* forward slip (v > 0):  x'' = -y'' - mu_bar(x);  backward slip (v < 0): x'' = -y'' + mu_bar(x);
* stick (v = 0): x'' = 0.

A piece ends at a profile switch time (piecewise-constant profiles), at the period end,
or at a terminal event located by solve_ivp:

* v = 0, direction-aware (only crossings against the slip direction count);
* x = x_mu and x = x_mu + w, where mu_bar has a kink (StopZone), direction-aware so the
  boundary just crossed is not found again at the start of the next piece;
* in stick on a smooth (Fourier) profile, |y''| crossing mu_bar upwards (two events
  y'' -/+ mu_bar), integrated on the trivial ODE with max_step = dt / (16 * order) so
  that no crossing of the trigonometric polynomial is stepped over.  On piecewise-constant
  profiles stick is left at the first piece with |y''| > mu_bar, without integration.

At v = 0 the mode is decided like the model: stick iff |y''| <= mu_bar (ties stick), else
slip in the direction -sign(y'').  Velocities are set to exactly 0 at v = 0 events and
positions exactly onto a zone boundary at zone events.

Outcomes: HORIZON; REST when the mass sticks where mu_bar(x) >= max|y''| (with
until="periods" the rest of the horizon is then skipped: nothing moves any more); ERROR
with solve_ivp's message if it fails, when more than ``max_events`` events are needed
("accumulation cannot be resolved by event location"), or when the event loop stalls
(more than 100 successive events without time advancing).  With until="rest" and no rest
within max_periods the status is HORIZON with a message: this baseline does not classify
accumulation or periodic motion (see the exact and Moreau solvers).

Time is kept as (period index, tau in [0, dt)); solve_ivp integrates in tau.  Dense output
samples the solve_ivp dense output on a uniform grid of ``samples_per_period`` points per
period starting at the start time, plus every event (post-event state).
"""

from __future__ import annotations

import math
import numbers
import time

import numpy as np
from scipy.integrate import solve_ivp

from ..model.friction import StopZone
from .outcomes import (BACKWARD_SLIP, EVENT_DTYPE, FORWARD_SLIP, STICK, EventKind, Status,
                          Trajectory)
from .moreau import friction_function, model_series, reference_origin

INTEGRATORS = ("RK23", "RK45", "DOP853", "Radau", "BDF", "LSODA")
#: Default bound on the number of events (option ``max_events`` if the lead adds it).
MAX_EVENTS = 1_000_000
#: Successive events without time advancing that count as a stalled event loop.
STALL_EVENTS = 100


def _event(fun, direction):
    fun.terminal, fun.direction = True, direction
    return fun


def _options(options):
    rtol, atol = options.get("rtol", 1e-8), options.get("atol", 1e-10)
    for name, value in (("rtol", rtol), ("atol", atol)):
        if isinstance(value, bool) or not isinstance(value, numbers.Real) or not 0 < value < math.inf:
            raise ValueError(f"option {name} must be a finite number > 0, got {value!r}")
    integrator = options.get("integrator", "DOP853")
    if integrator not in INTEGRATORS:
        raise ValueError(f"option integrator must be one of {list(INTEGRATORS)}, got {integrator!r}")
    max_events = options.get("max_events", MAX_EVENTS)
    if isinstance(max_events, bool) or not isinstance(max_events, numbers.Integral) or max_events < 1:
        raise ValueError(f"option max_events must be an integer >= 1, got {max_events!r}")
    return float(rtol), float(atol), integrator, int(max_events)


class _Run:
    """State of one event-driven run: (period, tau, x relative, v, mode)."""

    def __init__(self, scene, rtol, atol, integrator):
        self.scene = scene
        self.profile = profile = scene.profile
        self.dt = profile.dt
        self.surface = scene.surface
        self.rtol, self.atol, self.integrator = rtol, atol, integrator
        self.mu_bar = friction_function(scene.surface)
        self.max_acc = float(profile.max_abs_acceleration)
        self.piecewise = profile.piecewise_constant
        if self.piecewise:
            self.switches = set(profile.breaks[1:].tolist())
        else:
            self.stick_max_step = self.dt / (16 * getattr(profile, "order", 1))
        self.x_ref = reference_origin(scene)
        self.tau0 = scene.phase * self.dt
        self.end_period = scene.horizon_periods
        self.period, self.tau = 0, self.tau0
        self.x, self.v = scene.x0 - self.x_ref, scene.v0
        self.mode = self.decide(self.tau, self.x, self.v)
        self.events = []
        self.n_events = 0
        self.stalled, self.last_event = 0, None
        self.stats = {"steps": 0, "nfev": 0, "ivp_calls": 0}
        self.dense = scene.record.dense
        spp = int(scene.record.samples_per_period)
        # Grid times within a period as offsets in (0, dt]: a point at the period start is
        # the end (dt) of the previous period, so half-open pieces (tau_a, tau_b] see it.
        grid = np.mod(self.tau0 + np.arange(spp) * (self.dt / spp), self.dt)
        self.grid = np.sort(np.where(grid == 0.0, self.dt, grid))
        self.samples = [(0, self.tau, self.x, self.v)] if self.dense else []

    # -- the model --------------------------------------------------------------------
    def acceleration(self, tau):
        """y''(tau), right-continuous at switch times."""
        if self.piecewise:
            return float(self.profile.accels[self.profile.piece_index(tau)])
        return float(self.profile.acceleration(tau))

    def decide(self, tau, x, v):
        """Mode at (tau, x, v): sign(v), or at v = 0 stick iff |y''| <= mu_bar, else slip -sign(y'')."""
        if v != 0.0:
            return FORWARD_SLIP if v > 0 else BACKWARD_SLIP
        a = self.acceleration(tau)
        if abs(a) <= self.mu_bar(x):
            return STICK
        return BACKWARD_SLIP if a > 0 else FORWARD_SLIP

    # -- bookkeeping -------------------------------------------------------------------
    @property
    def finished(self):
        return self.period > self.end_period or (self.period == self.end_period and self.tau >= self.tau0)

    def segment_end(self):
        """End of the smooth piece holding tau: next switch time, period end, or horizon end."""
        if self.piecewise:
            breaks = self.profile.breaks
            end = float(breaks[self.profile.piece_index(self.tau) + 1])
        else:
            end = self.dt
        if self.period == self.end_period:
            end = min(end, self.tau0)
        return end

    def log(self, kind):
        """Count (and record) an event at the current time and state."""
        self.n_events += 1
        now = (self.period, self.tau)
        self.stalled = self.stalled + 1 if now == self.last_event else 0
        self.last_event = now
        if self.scene.record.events:
            self.events.append((int(kind), self.period, self.tau, self.x_ref + self.x, self.v, self.mode))

    def sample(self, tau_a, tau_b, state_at):
        """Grid samples of the current period in (tau_a, tau_b]."""
        if self.dense:
            g = self.grid[(self.grid > tau_a) & (self.grid <= tau_b)]
            if self.period == 0:
                g = g[g > self.tau0]
            if self.period == self.end_period:
                g = g[g <= self.tau0]
            if g.size:
                xs, vs = state_at(g)
                wrap = g >= self.dt
                self.samples.extend(zip(self.period + wrap, np.where(wrap, 0.0, g), xs, vs))

    def set_time(self, tau):
        """Move the clock to ``tau`` of the current period; tau = dt is the next period's start."""
        self.period, self.tau = (self.period + 1, 0.0) if tau >= self.dt else (self.period, tau)

    # -- one piece ---------------------------------------------------------------------
    def step(self):
        """Integrate one smooth piece (or up to the first event in it); None or (status, message)."""
        tau_a, tau_b = self.tau, self.segment_end()
        if self.mode == STICK:
            if self.mu_bar(self.x) >= self.max_acc:
                return Status.REST, None
            return self.stick(tau_a, tau_b)
        return self.slip(tau_a, tau_b)

    def end_piece(self, tau_b):
        """Stay stuck to the piece end."""
        x = self.x
        self.sample(self.tau, tau_b, lambda g: (np.full(g.size, x), np.zeros(g.size)))
        self.finish_piece(tau_b)

    def finish_piece(self, tau_b):
        """Clock to the piece end; a profile switch there is an event."""
        self.set_time(tau_b)
        if self.piecewise and tau_b in self.switches:
            # y'' jumps: at v = 0 the new piece decides between stick and slip.
            if self.v == 0.0:
                self.mode = self.decide(self.tau, self.x, 0.0)
            self.log(EventKind.SWITCH)
            self.record_event_sample()

    def stick(self, tau_a, tau_b):
        if self.piecewise:
            # Stick persists through this piece (decided at its start).
            self.end_piece(tau_b)
            return None
        mu = self.mu_bar(self.x)
        sol = solve_ivp(lambda t, y: (0.0, 0.0), (tau_a, tau_b), [self.x, 0.0], method=self.integrator,
                        rtol=self.rtol, atol=self.atol, max_step=self.stick_max_step,
                        events=[_event(lambda t, y: self.acceleration(t) - mu, 1),
                                _event(lambda t, y: self.acceleration(t) + mu, -1)])
        self.count(sol)
        if sol.status == -1:
            return Status.ERROR, f"solve_ivp failed in stick at period {self.period}, tau {tau_a!r}: {sol.message}"
        if sol.status == 1:
            which = 0 if sol.t_events[0].size else 1
            tau_e = float(sol.t_events[which][0])
            # The root may sit an ulp before the crossing; slip starts where |y''| > mu_bar.
            for _ in range(64):
                if abs(self.acceleration(tau_e)) > mu or tau_e >= tau_b:
                    break
                tau_e = math.nextafter(tau_e, math.inf)
            self.sample(tau_a, tau_e, lambda g: (np.full(g.size, self.x), np.zeros(g.size)))
            self.mode = BACKWARD_SLIP if which == 0 else FORWARD_SLIP
            self.set_time(tau_e)
            self.log(EventKind.SLIP)
            self.record_event_sample()
            return None
        self.end_piece(tau_b)
        return None

    def slip(self, tau_a, tau_b):
        s = float(self.mode)
        mu_bar = self.mu_bar
        if self.piecewise:
            a = self.acceleration(tau_a)
            rhs = lambda t, y: (y[1], -a - s * mu_bar(y[0]))
        else:
            acc = self.acceleration
            rhs = lambda t, y: (y[1], -acc(t) - s * mu_bar(y[0]))
        events = [_event(lambda t, y: y[1], -s)]
        bounds = (0.0, self.surface.w) if isinstance(self.surface, StopZone) else ()
        for b in bounds:
            side = -1.0 if (self.x > b or (self.x == b and s > 0)) else 1.0
            events.append(_event(lambda t, y, b=b: y[0] - b, side))
        sol = solve_ivp(rhs, (tau_a, tau_b), [self.x, self.v], method=self.integrator, rtol=self.rtol,
                        atol=self.atol, events=events, dense_output=self.dense)
        self.count(sol)
        if sol.status == -1:
            return Status.ERROR, f"solve_ivp failed in slip at period {self.period}, tau {tau_a!r}: {sol.message}"
        if sol.status == 1:
            which = next(i for i, te in enumerate(sol.t_events) if te.size)
            tau_e = float(sol.t_events[which][0])
            x_e, v_e = (float(c) for c in sol.y_events[which][0])
            self.sample(tau_a, tau_e, lambda g: sol.sol(g))
            self.set_time(tau_e)
            if which == 0:
                self.x, self.v = x_e, 0.0
                self.mode = self.decide(self.tau, x_e, 0.0)
                self.log(EventKind.STICK if self.mode == STICK else EventKind.REVERSAL)
            else:
                self.x, self.v = bounds[which - 1], v_e
                self.log(EventKind.ZONE)
            self.record_event_sample()
            return None
        self.sample(tau_a, tau_b, lambda g: sol.sol(g))
        self.x, self.v = float(sol.y[0, -1]), float(sol.y[1, -1])
        self.finish_piece(tau_b)
        return None

    def count(self, sol):
        self.stats["steps"] += sol.t.size - 1
        self.stats["nfev"] += sol.nfev
        self.stats["ivp_calls"] += 1

    def record_event_sample(self):
        """Sample the post-event state (replacing a grid sample at the same time)."""
        if self.dense:
            if self.samples[-1][:2] == (self.period, self.tau):
                self.samples.pop()
            self.samples.append((self.period, self.tau, self.x, self.v))

    def rest_of_horizon(self):
        """Stuck for good in a horizon run: fill the remaining samples and jump to the end."""
        if self.dense:
            x = self.x
            while not self.finished:
                tau_b = self.dt if self.period < self.end_period else self.tau0
                self.sample(self.tau, tau_b, lambda g: (np.full(g.size, x), np.zeros(g.size)))
                self.set_time(tau_b)
        self.period, self.tau = self.end_period, self.tau0


def solve(scene, options: dict) -> Trajectory:
    """Simulate ``scene`` by mode switching with solve_ivp (see the module docstring)."""
    rtol, atol, integrator, max_events = _options(options)
    cpu0 = time.process_time()
    run = _Run(scene, rtol, atol, integrator)
    status, message = Status.HORIZON, ""
    while not run.finished:
        outcome = run.step()
        if outcome is not None:
            status, message = outcome
            if status is Status.REST:
                if scene.until == "rest":
                    x = run.x_ref + run.x
                    message = (f"at rest for good: stuck at x = {x!r} where mu_bar = {run.mu_bar(run.x)!r} "
                               f">= max|y''| = {run.max_acc!r}")
                    break
                status = Status.HORIZON
                run.rest_of_horizon()
                continue
            break
        if run.n_events > max_events:
            status = Status.ERROR
            message = (f"stopped after {run.n_events} events (max_events = {max_events}) at period "
                       f"{run.period}: accumulation cannot be resolved by event location")
            break
        if run.stalled > STALL_EVENTS:
            status = Status.ERROR
            message = (f"event loop stalled: {run.stalled} successive events at period {run.period}, "
                       f"tau {run.tau!r} without time advancing")
            break
    if status is Status.HORIZON:
        message = f"simulated {run.period} periods (solve_ivp {integrator}, rtol={rtol!r}, atol={atol!r})"
        if scene.until == "rest":
            message = (f"not at rest after max_periods = {scene.horizon_periods} periods; the ivp baseline "
                       f"does not classify accumulation or periodic motion")
    series = {}
    if run.dense:
        if run.samples[-1][:2] != (run.period, run.tau):
            run.samples.append((run.period, run.tau, run.x, run.v))
        arr = np.array(run.samples, dtype=float).reshape(-1, 4)
        series = model_series(scene, scene.record.series, arr[:, 0], arr[:, 1], arr[:, 2], arr[:, 3], run.x_ref)
    events = np.array(run.events, dtype=EVENT_DTYPE) if scene.record.events else None
    info = {}
    if isinstance(scene.surface, StopZone):
        info["x_stick_min"] = scene.surface.x_stick_min(run.max_acc)
    return Trajectory(
        x_end=float(run.x_ref + run.x), v_end=float(run.v), period_end=int(run.period), tau_end=float(run.tau),
        status=status, message=message, method="ivp", options=dict(options), series=series, events=events,
        stats={"events": run.n_events, "cpu_time": time.process_time() - cpu0, **run.stats}, info=info,
    )
