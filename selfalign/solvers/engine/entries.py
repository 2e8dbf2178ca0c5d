"""The engine's entry points, the functions Python calls (:func:`selfalign.solvers.jit.kernel`
returns this module): the driver for batches and recorded runs, the decisions a Python stepper
calls, and dense output."""

from __future__ import annotations

from .dense import modes, sample_arcs
from .drive import run_members, run_recorded
from .python_stepper import after_period_entry, begin_entry, finish_entry, moved_entry, stick_entry

__all__ = ["after_period_entry", "begin_entry", "finish_entry", "modes", "moved_entry", "run_members", "run_recorded",
           "sample_arcs", "stick_entry"]
