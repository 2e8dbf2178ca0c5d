"""The compiled engine: steppers under one contract, one driver, for one trajectory or many.

Load it through :func:`selfalign.solvers.jit.kernel` (which registers the model's formulas with
numba and sets its cache directory first); importing this package compiles nothing, and
:mod:`.codes` (the named codes) imports no numba at all.

Layout
------
* :mod:`.codes`: stepper results, reasons, event and arc kinds (plain ints, no numba);
* :mod:`.compiled`: the compilation settings and arrays passed without reference counting;
* profile rows are read through the column accessors of :mod:`selfalign.solvers.records`
  (``data_size``, ``col_break``, ``col_level``, ...), the one place that knows the row layout;
* :mod:`.field`: the friction field (eqs. 7-9) and stick outcomes every stepper shares;
* :mod:`.recording`: arcs, events and samples of a recorded run;
* the steppers, one module each: :mod:`.piecewise` (exact, piecewise-constant profiles),
  :mod:`.smooth` (exact, Fourier and finite-jerk profiles on a uniform surface),
  :mod:`.jerk_zone` (exact, finite-jerk profiles on a stop zone), :mod:`.timestepping` (Moreau),
  :mod:`.parts` (exact, several parts on a piecewise-constant profile: its own state and run loop),
  :mod:`.planar` (exact, planar motion under a piecewise-constant table acceleration on a uniform surface:
  its own state and run loop too);
* :mod:`.drive`: the driver loop and the outcome decisions;
* :mod:`.entries`: the entry points Python calls, one per method (and one per specialisation, such
  as the piecewise stepper for members on a uniform surface), and the stepper registration;
* :mod:`.python_stepper`: the driver's decisions for a stepper written in Python (ivp);
* :mod:`.dense`: dense output of the recorded arcs.

Every trajectory of one part is one :data:`~selfalign.solvers.records.MEMBER_DTYPE` record (its
inputs, working state and outcome; several parts on one table: below); :func:`.drive.run_members`
drives each member of an array of them, the same code for one trajectory (``selfalign.simulate``)
and for a batch, so scalar and batch results are bit-identical by construction.  Positions are
relative to an origin (x_mu on a stop zone, else x0), so that x_mu = 1e6 costs no accuracy in the
zone; time is (period n, tau in [0, dt)), period boundaries at the start phase tau0.

The stepper contract
--------------------
A stepper advances one member by whole periods.  It is a compiled function

    ``period_<name>(s, row, run, bnd, cross, record, buffers, scratch, periods[, uniform]) -> code``

* ``s``: the member record.  On entry the state at the period boundary (n, tau0): ``s.xi``,
  ``s.v``, ``s.mode`` (-1, 0, +1: backward slip, stick, forward slip) and the derived constants
  :func:`.drive.prepare_member` set (``s.b1``, ``s.omega``, ``s.rest_acc``, ``s.xs``, ...).
* ``row``: the profile row; ``run``: the run settings record
  (:data:`~selfalign.solvers.records.RUN_DTYPE`: horizon code ``until``, ``max_events``, the
  Moreau iteration options); ``bnd``, ``cross``: the boundaries whose first crossings are
  recorded (:func:`.field.record_crossings`) and their records; ``record``: a compile-time
  constant, whether arcs, events and samples are recorded into ``buffers`` (arcs, events,
  samples, sample steps; :mod:`.recording`); ``scratch``: the stepper's own work arrays (what
  its ``scratch_<name>`` function allocated once per run; empty for most).
* ``periods`` (>= 1): how many periods the stepper may advance before it returns.  The driver
  asks for more than one only where it decides nothing at the period boundaries in between (a
  run to a fixed horizon that skips nothing), so that a stepper which loops over them keeps its
  state in registers; a stepper may always advance just one (the driver calls again).
* ``uniform`` (a stepper with a uniform-surface entry point in
  :data:`.entries.UNIFORM_MEMBER_RUNS` only): a compile-time constant, True where every member
  is on a uniform surface, so that the stepper's loops carry no zone code; it
  passes ``zone`` (False, or ``s.zone``) to :func:`.field.friction_at` and
  :func:`.field.region_of`.

It returns :data:`.codes.DONE` when the periods asked for are complete, with the state at the
boundary reached written back (``s.xi``, ``s.v``, ``s.mode``, ``s.n``) and the running totals of
the last period (:func:`.field.save_period`: events, path, largest x, displacement and its
extremes, regions visited), which the driver's cycle search and fast-forward read.  It reports
an event by: counting it in ``s.events`` (the event budget ``max_events`` is checked against
it), calling :func:`.field.on_stick` at every stick (which decides REST, ACCUMULATION and
FIRST_STICK from the model's stick rule), :func:`.field.record_crossings` when a boundary may
have been crossed, and :func:`.recording.record_event` / :func:`.recording.record_arc` if
``record``.  It stops inside a period by returning a ``STOP_*`` code through
:func:`.field.stop_at` (the state and time where it stopped; a stepper that advances several
periods per call uses :func:`.field.stop_in_period`, which also sets ``s.n``): ``STOP_REST``,
``STOP_ACCUMULATION``, ``STOP_FIRST_STICK`` (from :func:`.field.on_stick`), ``STOP_BUDGET``
(``max_events`` reached) or ``STOP_STALL`` (more than :data:`~selfalign.solvers.outcomes.STALL_EVENTS`
zero-length events in a row).  A failure of the arithmetic: the driver checks that x and v are
finite after every call and ends the run with reason NONFINITE at the state the call started
from; a stepper that advances several periods per call checks at every period boundary itself
and returns ``STOP_NONFINITE`` through :func:`.field.stop_nonfinite` with the state at the start
of the period that failed.  A stepper never decides an outcome itself, never allocates, and
keeps the tie rules below.

A new stepper of one member (planar motion, say) is a module with its ``period_<name>`` function,
a method code in :mod:`selfalign.solvers.records` and one line in :func:`.drive.step`, the
dispatch; the driver specialises on the method code (a compile-time constant), so a run
compiles only the stepper it uses.  A stepper whose state is not one member's, as that of
several parts, has its own state arrays and run loop (below).

The stepper of several parts
----------------------------
Several parts on one table (:mod:`selfalign.solvers.parts_exact`) are one coupled state, not a
batch of members, so :mod:`.parts` does not take a member record.  It has its own state arrays
and its own run loop, :func:`.parts.run_parts`, called through the entry point
:func:`.entries.parts_run`:

    ``parts_run(f, g, q, c, row, periods, max_events) -> reason``

* ``f`` (float, rows x N), ``g`` (int, rows x N): one column per part, the rows named in
  :mod:`.codes` (``PX``, ``PV``, ... ``PSIGMA``, ``PJOINED``, ...); on entry the start state (x
  relative to x_mu on a stop zone, v, widths, masses, friction factors, transition slopes), on
  return the end state, the clusters, and the events per part (``PSTICKS``, ``PSLIPS``,
  ``PIMPACTS``, ``POPENINGS``, ``PCROSSINGS``); the rest is the stepper's scratch (the caller
  allocates it: the loop allocates nothing);
* ``q`` (float), ``c`` (int): the run's scalars and counters (restitution, c_mu, the tie-rule
  floors, the profile's extreme y'', the start phase tau0; the end time, the events per kind);
* ``row``: the profile row of a piecewise-constant profile; the run starts at phase tau0 with
  the period boundaries at tau0 + n dt, as a member does.

It returns the reason code (:class:`~selfalign.solvers.outcomes.Reason`): PERIODS, REST,
MAX_EVENTS or STALL.  Its outcome decision is REST only, made by the stepper itself
(:func:`.parts.at_rest`: every part at rest and no y'' of the profile moves any cluster); the
driver's other decisions (cycles, accumulation, fast-forward) are not made for several parts,
and the caller checks that the end state is finite (NONFINITE).

Tie rules of the exact solver
-----------------------------
They make every zero-length step change the mode, so there is no Zeno loop:

1. |y''| = r mu_bar counts as stick.
2. v = 0 and a zone crossing at the same time: the v = 0 event wins (mu_bar is continuous, so
   no crossing is needed to decide the mode).
3. v = 0 exactly at a break (grazing): the v = 0 event is handled first with the ending
   piece's y'', then the break re-decides the mode with the new piece's y''.
4. A slip velocity of the wrong sign (rounding, at most a few ulp) is set to 0 at the start of
   an arc; an arc that decelerates from v = 0 then ends at once with a v = 0 event, which
   always changes the mode.
5. A mass exactly on a zone boundary belongs to the region it moves into (stuck: x = x_mu
   counts as low friction, x = x_mu + w as high friction).

Outcome decisions (:func:`.drive.drive`, docs/explanation/solvers.md)
----------------------------------------------------------
REST at a stick where r mu_bar(x) >= the stepper's rest acceleration (max|y''|; Moreau:
max|impulse| / h); ACCUMULATION at a stick in the transition zone above the previous zone
stick and within ``acc_tol`` of x_stick_min (eq. 41); NEVER_STOPS when the period-boundary
state repeats (exactly, or to NEAR_ULPS ulp while the mass moved MOTION_FACTOR times that
tolerance in between) with no progress, or repeats in one region of constant friction while
the mass walks away from the zone or through it; HORIZON at the horizon; ERROR on the event
budget, a stall or an overflow.  A bit-exact repeat of the period-boundary state is also
fast-forwarded (skipped in whole cycles) unless a recording is asked for.
"""
