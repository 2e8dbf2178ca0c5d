"""Entry points for a stepper written in Python (ivp, :mod:`selfalign.solvers.ivp`): the driver's
own decisions, on member 0, so that every method ends a run by the same rules.
"""

from __future__ import annotations

from .compiled import jit
from .drive import after_period, finish_run, prepare_member, start_mode
from .field import holds_for_good, on_stick


@jit
def begin_entry(members, row, method, acc_tol, a, until):
    """:func:`prepare_member` and :func:`start_mode` on member 0; returns the start code."""
    s = members[0]
    prepare_member(s, row, method, acc_tol)
    return start_mode(s, a, until, False, (0.0, 0.0))


@jit
def stick_entry(members, xi, mu, n, tau, until):
    """:func:`on_stick` on member 0."""
    return on_stick(members[0], xi, mu, n, tau, until, holds_for_good(members[0], mu))


@jit
def moved_entry(members, xi0, xi1):
    """Path and largest x after a move of member 0 (no boundary crossings are tracked)."""
    s = members[0]
    s.path += abs(xi1 - xi0)
    if xi1 > s.xi_max:
        s.xi_max = xi1


@jit
def after_period_entry(members, hist, count, max_cycle, swing, until, total, fast_forward, v0, mode0, xi0,
                       path0):
    """:func:`after_period` on member 0."""
    return after_period(members[0], hist, count, max_cycle, swing, until, total, fast_forward, v0, mode0, xi0,
                         path0)


@jit
def finish_entry(members, code, reason, until):
    """:func:`finish_run` on member 0."""
    finish_run(members[0], code, reason, until)
