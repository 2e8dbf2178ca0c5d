"""Exceptions and input checks shared by the whole library.

Every check raises before any work starts, with a one-line message naming
the offending quantity and what is allowed.
"""

from __future__ import annotations

import math
import numbers
from importlib.util import find_spec


class NonPhysicalProfile(ValueError):
    """The requested three-phase profile has no real solution (the paper's case 0)."""


class SceneError(ValueError):
    """A scene file or Scene object is invalid; the message names file and key."""


def require_extra(module: str, extra: str, needed_by: str) -> None:
    """Raise an ImportError naming the extra to install unless ``module`` is importable.

    The core install leaves matplotlib, rerun and Snakemake out (README "Install"); a layer that
    needs one calls this at its top.  It only looks the module up, so the guard costs no import time.
    """
    try:
        found = find_spec(module) is not None
    except ImportError:  # an import hook refuses the module
        found = False
    if not found:
        raise ImportError(f"{needed_by} needs {module}, which the core install leaves out: "
                          f"pip install 'selfalign[{extra}]'")


def check_finite(name: str, value) -> float:
    """Return ``value`` as a float, or raise naming ``name`` if it is not a finite number."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) and not hasattr(value, "__float__"):
        raise ValueError(f"{name} must be a finite number, got {value!r}")
    value = float(value)
    if not math.isfinite(value):
        raise ValueError(f"{name} must be a finite number, got {value!r}")
    return value


def check_positive(name: str, value) -> float:
    """Return ``value`` as a float, or raise unless it is finite and > 0."""
    value = check_finite(name, value)
    if value <= 0.0:
        raise ValueError(f"{name} must be > 0, got {value!r}")
    return value


def check_integer(name: str, value, low: int = 1, high: int = 2**53) -> int:
    """Return ``value`` as an int, or raise unless it is an integer in [low, high].

    bools, non-integral or non-finite floats and strings are refused; an integral float
    (``10.0``) is accepted.
    """
    integral = isinstance(value, numbers.Integral) or (isinstance(value, float) and math.isfinite(value)
                                                        and value.is_integer())
    if isinstance(value, bool) or not integral or not low <= value <= high:
        raise ValueError(f"{name} must be an integer in [{low}, {high:.6g}], got {value!r}")
    return int(value)
