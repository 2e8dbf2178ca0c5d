"""The engine's entry points, the functions Python calls (:func:`selfalign.solvers.jit.kernel`
returns this module): the driver for batches and recorded runs, one entry point per method
(:data:`MEMBER_RUNS`, :data:`RECORDED_RUNS`, so that a call from Python reaches compiled code
without specialising on the method at every call), the run of several parts on one table
(:func:`parts_run`), the general planar stepper (:func:`planar_smooth_run`), the decisions a Python
stepper calls, and dense output.

A new stepper registers here: its method code in the two tables, with one entry point each.
"""

from __future__ import annotations

from ..records import EXACT_PIECEWISE, EXACT_SMOOTH, MOREAU
from .compiled import borrowed, jit
from .dense import modes, sample_arcs
from .drive import run_members, run_recorded
from .parts import run_parts
from .planar import run_planar
from .planar_smooth import run_planar_smooth
from .python_stepper import after_period_entry, begin_entry, finish_entry, moved_entry, stick_entry


@jit
def members_piecewise(members, table, run, bnd, cross, hist, arcs, events, samples, steps):
    """:func:`~.drive.run_members` with the exact stepper on piecewise-constant profiles."""
    run_members(members, EXACT_PIECEWISE, False, table, run, bnd, cross, hist, arcs, events, samples, steps)


@jit
def members_piecewise_uniform(members, table, run, bnd, cross, hist, arcs, events, samples, steps):
    """:func:`members_piecewise` compiled for members on a uniform surface only (no zone code in its
    loops): the common case of a sweep and of the paper's steady-state studies."""
    run_members(members, EXACT_PIECEWISE, True, table, run, bnd, cross, hist, arcs, events, samples, steps)


@jit
def members_smooth(members, table, run, bnd, cross, hist, arcs, events, samples, steps):
    """:func:`~.drive.run_members` with the exact stepper on smooth profiles."""
    run_members(members, EXACT_SMOOTH, False, table, run, bnd, cross, hist, arcs, events, samples, steps)


@jit
def members_moreau(members, table, run, bnd, cross, hist, arcs, events, samples, steps):
    """:func:`~.drive.run_members` with Moreau time-stepping."""
    run_members(members, MOREAU, False, table, run, bnd, cross, hist, arcs, events, samples, steps)


@jit
def recorded_piecewise(members, table, run, bnd, cross, hist, arcs, events, samples, steps):
    """:func:`~.drive.run_recorded` with the exact stepper on piecewise-constant profiles."""
    run_recorded(members, EXACT_PIECEWISE, table, run, bnd, cross, hist, arcs, events, samples, steps)


@jit
def recorded_smooth(members, table, run, bnd, cross, hist, arcs, events, samples, steps):
    """:func:`~.drive.run_recorded` with the exact stepper on smooth profiles."""
    run_recorded(members, EXACT_SMOOTH, table, run, bnd, cross, hist, arcs, events, samples, steps)


@jit
def recorded_moreau(members, table, run, bnd, cross, hist, arcs, events, samples, steps):
    """:func:`~.drive.run_recorded` with Moreau time-stepping."""
    run_recorded(members, MOREAU, table, run, bnd, cross, hist, arcs, events, samples, steps)


@jit
def parts_run(f, g, q, c, row, periods, max_events):
    """:func:`~.parts.run_parts`: the exact stepper of several parts, on its own state arrays (not member
    records; :mod:`selfalign.solvers.engine`, the stepper contract); returns the reason code."""
    return run_parts(borrowed(f), borrowed(g), borrowed(q), borrowed(c), borrowed(row), periods, max_events)


@jit
def planar_run(f, c, starts, accels, periods, until_rest, max_events, spp, samples, log):
    """:func:`~.planar.run_planar`: the exact planar stepper on a piecewise-constant table acceleration, on its own
    state arrays (:mod:`selfalign.solvers.engine.planar`); returns the reason code."""
    return run_planar(borrowed(f), borrowed(c), borrowed(starts), borrowed(accels), periods, until_rest, max_events,
                      spp, borrowed(samples), borrowed(log))


def planar_smooth_run(rows, pieces, strips, q, f, c, samples, log):
    """:func:`~.planar_smooth.run_planar_smooth`: the general exact stepper of planar motion, on its own arrays
    (:mod:`selfalign.solvers.planar_smooth`); returns the reason code."""
    return run_planar_smooth(borrowed(rows), borrowed(pieces), borrowed(strips), borrowed(q), borrowed(f),
                             borrowed(c), borrowed(samples), borrowed(log))


#: Method code -> the entry point that drives every member without recording.
MEMBER_RUNS = {EXACT_PIECEWISE: members_piecewise, EXACT_SMOOTH: members_smooth, MOREAU: members_moreau}
#: Method code -> the entry point for members that are all on a uniform surface, where one is compiled.
UNIFORM_MEMBER_RUNS = {EXACT_PIECEWISE: members_piecewise_uniform}
#: Method code -> the entry point that drives member 0 recording it.
RECORDED_RUNS = {EXACT_PIECEWISE: recorded_piecewise, EXACT_SMOOTH: recorded_smooth,
                 MOREAU: recorded_moreau}


def member_run(code, members):
    """The entry point that drives the batch ``members`` (a member record array) with method
    ``code``: the uniform-surface one where it exists and no member is on a stop zone.  Each
    entry point compiles once per machine (~30 s), so one trajectory (``selfalign.simulate``)
    always takes :data:`MEMBER_RUNS`: the first call compiles one kernel, whatever the surface."""
    if not members["zone"].any():
        return UNIFORM_MEMBER_RUNS.get(code, MEMBER_RUNS[code])
    return MEMBER_RUNS[code]


__all__ = ["MEMBER_RUNS", "RECORDED_RUNS", "UNIFORM_MEMBER_RUNS", "after_period_entry", "begin_entry", "finish_entry",
           "member_run", "modes", "moved_entry", "parts_run", "planar_run", "planar_smooth_run", "sample_arcs",
           "stick_entry"]
