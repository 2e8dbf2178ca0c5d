"""Exceptions and input checks shared by the whole library.

Every check raises before any work starts, with a one-line message naming
the offending quantity and what is allowed.

The library's own exceptions share one base, so ``except selfalign.SelfalignError`` catches
every one of them; each also keeps a builtin base, so ``except ValueError`` (or
``RuntimeError``) catches it too::

    SelfalignError(Exception)
    ├── NonPhysicalProfile(SelfalignError, ValueError)  a three-phase profile with no real solution
    ├── SceneError(SelfalignError, ValueError)          an invalid scene file or Scene object
    ├── DesignSpecError(SelfalignError, ValueError)     an invalid design spec file
    │                                                   (selfalign.io.design_spec; not a SceneError)
    └── KernelError(SelfalignError, RuntimeError)       the compiled kernel cannot be imported or
                                                        compiled (selfalign.solvers.jit)

Wrong input to a function or class is a builtin error: TypeError for an argument of the wrong
type (a string or an array where a number is expected, a number where a profile is expected:
:func:`check_real`, :func:`check_real_array`, :func:`check_integer`), ValueError (or SceneError,
for a Scene) for a wrong value (negative, NaN, out of range: :func:`check_finite`,
:func:`check_positive`).  A scene file or design spec, and the dict of one, is a document: any
problem in it, of type or value, is a SceneError or DesignSpecError naming the key.
"""

from __future__ import annotations

import math
import numbers
from importlib.util import find_spec

import numpy as np


class SelfalignError(Exception):
    """Base of the library's own exceptions.

    ``except selfalign.SelfalignError`` catches every exception the library raises on purpose:
    :class:`~selfalign.NonPhysicalProfile`, :class:`~selfalign.SceneError` and
    :class:`~selfalign.DesignSpecError` (each also a ValueError) and
    :class:`~selfalign.KernelError` (also a RuntimeError).  Wrong arguments of a function or
    class are the builtin TypeError or ValueError (the module docstring of
    ``selfalign.model.errors`` draws the hierarchy).

    See Also
    --------
    SceneError : An invalid scene file or Scene object.
    DesignSpecError : An invalid design spec file.

    Examples
    --------
    >>> import selfalign as sa
    >>> try:
    ...     sa.ThreePhaseProfile(dt=1.0, dy=1.0, y2=1.0, y3=1.0)
    ... except sa.SelfalignError as exc:
    ...     print(type(exc).__name__, isinstance(exc, ValueError))
    NonPhysicalProfile True
    >>> issubclass(sa.KernelError, sa.SelfalignError), issubclass(sa.KernelError, RuntimeError)
    (True, True)
    """


class NonPhysicalProfile(SelfalignError, ValueError):
    """The requested three-phase profile has no real solution (the paper's case 0).

    The seven constraints of the Appendix (Sect. 4.4.3) have a real solution only while the
    feasibility number q = sqrt(8 dy (1/y2 + 1/y3)) / dt is at most 1; beyond it lies case 0 of
    Table 1.  :class:`~selfalign.ThreePhaseProfile` (and its finite-jerk version)
    raises this error before any work, with one line naming the largest stroke that is
    physical.  It is a :class:`SelfalignError` and a ValueError, so ``except ValueError``
    catches it too; scene files report it as a :class:`SceneError` naming the file.

    See Also
    --------
    ThreePhaseProfile : The profile whose constructor raises it.
    classify : Case 0 for such parameters, without raising.

    Examples
    --------
    >>> import selfalign as sa
    >>> try:
    ...     sa.ThreePhaseProfile(dt=1.0, dy=1.0, y2=1.0, y3=1.0)
    ... except sa.NonPhysicalProfile as exc:
    ...     print(exc)
    no physical three-phase profile (case 0): 8*dy*(1/y2 + 1/y3) = 16 exceeds dt^2 = 1;
    need dy <= dt^2 / (8 (1/y2 + 1/y3)) = dy / q^2 = 0.0625
    >>> sa.classify((1.0, 1.0, 1.0, 1.0))
    0
    """


class SceneError(SelfalignError, ValueError):
    """A scene file or Scene object is invalid; the message names file and key.

    Raised before any work starts, with a one-line message naming the offending quantity and
    what is allowed: by :class:`~selfalign.Scene` and :class:`~selfalign.Record` for a bad
    field, and by :func:`~selfalign.load_scene` and :func:`~selfalign.scene_from_dict` for a
    file or mapping that cannot be read, breaks the schema or describes no physical scene (the
    message then starts with the file and the key).  Design spec files raise
    :class:`~selfalign.DesignSpecError` instead, which is not a SceneError.  It is a
    :class:`SelfalignError` and a ValueError, so ``except ValueError`` catches it too.

    See Also
    --------
    load_scene : Reads a scene file.
    scene_from_dict : Builds a scene from a mapping.

    Examples
    --------
    >>> import selfalign as sa
    >>> layout = {"profile": {"kind": "three_phase", "dt": 1.05, "dy": 0.084, "y2": 2.2, "y3": 0.9},
    ...           "horizon": {"periods": 0}}
    >>> try:
    ...     sa.scene_from_dict(layout, source="demo.yaml")
    ... except sa.SceneError as exc:
    ...     print(exc)
    demo.yaml: horizon.periods: must be >= 1, got 0
    """


def require_extra(module: str, extra: str, needed_by: str) -> None:
    """Raise an ImportError naming the extra to install unless ``module`` is importable.

    The core install leaves matplotlib, rerun and Snakemake out (docs/howto/install.md); a layer that
    needs one calls this at its top.  It only looks the module up, so the guard costs no import time.
    """
    try:
        found = find_spec(module) is not None
    except ImportError:  # an import hook refuses the module
        found = False
    if not found:
        raise ImportError(f"{needed_by} needs {module}, which the core install leaves out: "
                          f"pip install 'selfalign[{extra}]'")


def check_real(name: str, value) -> float:
    """Return ``value`` as a float, or raise TypeError naming ``name`` unless it is a real number.

    A real number is an ``int``, a ``float`` or a numpy integer or floating scalar (anything
    registered as :class:`numbers.Real`, e.g. ``fractions.Fraction``).  Refused: ``bool``,
    ``decimal.Decimal`` (not a :class:`numbers.Real`: its arithmetic with floats raises),
    strings, and numpy arrays of any shape, 0-d and size-1 included (a parameter is one number,
    so an array there is taken for a mix-up rather than unwrapped).
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number (int, float or numpy scalar), got {value!r} "
                        f"({type(value).__name__})")
    return float(value)


def check_choice(name: str, value, allowed) -> str:
    """Return ``value`` if it is one of the strings ``allowed``: TypeError naming ``name`` unless it is a
    string, ValueError naming the allowed values unless it is one of them."""
    if not isinstance(value, str):
        raise TypeError(f"{name} must be a string, one of {list(allowed)}, got {value!r} ({type(value).__name__})")
    if value not in allowed:
        raise ValueError(f"{name} must be one of {list(allowed)}, got {value!r}")
    return value


def check_real_array(name: str, value) -> np.ndarray:
    """Return ``value``, a real number or an array-like of them, as a float array, or raise
    TypeError naming ``name`` unless its entries are integers or floats (strings, bools, None
    and other objects are refused, not converted)."""
    array = np.asarray(value)
    if array.dtype.kind not in "iuf":
        raise TypeError(f"{name} must be a real number or an array of them, got {array.dtype} {value!r:.60}")
    return np.asarray(array, dtype=float)


def check_finite(name: str, value) -> float:
    """Return ``value`` as a float: TypeError unless it is a real number (:func:`check_real`),
    ValueError unless it is finite."""
    value = check_real(name, value)
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

    TypeError unless it is a real number (:func:`check_real`); ValueError for a non-integral
    or non-finite value or one outside [low, high].  An integral float (``10.0``, ``1e6``)
    is accepted.  The default ``high``, 2**53, is the largest count a double holds exactly.
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be an integer, got {value!r} ({type(value).__name__})")
    integral = isinstance(value, numbers.Integral) or math.isfinite(value) and float(value).is_integer()
    if not integral or not low <= value <= high:
        raise ValueError(f"{name} must be an integer in [{low}, {high:.6g}], got {value!r}")
    return int(value)
