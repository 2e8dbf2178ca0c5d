"""Planar mode-switching integration with scipy.integrate.solve_ivp (``method="ivp"`` of a planar scene).

The planar counterpart of :mod:`selfalign.solvers.ivp` (docs/explanation/planar-model.md): the inclusion
x'' = -Y''(t) + f, f in -mu_bar(x) Sign2(x') of a point part on a table moving in the plane is
integrated one smooth piece at a time in the current mode:

* slip (|v| > 0): x' = v, v' = -Y''(t) - mu_bar(x) v / |v|;
* stick (v = 0): x' = 0, while |Y''| <= r mu_bar(x) (r = mu_s / mu_k, 1 for Coulomb friction; the tie
  sticks).  A stick ends when |Y''| > r mu_bar: the slip starts along -Y'' (the direction of the net
  driving force, the disc's maximal dissipation) with kinetic friction.

A piece ends at a profile switch (``PlanarProfile.switch_times``: y'' jumps or bends there), at the
period end, or at a terminal event located by solve_ivp:

* the speed falling to the floor V_f = SPEED_TOLERANCES (atol + rtol V) (V = max|Y''| dt + |v0|, the
  run's speed scale), taken for v = 0: in a planar stop the direction of v turns at a rate
  |F| sin(angle to F) / |v|, which grows without bound as |v| -> 0, and an explicit integrator's steps
  shrink with |v| short of the stop (tens of thousands of rejected steps without reaching it).  The
  stop is then early by about V_f / (mu_bar - |F|) in time and V_f^2 in position;
* the speed reaching 0.  |v| has no sign change there, so the event function is v . d with d the
  direction of the driving force F = -Y'' (d = F / |F|; on a piece with Y'' = 0, d = the direction of v
  at the piece's start, which friction alone does not turn).  With F constant on the piece,
  (v . d)' = |F| - mu_bar (v / |v|) . d, which is |F| > 0 wherever v . d = 0 with v != 0: v . d never
  falls through 0 at a nonzero speed.  A downward zero of v . d is therefore the stop itself (the
  speed of a decelerating slip aligns with F as it vanishes), and an upward zero is either a slip
  reversing through v = 0 against F (in the 1-D reduction, exactly) or v turning through the normal
  of F at a nonzero speed, which is no event: a zero whose located speed exceeds
  :data:`SPEED_TOLERANCES` times atol + rtol V (V the run's speed scale) is passed and the integration
  goes on from it (it counts towards the event budget and the stall guard).  On a profile whose
  y'' varies in a piece (piecewise-linear, Fourier) d = F(t) / |F(t)| turns, and a zero of either sign
  is a stop only where the speed is that small;
* a strip boundary n . x = x_mu or x_mu + w crossed (mu_bar has a kink there), either way (n . x is not
  monotone in a planar slip); the part is set onto the boundary (x moved along n by the rounding of
  n . x - b) and the integration restarts there.  A kink where two strips' coefficients cross inside
  their bands (the max of two affine functions) is no event: solve_ivp's error control steps over it;
* on a smooth profile (piecewise-linear, Fourier) in stick, |Y''|^2 crossing (r mu_bar)^2 upwards,
  integrated on the trivial ODE with max_step = dt / (16 * order), as the 1-D method does.  On a
  piecewise-constant profile stick is decided at each piece's start and holds through it, without
  integration.

An event function that is 0 at the start of a piece (a slip from rest, a restart on a boundary or at
a passed zero of v . d) is divided by t - t_start, with the sign of its first change at t_start: its
later roots are the same, and solve_ivp does not find the start again.  A step that ends past an event
has evaluated the mode's ODE beyond it (past a kink of mu_bar, or past v = 0 where v / |v| jumps),
which its error estimate does not see; as in the 1-D method the piece is integrated again up to the
located event, so that its last step ends there.

At v = 0 the mode is decided by the model's rule on |Y''| against r mu_bar(x).  Outcomes: REST
(until='rest': a stick where r mu_bar(x) >= max|Y''|; until='periods' fast-forwards such a stick to the
horizon when no event log is kept), PERIODS / MAX_PERIODS at the horizon, MAX_EVENTS (the budget
``max_events``), STALL (more than STALL_EVENTS successive events within STALL_ULPS ulp of dt of each
other), NONFINITE (the last finite state kept), SOLVER_FAILED (solve_ivp failed).  Samples are
solve_ivp's dense output at the sample times tau0 + k dt / samples_per_period.
"""

from __future__ import annotations

import math

import numpy as np

from ..model.planar import planar_coefficient, strip_rows
from .engine.codes import EV_SLIP, EV_STICK, EV_SWITCH, EV_ZONE
from .ivp import _event, _first_time
from .outcomes import STALL_EVENTS, STALL_ULPS, Reason, Status, message
from .planar import PLANAR_EVENT_DTYPE, PLANAR_SAMPLE_DTYPE, PlanarResult, sample_times

#: A zero of v . d (the stop event) is v = 0 where the located speed is at most SPEED_TOLERANCES times
#: atol + rtol V (V = max|Y''| dt + |v0|, the run's speed scale): solve_ivp's error at the zero is of
#: that size.  At a larger speed it is v turning through the normal of the driving force, and the slip
#: goes on.
SPEED_TOLERANCES = 10.0
#: Evaluations of the slip ODE one piece may take before the run ends with SOLVER_FAILED: a slip whose steps
#: shrink without end (a zero speed or a boundary no event resolved) is an error, never a hang.
MAX_SLIP_EVALUATIONS = 200_000


class _TooManySteps(Exception):
    """A slip piece used up MAX_SLIP_EVALUATIONS."""


def _from_zero(fun, t_start, limit):
    """``fun`` divided by t - t_start, ``limit`` (its sign at t_start+) at t_start: for an event function
    that is 0 at the start of a piece.  Its later roots are those of ``fun``, and solve_ivp does not
    find a root at the start."""
    return lambda t, y: fun(t, y) / (t - t_start) if t > t_start else limit


class _Run:
    """State of one planar event-driven run: the clock (period p, tau), x, v (2,), mode (0 stick, 1 slip)."""

    def __init__(self, scene, options):
        self.scene = scene
        self.profile = profile = scene.profile
        self.dt = float(profile.dt)
        self.rows = strip_rows(scene.strips)
        self.ratio = float(scene.friction.ratio)
        self.rtol, self.atol, self.integrator = options["rtol"], options["atol"], options["integrator"]
        self.max_events = int(options["max_events"])
        self.piecewise = bool(profile.piecewise_constant)
        switches = np.asarray(profile.switch_times, dtype=float)
        # The ends of the smooth pieces of one period; the period end is a switch iff 0 is one.
        self.switch_set = set(switches.tolist())
        self.period_switch = 0.0 in self.switch_set
        if self.piecewise:
            starts, accels = profile.pieces()
            self.starts = np.asarray(starts, dtype=float)
            self.accels = np.asarray(accels, dtype=float)
            self.ends = np.append(self.starts[1:], self.dt)
        else:
            self.ends = np.append(np.unique(switches[switches > 0.0]), self.dt)
            order = max(getattr(c, "order", 1) for c in (profile.x, profile.y) if c is not None)
            self.stick_max_step = self.dt / (16 * order)
        self.amax = float(profile.max_abs_acceleration)
        self.until = scene.until
        self.total = int(scene.horizon_periods)
        self.tau0 = float(scene.phase) * self.dt
        self.p, self.tau = 0, self.tau0
        self.x = np.array(scene.x0, dtype=float)
        self.v = np.array(scene.v0, dtype=float)
        self.speed_tol = SPEED_TOLERANCES * (self.atol + self.rtol * (self.amax * self.dt + float(np.hypot(*self.v))))
        self.mode = 1
        # Event functions that start a piece at 0: the velocity event's sign after its zero, and the
        # boundary the part sits on (strip row, end 0 or 1).
        self.fresh_sign, self.on_boundary = None, None
        self.counts = {"sticks": 0, "slips": 0, "crossings": 0, "breaks": 0, "steps": 0}
        self.n_events, self.stalled, self.last_event = 0, 0, None
        self.stall_time = STALL_ULPS * math.ulp(self.dt)
        self.log_on = bool(scene.record.events)
        self.events = []
        self.dense = bool(scene.record.dense)
        self.times = sample_times(scene) if self.dense else np.zeros(0)
        self.n_samples = self.times.size
        self.samples = np.zeros(self.n_samples, dtype=PLANAR_SAMPLE_DTYPE)
        self.k_next = 0                              # the next sample to fill

    # -- the model --------------------------------------------------------------------
    def mu_bar(self, x):
        return planar_coefficient(float(x[0]), float(x[1]), self.rows)

    def piece_index(self, tau):
        return min(int(np.searchsorted(self.starts, tau, side="right")) - 1, self.starts.size - 1)

    def acceleration(self, tau):
        """Y''(tau) (2,), right-continuous at switch times."""
        if self.piecewise:
            return self.accels[self.piece_index(tau)]
        return np.asarray(self.profile.acceleration(float(tau)), dtype=float).reshape(2)

    def slips_at(self, tau, x):
        """The model's rule at v = 0: True where |Y''| > r mu_bar(x) (the tie sticks)."""
        a = self.acceleration(tau)
        return float(np.hypot(a[0], a[1])) > self.ratio * self.mu_bar(x)

    def drive(self, tau, fallback):
        """The direction of the driving force -Y''(tau), ``fallback`` where Y''(tau) = 0."""
        a = self.acceleration(tau)
        norm = float(np.hypot(a[0], a[1]))
        return fallback if norm == 0.0 else -a / norm

    # -- bookkeeping -------------------------------------------------------------------
    def now(self):
        return self.p * self.dt + self.tau

    def segment_end(self):
        """End of the smooth piece holding tau: the next switch or the period end, or the horizon."""
        end = float(self.ends[int(np.searchsorted(self.ends, self.tau, side="right"))])
        if self.p == self.total and self.tau < self.tau0 < end:
            end = self.tau0
        return end

    def note(self):
        """Count an event at the current time; events that follow each other within ``stall_time`` count
        towards a stall."""
        self.n_events += 1
        now = self.now()
        advance = math.inf if self.last_event is None else now - self.last_event
        self.stalled = self.stalled + 1 if advance <= self.stall_time else 0
        self.last_event = now

    def log(self, kind):
        """Count (and record) an event at the current time and state."""
        self.note()
        if self.log_on:
            now = self.now()
            self.events.append((now, int(kind), self.x.copy(), self.v.copy()))

    def sample(self, tau_b, state_at, mode):
        """Fill the samples at times up to tau_b of the current period from ``state_at(local taus)``."""
        if not self.dense:
            return
        t_b = self.p * self.dt + tau_b
        k0 = self.k_next
        k1 = k0
        while k1 < self.n_samples and self.times[k1] <= t_b:
            k1 += 1
        if k1 > k0:
            times = self.times[k0:k1]
            xs, vs = state_at(times - self.p * self.dt)
            rows = self.samples[k0:k1]
            rows["t"], rows["x"], rows["v"], rows["mode"] = times, xs, vs, mode
            self.k_next = k1

    def hold(self, tau_b):
        """Samples of the part stuck at x up to tau_b."""
        x = self.x.copy()
        self.sample(tau_b, lambda g: (np.broadcast_to(x, (g.size, 2)), np.zeros((g.size, 2))), 0)

    def set_time(self, tau):
        """Move the clock to ``tau`` of the current period; tau = dt is the next period's start."""
        self.p, self.tau = (self.p + 1, 0.0) if tau >= self.dt else (self.p, tau)

    def start_slip(self):
        """A stick ends: slip from rest along -Y''."""
        self.mode = 1
        self.counts["slips"] += 1
        self.fresh_sign = 1.0
        self.log(EV_SLIP)

    def stop(self):
        """v = 0 reached: stick, or at once a slip from rest along -Y'' (a slip reversing through 0).
        Returns a Reason to end the run with, or None."""
        self.v = np.zeros(2)
        if self.slips_at(self.tau, self.x):
            self.start_slip()
            return None
        self.mode = 0
        self.counts["sticks"] += 1
        self.log(EV_STICK)
        return self.stuck_for_good()

    def stuck_for_good(self):
        """At a stick where r mu_bar(x) >= max|Y''|: REST (until='rest'), or the horizon reached at once
        (until='periods', when no event log is kept).  Returns a Reason or None."""
        if self.ratio * self.mu_bar(self.x) < self.amax:
            return None
        if self.until == "rest":
            return Reason.REST
        if self.log_on:
            return None
        self.p, self.tau = self.total, self.tau0
        self.hold(self.tau0)
        return Reason.PERIODS

    def finish_piece(self, tau_b):
        """Clock to the piece end; a profile switch there is an event, which in stick re-decides the mode."""
        self.set_time(tau_b)
        if self.tau in self.switch_set:
            self.counts["breaks"] += 1
            self.log(EV_SWITCH)

    # -- one piece ---------------------------------------------------------------------
    def step(self):
        """Integrate one smooth piece (or up to the first event in it).  Returns a Reason to end the run
        with (and a detail for SOLVER_FAILED), or None."""
        tau_a, tau_b = self.tau, self.segment_end()
        if self.mode == 0:
            if self.slips_at(tau_a, self.x):
                self.start_slip()
                return None
            return self.stick(tau_a, tau_b)
        return self.slip(tau_a, tau_b)

    def stick(self, tau_a, tau_b):
        from scipy.integrate import solve_ivp

        if self.piecewise:                   # decided at the piece's start, holds through it
            self.hold(tau_b)
            self.finish_piece(tau_b)
            return None
        limit = self.ratio * self.mu_bar(self.x)

        def exit_value(t, y):
            # positive exactly where the model's rule says slip; a tie holds the stick
            a = self.acceleration(t)
            value = float(a[0] ** 2 + a[1] ** 2) - limit**2
            return value if math.hypot(a[0], a[1]) > limit else min(value, -math.ulp(0.0))

        sol = solve_ivp(lambda t, y: (0.0,), (tau_a, tau_b), [0.0], method=self.integrator, rtol=self.rtol,
                        atol=self.atol, max_step=self.stick_max_step, events=[_event(exit_value, 1)])
        self.counts["steps"] += sol.t.size - 1
        if sol.status == -1:
            return Reason.SOLVER_FAILED, f"solve_ivp failed in stick at period {self.p}, tau {tau_a!r}: {sol.message}"
        if sol.status == 1:
            tau_e = _first_time(float(sol.t_events[0][0]), tau_b, lambda t: self.slips_at(t, self.x))
            self.hold(tau_e)
            self.set_time(tau_e)
            self.start_slip()
            return None
        self.hold(tau_b)
        self.finish_piece(tau_b)
        return None

    def slip(self, tau_a, tau_b):
        from scipy.integrate import solve_ivp

        x0, v0 = self.x.copy(), self.v.copy()
        speed0 = float(np.hypot(*v0))
        start_dir = v0 / speed0 if speed0 > 0.0 else self.drive(tau_a, np.array([1.0, 0.0]))
        rows, mu_bar = self.rows, planar_coefficient
        if self.piecewise:
            a = self.acceleration(tau_a)
            d = self.drive(tau_a, start_dir)
            acc = lambda t: a  # noqa: E731
            along = lambda t, y: y[2] * d[0] + y[3] * d[1]  # noqa: E731
        else:
            acc = self.acceleration

            def along(t, y):
                e = self.drive(t, start_dir)
                return y[2] * e[0] + y[3] * e[1]

        calls = [0]

        def rhs(t, y):
            calls[0] += 1
            if calls[0] > MAX_SLIP_EVALUATIONS:
                raise _TooManySteps
            s = math.hypot(y[2], y[3])
            ux, uy = (y[2] / s, y[3] / s) if s > 0.0 else start_dir
            mu = mu_bar(y[0], y[1], rows)
            g = acc(t)
            return (y[2], y[3], -g[0] - mu * ux, -g[1] - mu * uy)

        y0 = np.concatenate([x0, v0])
        velocity = along
        if self.fresh_sign is not None or along(tau_a, y0) == 0.0:
            velocity = _from_zero(along, tau_a, 1.0 if self.fresh_sign is None else self.fresh_sign)
        # Two function objects: solve_ivp reads the direction off each.
        floor = self.speed_tol
        events = [_event(lambda t, y: velocity(t, y), -1.0), _event(lambda t, y: velocity(t, y), 1.0),
                  _event(lambda t, y: math.hypot(y[2], y[3]) - floor, -1.0)]
        bounds = []
        for k, row in enumerate(rows):
            n = row[:2]
            for end, b in enumerate((row[2], row[2] + row[3])):
                def side(t, y, n=n, b=b):
                    return n[0] * y[0] + n[1] * y[1] - b
                if self.on_boundary == (k, end) or side(tau_a, y0) == 0.0:
                    first = float(n @ v0) or float(n @ start_dir) or 1.0
                    side = _from_zero(side, tau_a, first)
                events.append(_event(side, 0.0))
                bounds.append((n, b, k, end))
        self.fresh_sign, self.on_boundary = None, None
        t_end, which = tau_b, None
        for _ in range(4):
            try:
                sol = solve_ivp(rhs, (tau_a, t_end), y0, method=self.integrator, rtol=self.rtol, atol=self.atol,
                                events=events, dense_output=self.dense)
            except _TooManySteps:
                return Reason.SOLVER_FAILED, (f"solve_ivp needed more than {MAX_SLIP_EVALUATIONS} evaluations of the "
                                              f"slip ODE in one piece at period {self.p}, tau {tau_a!r} (steps "
                                              f"shrinking at a zero speed or a strip boundary no event resolved)")
            self.counts["steps"] += sol.t.size - 1
            if sol.status != 1:
                break
            found = [(float(te[0]), i) for i, te in enumerate(sol.t_events) if te.size]
            t_e, first = min(found)
            if t_e >= t_end:                 # the event again, at the end of the last step
                which = first
                break
            # Integrate again up to the event (module docstring), so that the last step ends there.
            t_end, which = t_e, first
        if sol.status == -1:
            return Reason.SOLVER_FAILED, f"solve_ivp failed in slip at period {self.p}, tau {tau_a!r}: {sol.message}"
        state = sol.y[:, -1]
        if not np.all(np.isfinite(state)):
            return Reason.NONFINITE, ""
        self.sample(t_end, lambda g: (sol.sol(g)[:2].T, sol.sol(g)[2:].T), 1)
        self.x, self.v = state[:2].copy(), state[2:].copy()
        if which is None:
            self.finish_piece(tau_b)
            return None
        self.set_time(t_end)
        if which < 3:
            speed = float(np.hypot(*self.v))
            if which == 2 or speed <= self.speed_tol or (which == 0 and self.piecewise):
                return self.stop()
            self.fresh_sign = 1.0 if which == 1 else -1.0        # v turned through the normal of F
            self.note()
            return None
        n, b, k, end = bounds[which - 3]
        self.x = self.x + (b - float(n @ self.x)) * n
        self.on_boundary = (k, end)
        self.counts["crossings"] += 1
        self.log(EV_ZONE)
        return None


def run(scene, options: dict) -> PlanarResult:
    """Simulate a planar ``scene`` mode by mode with scipy's solve_ivp (module docstring).

    Parameters
    ----------
    scene : Scene
        A planar scene (``scene.planar``): a :class:`~selfalign.model.planar.PlanarProfile`, a uniform
        surface or strips, Coulomb or static/kinetic friction.
    options : dict
        The ivp method's options, checked and filled by :mod:`selfalign.solvers.methods`: ``rtol``,
        ``atol``, ``integrator`` (a solve_ivp method) and ``max_events``.

    Returns
    -------
    PlanarResult
        The end state and time, the reason the run ended, the event counts, solve_ivp's steps, and the
        samples and event log the scene's record asks for.

    Examples
    --------
    >>> import selfalign as sa
    >>> from selfalign.solvers import planar_ivp
    >>> p = sa.ThreePhaseProfile(1.05, 0.084, 2.2, 0.9)
    >>> scene = sa.Scene(sa.PlanarProfile(p, p, offset=0.25), periods=3)
    >>> result = planar_ivp.run(scene, {"rtol": 1e-10, "atol": 1e-12, "integrator": "DOP853",
    ...                                 "max_events": 10_000})
    >>> result.reason.name, result.x_end.round(6).tolist()
    ('PERIODS', [0.110584, 0.13956])
    """
    run_ = _Run(scene, options)
    reason, detail = None, ""
    if float(np.hypot(*run_.v)) == 0.0:
        run_.mode = 0
        reason = None if run_.slips_at(run_.tau, run_.x) else run_.stuck_for_good()
    horizon = Reason.PERIODS if run_.until == "periods" else Reason.MAX_PERIODS
    while reason is None:
        if (run_.p, run_.tau) >= (run_.total, run_.tau0):
            reason = horizon
            break
        last = (run_.x.copy(), run_.v.copy())
        out = run_.step()
        if isinstance(out, tuple):
            reason, detail = out
        elif out is not None:
            reason = out
        if reason == Reason.NONFINITE:
            run_.x, run_.v = last
        elif reason is None and run_.n_events > run_.max_events:
            reason = Reason.MAX_EVENTS
        elif reason is None and run_.stalled > STALL_EVENTS:
            reason = Reason.STALL
    if run_.mode == 0:
        run_.hold(run_.tau)                              # a part stuck at the end: its samples up to now
    return _result(run_, Reason(reason), detail)


def _result(run_, reason, detail):
    """The PlanarResult of a finished run."""
    x, v = run_.x, run_.v
    fields = {"periods": run_.total, "fast_forward": 0, "max_periods": run_.total, "x": tuple(x.tolist()),
              "v": tuple(v.tolist()), "mu": run_.ratio * run_.mu_bar(x), "rest_acc": run_.amax,
              "holding": "r mu_bar" if run_.ratio != 1.0 else "mu_bar", "max_events": run_.max_events,
              "period": run_.p, "tau": run_.tau, "stall": STALL_EVENTS, "stall_ulps": STALL_ULPS,
              "detail": detail}
    samples = run_.samples[:run_.k_next] if run_.dense else None
    log = None
    if run_.log_on:
        log = np.zeros(len(run_.events), dtype=PLANAR_EVENT_DTYPE)
        for i, (t, kind, xe, ve) in enumerate(run_.events):
            log[i] = (t, kind, xe, ve)
    return PlanarResult(t_end=run_.now(), x_end=x.copy(), v_end=v.copy(), reason=reason,
                        message=message(reason, **fields) if reason.status is Status.ERROR else "",
                        sticks=run_.counts["sticks"],
                        slips=run_.counts["slips"], crossings=run_.counts["crossings"],
                        breaks=run_.counts["breaks"], steps=run_.counts["steps"], samples=samples, log=log)
