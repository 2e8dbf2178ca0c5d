"""Named codes of the engine, importable without numba: stepper results, reasons, event and arc
kinds, and the floating-point constants the steppers share.  Plain ints, so that numba folds
them into the compiled code as constants.
"""

from __future__ import annotations

import math

from ...model import arcs as A
from ...model.parts import CHAIN_WORK_ROWS, IMPACT_WORK_ROWS, STATIC_WORK_ROWS
from ..outcomes import EventKind, Reason

INF = math.inf
EPS = 2.0 ** -52
LARGEST = 1.7976931348623157e308         # the largest finite float
NAN = math.nan

# Reason codes as plain ints (compile-time constants for numba).
REASON_ACCUMULATION = int(Reason.ACCUMULATION)
REASON_BOUNDED = int(Reason.BOUNDED)
REASON_FIRST_STICK = int(Reason.FIRST_STICK)
REASON_MAX_EVENTS = int(Reason.MAX_EVENTS)
REASON_MAX_PERIODS = int(Reason.MAX_PERIODS)
REASON_NONFINITE = int(Reason.NONFINITE)
REASON_PERIODIC = int(Reason.PERIODIC)
REASON_PERIODS = int(Reason.PERIODS)
REASON_REST = int(Reason.REST)
REASON_STALL = int(Reason.STALL)
REASON_WALK_BACKWARD = int(Reason.WALK_BACKWARD)
REASON_WALK_FORWARD = int(Reason.WALK_FORWARD)

# Stepper results: DONE (the periods asked for are complete) or why the stepper stopped inside one
# (STOP_NONFINITE: x or v stopped being finite; the state is the last finite one, at the start of
# that period).
DONE, STOP_REST, STOP_ACCUMULATION, STOP_FIRST_STICK, STOP_BUDGET, STOP_STALL, STOP_NONFINITE = 0, 1, 2, 3, 4, 5, 6


# Event kinds of the event log (:class:`~selfalign.solvers.outcomes.EventKind`).
EV_SWITCH, EV_STICK, EV_SLIP, EV_REVERSAL, EV_ZONE = (int(EventKind.SWITCH), int(EventKind.STICK),
                                                      int(EventKind.SLIP), int(EventKind.REVERSAL),
                                                      int(EventKind.ZONE))
# Arc kinds (:mod:`selfalign.model.arcs`).
ARC_QUADRATIC, ARC_HARMONIC, ARC_HYPERBOLIC, ARC_STICK, ARC_SMOOTH = (A.QUADRATIC, A.HARMONIC, A.HYPERBOLIC, A.STICK,
                                                                      A.SMOOTH)

# What ends a slip arc: the end of its piece (or step), v = 0, or a zone edge reached.
END_PIECE, END_STOP, END_EDGE = 0, 1, 2


# The stepper of several parts (:mod:`.parts`, :mod:`selfalign.solvers.parts_exact`).  Its tie-rule
# thresholds: a gap between clusters within CONTACT_ULPS ulp of the positions' scale counts as closed (tie
# rule 4); a relative velocity at a closed contact within VELOCITY_ULPS ulp of the velocity scale counts as
# zero (tie rule 5, the Zeno floor); accelerations of touching neighbours within ACCELERATION_ULPS ulp of the
# force scale count as equal (tie rule 6); a closing search on a stop zone's arcs takes at most SEARCH_STEPS
# steps.
CONTACT_ULPS, VELOCITY_ULPS, ACCELERATION_ULPS, SEARCH_STEPS = 16, 64, 8, 10_000
# Its state is three arrays the caller allocates, one column per part: rows of a float array ...
(PX, PV, PW, PM, PK, PSLOPE, PA, POMEGA, PKAPPA, PB, PS, POUT, PLOWER, PLAND) = range(14)
PWORK = 14                                       # first of the scratch rows of chain_minimiser, impact_velocities
PARTS_FLOAT_ROWS = PWORK + max(CHAIN_WORK_ROWS, IMPACT_WORK_ROWS, STATIC_WORK_ROWS)
# ... rows of an int array (flags are 0/1; the lists hold the parts or contacts of the next event) ...
(PSIGMA, PKIND, POLD_SIGMA, PJOINED, PDIRTY, PALL_JOINED, PTOUCHING, PCLOSED, PTOGETHER, PWAS_JOINED, PIS_STOP,
 PIS_CLOSE, PIS_OPEN, PLANDS, PLIST_STOPS, PLIST_CLOSES, PLIST_CROSSINGS, PLIST_OPENS, PSTICKS, PSLIPS, PIMPACTS,
 POPENINGS, PCROSSINGS, PHELD) = range(24)
PARTS_INT_ROWS = 24
# ... and the run's scalars: settings (restitution, c_mu, the scales and floors, the profile's extreme y'',
# the start phase, the ratio r = mu_s / mu_k) and results (end time, smallest gap relative to the positions'
# scale after any event) ...
(QE, QC_MU, QLENGTH, QV_FLOOR, QA_TOL, QHIGHEST, QLOWEST, QTAU0, QT_END, QMIN_GAP, QRATIO) = range(11)
PARTS_SCALARS = 11
# ... and counters: the surface (1: stop zone), the events per kind, the list lengths (stops, closes,
# crossings, opens).
(CZONE, CSTICKS, CSLIPS, CIMPACTS, COPENINGS, CBREAKS, CLISTS) = range(7)
PARTS_COUNTERS = CLISTS + 4


# The exact planar stepper on a piecewise-constant table acceleration (:mod:`.planar`,
# :mod:`selfalign.solvers.planar_exact`).  Its float state: the position relative to the origin and the
# velocity (in: the start, out: the end), the end phase, and the run's settings (period, start phase tau0,
# kinetic friction mu_bar, the ratio r = mu_s / mu_k, the largest |Y''| of the profile) ...
(PL_X, PL_Y, PL_VX, PL_VY, PL_TAU_END, PL_DT, PL_TAU0, PL_MU, PL_RATIO, PL_REST) = range(10)
PLANAR_FLOATS = 10
# ... and its counters: the end period, the end mode (0 stick, 1 slip), the events per kind, the closed-form
# arcs, all events (the budget max_events counts them), the log entries and the samples written.
(PC_N_END, PC_MODE, PC_STICKS, PC_SLIPS, PC_REVERSALS, PC_BREAKS, PC_ARCS, PC_EVENTS, PC_LOG,
 PC_SAMPLES) = range(10)
PLANAR_COUNTERS = 10
# Columns of its event log (period, phase, kind, x, y, vx, vy) and of its samples (x, y, vx, vy, mode).
PLANAR_LOG_COLUMNS, PLANAR_SAMPLE_COLUMNS = 7, 5


# The general planar stepper (:mod:`.planar_smooth`, :mod:`selfalign.solvers.planar_smooth`).  Its settings, a
# float array: the period, the y component's lag (phase dt), cos and sin of the profile's angle, r = mu_s / mu_k,
# max|Y''|, the start phase tau0, the sample spacing dt / samples_per_period, the accumulation tolerance, the stick
# grid spacing (0: no Fourier component) ...
(GS_DT, GS_SHIFT, GS_COS, GS_SIN, GS_RATIO, GS_AMAX, GS_TAU0, GS_SAMPLE, GS_ACC_TOL, GS_GRID) = range(10)
GENERAL_SETTINGS = 10
# ... its float state (position, velocity, phase tau in the period, the slip direction at a start from rest, the
# next step size, the last two distances of a band stick to the rest set, the end position of an accumulation and
# its contraction) ...
(GF_X, GF_Y, GF_VX, GF_VY, GF_TAU, GF_UX, GF_UY, GF_H, GF_D1, GF_D2, GF_LIMX, GF_LIMY, GF_CONTRACTION) = range(13)
GENERAL_FLOATS = 13
# ... and its integers: settings (the horizon in periods, until='rest', the event budget, whether samples and the
# log are recorded), the state (mode 0 stick / 1 slip, period, piece, zero-length events in a row, band sticks
# seen) and the counts.
(GI_PERIODS, GI_UNTIL_REST, GI_MAX_EVENTS, GI_RECORD_SAMPLES, GI_RECORD_LOG, GI_MODE, GI_PERIOD, GI_PIECE, GI_STALLED,
 GI_NH, GI_STICKS, GI_SLIPS, GI_CROSSINGS, GI_BREAKS, GI_STEPS, GI_EVENTS, GI_SAMPLES, GI_LOG) = range(18)
GENERAL_INTS = 18
# Columns of its merged profile pieces (start and end phase, the piece of each component, the y component's time
# offset) and of its samples (t, x, y, vx, vy, mode) and log entries (t, kind, x, y, vx, vy).
PIECE_START, PIECE_END, PIECE_X, PIECE_Y, PIECE_OFFSET = range(5)
GENERAL_PIECE_COLUMNS, GENERAL_RECORD_COLUMNS = 5, 6
