"""Named codes of the engine, importable without numba: stepper results, reasons, event and arc
kinds, and the floating-point constants the steppers share.  Plain ints, so that numba folds
them into the compiled code as constants.
"""

from __future__ import annotations

import math

from ...model import arcs as A
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
