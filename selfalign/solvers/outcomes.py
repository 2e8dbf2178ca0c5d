"""The result of a simulation: one object with a status and a message.

Like scipy's ``OdeResult``: the end state is always there; dense series and
the event log only when the scene asked for them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import Enum

import numpy as np


class Status(str, Enum):
    """How a run ended."""

    HORIZON = "horizon"            #: the requested number of periods was simulated
    REST = "rest"                  #: stuck where mu_bar(x) >= max|y''|: at rest for good
    ACCUMULATION = "accumulation"  #: stick positions converge geometrically to a limit
    NEVER_STOPS = "never_stops"    #: keeps moving without coming to rest (periodic or walking through)
    ERROR = "error"                #: the solver could not continue; see message


class EventKind(int, Enum):
    """Kinds of events in the event log (the code stored in ``events['kind']``)."""

    SWITCH = 0    #: the table acceleration jumps (a profile switch time)
    STICK = 1     #: slip ends in stick (relative velocity reaches zero and |y''| <= mu_bar)
    SLIP = 2      #: stick ends: |y''| exceeds mu_bar
    REVERSAL = 3  #: the relative velocity passes through zero and the slip changes direction
    ZONE = 4      #: the body crosses x_mu or x_mu + w


#: Mode codes in ``mode`` series and the event log.
BACKWARD_SLIP, STICK, FORWARD_SLIP = -1, 0, 1

EVENT_DTYPE = np.dtype([("kind", "i1"), ("period", "i8"), ("tau", "f8"),
                        ("x", "f8"), ("v", "f8"), ("mode", "i1")])


@dataclass
class Trajectory:
    """Outcome of :func:`selfalign.simulate`.

    ``x_end``, ``v_end`` are the final state (for an accumulation, the
    limit); the end time is ``period_end * dt + tau_end``.  ``series`` maps
    the recorded names (``t``, ``x``, ``v``, ``y``, ``yd``, ``ydd``,
    ``friction``, ``mode``) to arrays; ``events`` is a structured array of
    ``EVENT_DTYPE`` or None; ``stats`` holds ``events``, ``steps``,
    ``cpu_time``; ``info`` holds outcome details (e.g. ``limit``,
    ``contraction``, ``stick_events`` for an accumulation).
    """

    x_end: float
    v_end: float
    period_end: int
    tau_end: float
    status: Status
    message: str
    method: str
    options: dict = field(default_factory=dict)
    series: dict = field(default_factory=dict)
    events: np.ndarray | None = None
    stats: dict = field(default_factory=dict)
    info: dict = field(default_factory=dict)

    @property
    def success(self) -> bool:
        return self.status is not Status.ERROR

    def __getattr__(self, name):
        # t, x, v, ... read as attributes; missing series raise a clear error.
        series = self.__dict__.get("series", {})
        if name in ("t", "x", "v", "y", "yd", "ydd", "friction", "mode"):
            if name in series:
                return series[name]
            raise AttributeError(f"series {name!r} was not recorded; add it to the scene's record.series")
        raise AttributeError(name)
