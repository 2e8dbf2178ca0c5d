"""The model formulas that the compiled event kernel runs as they are.

A function marked with :func:`formula` is a plain scalar Python function of floats
(written with :mod:`math` only).  Python code calls it directly; when the event kernel
(:mod:`selfalign.solvers.engine`) is first loaded it registers every marked function
with numba, so that the compiled code calls this same function compiled, never a copy.
Marking imports nothing: ``import selfalign`` stays light.
"""

from __future__ import annotations

#: Every function marked with :func:`formula`, in definition order.
FORMULAS: list = []


def formula(func):
    """Mark ``func`` as a model formula the compiled kernel may call (returns it unchanged)."""
    FORMULAS.append(func)
    return func
