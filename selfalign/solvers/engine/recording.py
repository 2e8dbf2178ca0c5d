"""Recording arcs, events and samples of one run (scalar runs only).  The buffers are sized by
the caller and never reassigned here (a loop-carried array costs reference counting in every
iteration); a record past the end is only counted, and the caller runs again with buffers of
the counted size.
"""

from __future__ import annotations

from .compiled import jit


@jit
def normalised_time(n, tau, dt):
    """(period, tau) with tau in [0, dt): an event at the very end of a period starts the next."""
    if tau >= dt:
        return n + 1, tau - dt
    return n, tau


@jit
def record_arc(arcs, s, dt, kind, n, tau, dur, xi, v, acc, a, om, mode, region):
    k = s.n_arcs
    if k < arcs.shape[0]:
        r = arcs[k]
        r.kind = kind
        r.period, r.tau = normalised_time(n, tau, dt)
        r.duration, r.x, r.v, r.acc, r.table_acc, r.omega, r.mode, r.region = dur, xi, v, acc, a, om, mode, region
    s.n_arcs = k + 1


@jit
def record_event(events, s, dt, kind, n, tau, xi, v, mode_before, mode_after, acc_before, acc_after):
    k = s.n_events
    if k < events.shape[0]:
        r = events[k]
        r.kind = kind
        r.period, r.tau = normalised_time(n, tau, dt)
        r.x, r.v, r.mode_before, r.mode = xi, v, mode_before, mode_after
        r.acc_before, r.acc_after = acc_before, acc_after
    s.n_events = k + 1


@jit
def record_sample(samples, s, n, tau, xi, v, mode):
    k = s.n_samples
    if k < samples.shape[0]:
        r = samples[k]
        r.period, r.tau, r.x, r.v, r.mode = n, tau, xi, v, mode
    s.n_samples = k + 1
