"""Mode-switching integration with scipy.integrate.solve_ivp (``method="ivp"``): the baseline a user would write.

The inclusion x'' + y''(t) in -mu_bar(x) Sign(x') (eqs. 6, 38) is integrated one smooth
piece at a time in the current mode:

* forward slip (v > 0):  x'' = -y'' - mu_bar(x);  backward slip (v < 0): x'' = -y'' + mu_bar(x);
  under Stribeck friction mu_bar(x) times mu(v) / mu_k (:func:`selfalign.model.friction.stribeck_factor`);
* stick (v = 0): x'' = 0, while |y''| <= r mu_bar(x) (r = mu_s / mu_k, 1 for Coulomb friction).

A piece ends at a profile break (piecewise-constant y'', and the piecewise-linear y'' of a
finite-jerk profile), at a period boundary
(the start phase), or at a terminal event located by solve_ivp:

* v = 0, direction-aware (only crossings against the slip direction count); a slip from rest
  locates v / (t - t_start), the mean acceleration since its start, which has v's later roots
  but not the start itself (solve_ivp finds a root at the start again when its first step
  overshoots a short slip);
* x = x_mu and x = x_mu + w, where mu_bar has a kink (StopZone), direction-aware so the
  boundary just crossed is not found again at the start of the next piece;
* in stick on a smooth (Fourier, piecewise-linear) profile, |y''| crossing the stick limit
  r mu_bar upwards (two events y'' -/+ r mu_bar), integrated on the trivial ODE with
  max_step = dt / (16 * order) (a piecewise-linear y'' crosses at most once per piece) so
  that no crossing is stepped over.  On piecewise-constant profiles stick is left at the
  first piece with |y''| > r mu_bar, without integration.

Under Stribeck friction a slip step is at most v_s / (max|y''| + r max mu_bar) long: v changes
by at most v_s in one step, so no step crosses the band |v| ~ v_s where mu rises to mu_s with
no stage inside it (its error estimate would see mu_k only and accept an error far above rtol);
a v_s so small that a period would need more than 1e6 such steps is refused before the run
(:func:`selfalign.solvers.methods.check_ivp_work`).  rtol and atol are bounded
(:data:`selfalign.solvers.methods.IVP_RTOL`, ``IVP_ATOL``).

x is monotone in a slip, so a slip crosses each zone boundary at most once, and never the one it
starts on (which is no event of it).  A step that ends past a boundary has evaluated the far
side's mu_bar in its last stages; solve_ivp's error estimate does not see the kink, and the
dense output the crossing is located on is bent by far more than rtol (4.5e-9 in x' at rtol
1e-12 in tests/test_ivp.py).  A slip that crosses a boundary is therefore integrated again up to
the located crossing, so that its last step ends there.  A step that crosses a boundary and, past
x' = 0, comes back (the ODE of the mode goes on beyond the slip's end) shows solve_ivp no sign
change of x - b; a slip that stops beyond a boundary it did not report is likewise integrated
again up to its stop, where the crossing is a sign change of the last step.

At v = 0 the mode is decided like the model (:func:`selfalign.model.friction.decide_mode`),
at the first time (at most 64 ulps on) where it differs from the slip that just ended: a slip
shorter than an ulp of t ends at its own start time, where the model still says slip.
A stick ends by the same rule: its exit events are positive exactly where decide_mode says
slip, so a |y''| equal to r mu_bar to rounding (a plateau at x_stick_min) holds the stick as in
the exact solver, where a plain |y''| - r mu_bar, zero there, would be a crossing to solve_ivp.
A slip whose v passes through 0 and back within one step is not seen (solve_ivp locates
events by sign changes at step ends): on the grazing Fourier profile of tests/test_studies.py
a reversal is stepped over once in 12 periods at every rtol from 1e-8 to 1e-13.
Velocities are set to exactly 0 at v = 0 events and positions exactly onto a zone
boundary at zone events.

The outcome decisions are those of every method, made by the compiled driver's own
functions (:mod:`selfalign.solvers.engine`: REST and ACCUMULATION at stick events, the
period-boundary cycle tests, the horizon); this module only steps.  Event location at a
finite tolerance rarely repeats a period-boundary state to the driver's tolerance, so a
periodic motion inside the zone usually ends with HORIZON (reason BOUNDED) here.  The
event budget ``max_events`` bounds an accumulation, whose infinitely many ever shorter
slips event location cannot resolve (ERROR, reason MAX_EVENTS), and a stalled event loop
is an ERROR too (reason STALL): more than STALL_EVENTS successive events, each within
STALL_ULPS ulp of dt of the one before, as a mode chattering in ulp-long steps makes (the tie
rule prevents it; the guard bounds the work should it break).  Dense output samples solve_ivp's
dense output on a uniform grid of ``samples_per_period`` points per period from the start time,
plus every event.
"""

from __future__ import annotations

import math

import numpy as np

from ..model.friction import StopZone, coefficient, decide_mode, stribeck_factor
from . import records as R
from .engine.codes import DONE, STOP_BUDGET, STOP_STALL
from .jit import call, kernel
from .methods import ivp_slip_step
from .outcomes import HIGH, LOW, MAX_CYCLE, STALL_EVENTS, STALL_ULPS, ZONE, EventKind, Reason

#: The slip modes a stick can end in, in the order of the stick's exit events.
_SLIP_MODES = (-1, 1)


def _event(fun, direction):
    fun.terminal, fun.direction = True, direction
    return fun


class _Run:
    """State of one event-driven run: time (period p, tau), x relative to the origin, v, mode."""

    def __init__(self, scene, options, members, origin):
        self.scene = scene
        self.profile = profile = scene.profile
        self.dt = profile.dt
        self.surface = scene.surface
        self.zone = isinstance(scene.surface, StopZone)
        self.law = scene.friction
        self.rtol, self.atol, self.integrator = options["rtol"], options["atol"], options["integrator"]
        self.piecewise = profile.piecewise_constant
        # The integration stops at every break (y'' jumps or bends there); a Fourier profile has none.
        self.breaks = getattr(profile, "breaks", None)
        if self.piecewise:
            self.switches = set(profile.breaks[1:].tolist())      # the period end is a switch too
        else:
            self.stick_max_step = self.dt / (16 * getattr(profile, "order", 1))
        self.slip_max_step = ivp_slip_step(profile, self.surface, self.law)     # Stribeck friction
        self.origin = origin
        self.tau0 = scene.phase * self.dt
        self.p, self.tau = 0, self.tau0
        self.x, self.v = float(members[0]["xi"]), float(members[0]["v"])
        self.mode = int(members[0]["mode"])
        self.events = []
        self.n_events = 0
        self.stalled, self.last_event = 0, None
        self.stall_time = STALL_ULPS * math.ulp(self.dt)
        self.stats = {"steps": 0, "nfev": 0, "ivp_calls": 0}
        self.dense = scene.record.dense
        spp = int(scene.record.samples_per_period)
        # Grid times within a period as offsets in (0, dt]: a point at the period start is
        # the end (dt) of the previous period, so half-open pieces (tau_a, tau_b] see it.
        grid = np.mod(self.tau0 + np.arange(spp) * (self.dt / spp), self.dt)
        self.grid = np.sort(np.where(grid == 0.0, self.dt, grid))
        self.samples = [(0, self.tau, self.x, self.v)] if self.dense else []
        # The period since the last boundary: start state, extremes, regions visited.
        self.boundary_x = self.x
        self.lo = self.hi = 0.0
        self.regions = 0

    # -- the model --------------------------------------------------------------------
    def mu_bar(self, x):
        return coefficient(x, self.surface.w, self.surface.c_mu) if self.zone else 1.0

    def acceleration(self, tau):
        """y''(tau), right-continuous at switch times."""
        if self.piecewise:
            return float(self.profile.accels[self.profile.piece_index(tau)])
        return float(self.profile.acceleration(tau))

    def decide(self, tau, x, v):
        """Mode at (tau, x, v): sign(v), or at v = 0 the stick/slip rule of the model."""
        if v != 0.0:
            return 1 if v > 0 else -1
        return decide_mode(self.acceleration(tau), self.law.ratio * self.mu_bar(x))

    def slip_friction(self, x, v):
        """Friction magnitude in slip at (x, v): mu_bar(x), times mu(v)/mu_k under Stribeck friction."""
        law = self.law
        if law.stribeck:
            return self.mu_bar(x) * stribeck_factor(abs(v), law.ratio, law.v_s, law.delta)
        return self.mu_bar(x)

    def xdd(self, tau, x, mode):
        return 0.0 if mode == 0 else -self.acceleration(tau) - mode * self.slip_friction(x, self.v)

    def region(self, x0, x1):
        if not self.zone or max(x0, x1) <= 0.0:
            return LOW
        return HIGH if min(x0, x1) >= self.surface.w else ZONE

    # -- bookkeeping -------------------------------------------------------------------
    def segment_end(self):
        """End of the smooth piece holding tau: next switch, the period boundary tau0, or dt."""
        end = self.dt
        if self.breaks is not None:
            piece = min(int(np.searchsorted(self.breaks, self.tau, side="right")) - 1, self.breaks.size - 2)
            end = float(self.breaks[piece + 1])
        if self.tau < self.tau0 < end:
            end = self.tau0
        return end

    def log(self, kind, mode_before):
        """Count (and record) an event at the current time and state; events that follow each other
        within ``stall_time`` count towards a stall (chattering)."""
        self.n_events += 1
        now = (self.p, self.tau)
        last = self.last_event
        advance = math.inf if last is None else (now[0] - last[0]) * self.dt + (now[1] - last[1])
        self.stalled = self.stalled + 1 if advance <= self.stall_time else 0
        self.last_event = now
        if self.scene.record.events:
            self.events.append((int(kind), self.p, self.tau, self.x, self.v, mode_before, self.mode,
                                self.xdd(self.tau, self.x, mode_before), self.xdd(self.tau, self.x, self.mode)))

    def sample(self, tau_a, tau_b, state_at):
        """Grid samples of the current period in (tau_a, tau_b]."""
        if self.dense:
            g = self.grid[(self.grid > tau_a) & (self.grid <= tau_b)]
            if g.size:
                xs, vs = state_at(g)
                wrap = g >= self.dt
                self.samples.extend(zip(self.p + wrap, np.where(wrap, 0.0, g), xs, vs))

    def moved(self, x0, x1):
        self.regions |= 1 << self.region(x0, x1)
        d = x1 - self.boundary_x
        self.lo, self.hi = min(self.lo, d), max(self.hi, d)

    def set_time(self, tau):
        """Move the clock to ``tau`` of the current period; tau = dt is the next period's start."""
        self.p, self.tau = (self.p + 1, 0.0) if tau >= self.dt else (self.p, tau)

    def at_boundary(self):
        return self.tau == self.tau0 and self.p > 0

    def record_event_sample(self):
        """Sample the post-event state (replacing a grid sample at the same time)."""
        if self.dense:
            if self.samples and self.samples[-1][:2] == (self.p, self.tau):
                self.samples.pop()
            self.samples.append((self.p, self.tau, self.x, self.v))

    # -- one piece ---------------------------------------------------------------------
    def step(self, stick):
        """Integrate one smooth piece (or up to the first event in it).  ``stick(x, mu)``
        reports a stick event to the driver and returns its stop code.  Returns a stop
        code, or (reason, detail) when solve_ivp fails."""
        tau_a, tau_b = self.tau, self.segment_end()
        if self.mode == 0:
            return self.stick(tau_a, tau_b)
        return self.slip(tau_a, tau_b, stick)

    def finish_piece(self, tau_b, stick):
        """Clock to the piece end; a profile switch there is an event, which at v = 0
        re-decides the mode with the new piece's y''."""
        self.set_time(tau_b)
        if self.piecewise and tau_b in self.switches:
            before = self.mode
            if self.v == 0.0:
                self.mode = self.decide(self.tau, self.x, 0.0)
            self.log(EventKind.SWITCH, before)
            self.record_event_sample()
            if before != 0 and self.mode == 0:
                return stick(self.x, self.mu_bar(self.x))
        return DONE

    def stick(self, tau_a, tau_b):
        from scipy.integrate import solve_ivp

        x = self.x
        if self.piecewise:
            # Stick persists through this piece (decided at its start).
            self.sample(tau_a, tau_b, lambda g: (np.full(g.size, x), np.zeros(g.size)))
            self.moved(x, x)
            return self.finish_piece(tau_b, None)
        mu = self.law.ratio * self.mu_bar(x)          # the static limit
        sol = solve_ivp(lambda t, y: (0.0, 0.0), (tau_a, tau_b), [x, 0.0], method=self.integrator,
                        rtol=self.rtol, atol=self.atol, max_step=self.stick_max_step,
                        events=[_event(self.stick_exit(mu, mode), 1) for mode in _SLIP_MODES])
        self.count(sol)
        if sol.status == -1:
            return Reason.SOLVER_FAILED, f"solve_ivp failed in stick at period {self.p}, tau {tau_a!r}: {sol.message}"
        self.moved(x, x)
        if sol.status == 1:
            which = 0 if sol.t_events[0].size else 1
            # The root may sit an ulp before the crossing; slip starts where the model's rule says slip.
            tau_e = _first_time(float(sol.t_events[which][0]), tau_b,
                                lambda t: decide_mode(self.acceleration(t), mu) != 0)
            self.sample(tau_a, tau_e, lambda g: (np.full(g.size, x), np.zeros(g.size)))
            self.mode = _SLIP_MODES[which]
            self.set_time(tau_e)
            self.log(EventKind.SLIP, 0)
            self.record_event_sample()
            return DONE
        self.sample(tau_a, tau_b, lambda g: (np.full(g.size, x), np.zeros(g.size)))
        return self.finish_piece(tau_b, None)

    def stick_exit(self, mu, mode):
        """The event function of a stick ending in slip ``mode`` (-1 or 1) at the static limit ``mu``:
        -mode y'' - mu, positive exactly where the model's rule (:func:`decide_mode`) says slip in
        ``mode``.  solve_ivp takes a zero for a crossing, so where the rule says stick the value is
        kept below 0: a |y''| that equals mu to rounding (a plateau on x_stick_min) holds the stick,
        as it does in the exact solver, instead of slipping for an ulp and sticking again."""
        def exit_value(t, y):
            a = self.acceleration(t)
            value = -mode * a - mu
            return value if decide_mode(a, mu) == mode else min(value, -math.ulp(0.0))
        return exit_value

    def slip(self, tau_a, tau_b, stick):
        from scipy.integrate import solve_ivp

        s = float(self.mode)
        coefficient_at = self.mu_bar
        # Stribeck friction depends on v; Coulomb and static/kinetic slip on x alone.
        mu_bar = self.slip_friction if self.law.stribeck else lambda x, v: coefficient_at(x)  # noqa: E731
        if self.piecewise:
            a = self.acceleration(tau_a)
            rhs = lambda t, y: (y[1], -a - s * mu_bar(y[0], y[1]))  # noqa: E731
        else:
            acc = self.acceleration
            rhs = lambda t, y: (y[1], -acc(t) - s * mu_bar(y[0], y[1]))  # noqa: E731
        events = [_event(self.velocity_event(tau_a), -s)]
        # x is monotone in a slip (it ends at x' = 0), so a boundary the slip starts on is never
        # crossed in it: only the others are events, each in the direction the slip moves.
        bounds = tuple(b for b in ((0.0, self.surface.w) if self.zone else ()) if b != self.x)
        for b in bounds:
            events.append(_event(lambda t, y, b=b: y[0] - b, -1.0 if self.x > b else 1.0))
        x0 = self.x
        t_end = tau_b
        while True:
            sol = solve_ivp(rhs, (tau_a, t_end), [x0, self.v], method=self.integrator, rtol=self.rtol,
                            atol=self.atol, max_step=self.slip_max_step, events=events, dense_output=self.dense)
            self.count(sol)
            if sol.status != 1 or t_end != tau_b:
                break
            # A step that ends past an event has evaluated the ODE of this mode beyond it, where the
            # model no longer holds, and solve_ivp's error estimate does not see it:
            # * past a zone boundary, mu_bar has a kink; the stages beyond it bend the step's dense
            #   output by far more than rtol (at rtol 1e-12, 4.5e-9 in x' at one crossing of a zone
            #   1e-3 wide with c_mu 4.7), and the crossing is located on that output;
            # * past x' = 0, a step that carries x across a boundary and back shows no change of
            #   x - b: the slip then ends on the far side of a boundary it never reported, integrated
            #   across the kink.  Since x is monotone up to x' = 0, that happened iff the stop lies
            #   beyond a boundary.
            # Integrating again up to the event ends the last step there (with every stage on the
            # near side), and a crossing before it is a sign change of a step.
            first = next(i for i, te in enumerate(sol.t_events) if te.size)
            if first == 0:
                x_stop = float(sol.y_events[0][0][0])
                if not any(min(x0, x_stop) < b < max(x0, x_stop) for b in bounds):
                    break
            t_end = float(sol.t_events[first][0])
        if sol.status == -1:
            return Reason.SOLVER_FAILED, f"solve_ivp failed in slip at period {self.p}, tau {tau_a!r}: {sol.message}"
        if sol.status == 0 and t_end != tau_b:           # the event, reached again at the end of the last step
            sol.status, sol.t_events[first], sol.y_events[first] = 1, sol.t[-1:], sol.y[:, -1:].T
        if sol.status == 1:
            which = next(i for i, te in enumerate(sol.t_events) if te.size)
            tau_e = float(sol.t_events[which][0])
            x_e, v_e = (float(c) for c in sol.y_events[which][0])
            before = self.mode
            if which == 0:
                # x' came back through 0 against the slip, so the model cannot go on slipping this
                # way; where it still says so at the root, the root sits ulps early (a slip shorter
                # than an ulp of tau): the mode is decided at the first time the decision changes.
                tau_e = _first_time(tau_e, tau_b, lambda t: self.decide(t, x_e, 0.0) != before)
            self.sample(tau_a, tau_e, lambda g: sol.sol(g))
            self.set_time(tau_e)
            if which == 0:
                self.x, self.v = x_e, 0.0
                self.mode = self.decide(self.tau, x_e, 0.0)
                self.log(EventKind.STICK if self.mode == 0 else EventKind.REVERSAL, before)
            else:
                self.x, self.v = bounds[which - 1], v_e
                self.log(EventKind.ZONE, before)
            self.moved(x0, self.x)
            self.record_event_sample()
            if which == 0 and self.mode == 0:
                return stick(self.x, self.mu_bar(self.x))
            return DONE
        self.sample(tau_a, tau_b, lambda g: sol.sol(g))
        self.x, self.v = float(sol.y[0, -1]), float(sol.y[1, -1])
        self.moved(x0, self.x)
        return self.finish_piece(tau_b, stick)

    def velocity_event(self, tau_a):
        """The event function of x' = 0 for a slip from ``tau_a``.  A slip from rest starts at
        a root of x' itself, which solve_ivp finds again at tau_a whenever its first step overshoots
        a slip shorter than the step (y'' turning back towards the stick band).  x' / (t - tau_a),
        the mean acceleration since the start, has the same later roots and at tau_a the limit
        x''(tau_a), nonzero with the slip's sign: the slip then ends at its true end."""
        if self.v != 0.0:
            return lambda t, y: y[1]
        start = self.xdd(tau_a, self.x, self.mode)
        return lambda t, y: y[1] / (t - tau_a) if t > tau_a else start

    def count(self, sol):
        self.stats["steps"] += sol.t.size - 1
        self.stats["nfev"] += sol.nfev
        self.stats["ivp_calls"] += 1


def solve(scene, options: dict, cpu0: float):
    """Simulate ``scene`` by mode switching with solve_ivp (module docstring); the outcome
    decisions are the compiled driver's."""
    import time

    from .assembly import scene_member, trajectory

    K = kernel()
    profile = scene.profile
    members, origin = scene_member(scene)
    amax = float(profile.max_abs_acceleration)
    row = np.array(R.profile_header(profile.dt, amax, profile.velocity_swing, amax))
    until = R.UNTIL_CODES[scene.until]
    total = scene.horizon_periods
    a0 = float(profile.acceleration(scene.phase * profile.dt))
    code = call(K.begin_entry, members, row, -1, options["accumulation_tol"], a0, until)
    run = _Run(scene, options, members, origin)
    hist = R.records(R.HIST_DTYPE, MAX_CYCLE)
    count, reason, detail = 0, -1, ""
    s = members[0]

    def stick(x, mu):
        return int(call(K.stick_entry, members, x, mu, run.p, run.tau, until))

    def stop(code_):
        s["xi"], s["v"], s["mode"] = run.x, run.v, run.mode
        s["stop_n"], s["stop_tau"] = (run.p, run.tau)
        return code_

    while code == DONE and (run.p, run.tau) < (total, run.tau0):    # the horizon is (total, tau0)
        out = run.step(stick)
        if isinstance(out, tuple):
            reason, detail = int(out[0]), out[1]
            stop(DONE)
            s["stop_n"], s["stop_tau"] = run.p, run.tau
            break
        call(K.moved_entry, members, s["xi"], run.x)
        s["xi"] = run.x
        if out != DONE:
            code = stop(out)
            break
        if run.n_events > options["max_events"]:
            code = stop(STOP_BUDGET)
            break
        if run.stalled > STALL_EVENTS:
            code = stop(STOP_STALL)
            break
        if run.at_boundary():
            v0, mode0, xi0, path0 = s["v"], s["mode"], run.boundary_x, s["path"]
            s["xi"], s["v"], s["mode"], s["n"] = run.x, run.v, run.mode, run.p
            s["dxp"], s["lo"], s["hi"], s["regions"] = run.x - run.boundary_x, run.lo, run.hi, run.regions
            # Skipping repeating periods (as the compiled steppers do) is allowed when nothing is
            # recorded, or for a mass at rest for good when only series are: their samples are
            # filled in.  Never while the event log is kept.
            skip = not (run.dense or scene.record.events) or (bool(s["at_rest"]) and not scene.record.events)
            reason, count, horizon = call(K.after_period_entry, members, hist, count, MAX_CYCLE,
                                          float(row[R.SWING]), until, total, skip, v0, mode0, xi0, path0)
            if int(s["n"]) != run.p:                 # fast-forward (stuck for good)
                _fill_stuck(run, int(s["n"]))
                run.p, run.x = int(s["n"]), float(s["xi"])
            run.boundary_x, run.lo, run.hi, run.regions = run.x, 0.0, 0.0, 0
            if reason >= 0 or horizon:
                break
    if reason < 0 and code == DONE:
        s["xi"], s["v"], s["mode"], s["n"] = run.x, run.v, run.mode, run.p
    call(K.finish_entry, members, code, reason, until)
    samples = None
    if run.dense:
        end = (int(s["n_end"]), float(s["tau_end"]), float(s["xi"]), float(s["v"]))
        if not run.samples or run.samples[-1][:2] != end[:2]:
            run.samples.append(end)
        samples = np.zeros(len(run.samples), dtype=R.SAMPLE_DTYPE)
        arr = np.array(run.samples, dtype=float).reshape(-1, 4)
        samples["period"], samples["tau"], samples["x"], samples["v"] = arr[:, 0], arr[:, 1], arr[:, 2], arr[:, 3]
    events = np.array(run.events, dtype=R.EVENT_DTYPE) if scene.record.events else None
    traj = trajectory(scene, "ivp", options, -1, row, members[0], origin, None, events, samples,
                       time.process_time() - cpu0, detail)
    traj.stats.update(run.stats, events=run.n_events)
    return traj


def _first_time(tau, tau_end, holds):
    """The first float time t >= ``tau`` where ``holds(t)``, for a root located ulps early: at
    most 64 ulps on and never past ``tau_end`` (the last time tried when none holds)."""
    for _ in range(64):
        if holds(tau) or tau >= tau_end:
            break
        tau = math.nextafter(tau, math.inf)
    return tau


def _fill_stuck(run, n_end):
    """Dense samples of a mass stuck for good from the current boundary up to period n_end."""
    if run.dense:
        x = run.x
        while run.p < n_end:
            run.sample(run.tau0, run.dt, lambda g: (np.full(g.size, x), np.zeros(g.size)))
            run.p += 1
            run.sample(0.0, run.tau0, lambda g: (np.full(g.size, x), np.zeros(g.size)))
