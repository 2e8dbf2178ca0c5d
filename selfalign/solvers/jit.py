"""Loading the compiled engine (:mod:`selfalign.solvers.engine`) on first use.

numba is imported here and nowhere else at import time of a solver call, so that
``import selfalign`` stays light.  :func:`kernel`:

* registers the model formulas and their helpers (:mod:`selfalign.model.registry`; those of several
  parts too, which :mod:`selfalign.solvers.parts_moreau` compiles with its own stepper) and the profile-row layout
  (:data:`selfalign.solvers.records.LAYOUT`) with numba, so the kernel calls those very functions
  compiled;
* keeps numba's on-disk cache (``cache=True``) in a directory keyed by the content of
  every source file the kernel is compiled from, by the numba and Python versions and by
  the CPU: numba itself checks only the time stamp of the file that holds the decorated
  function, so an edit of a model formula would otherwise run stale compiled code.  The
  root is ``$SELFALIGN_CACHE_DIR`` or ``$XDG_CACHE_HOME/selfalign`` (``~/.cache/selfalign``);
* turns a failure to import or compile into :class:`KernelError` with a clear message.

The first call of each kernel entry point in a fresh cache compiles it (seconds; see
docs/explanation/performance.md); later processes load it from the cache.  :func:`call` says so before
it waits: once per process, the first time an entry point has no cache entry on disk, the
logger ``selfalign.solvers.jit`` (:data:`LOGGER`) tells at level INFO what compiles and
where the result is kept (the CLI prints it on stderr).
"""

from __future__ import annotations

import hashlib
import logging
import os
import platform
import sys
import time
from importlib import import_module
from pathlib import Path

from ..model.errors import SelfalignError

#: Source files the compiled kernel is built from (relative to the package): the kernel and every
#: module of the package it imports, directly or not (tests/test_jit.py checks the closure).
SOURCES = tuple(f"solvers/engine/{name}.py" for name in (
    "entries", "codes", "compiled", "recording", "field", "piecewise", "smooth", "jerk_zone", "timestepping", "drive",
    "python_stepper", "dense", "parts", "planar", "planar_smooth")) + (
    "solvers/records.py", "solvers/outcomes.py", "model/arcs.py", "model/friction.py", "model/parts.py",
    "model/planar.py", "model/planar_slip.py", "model/profiles.py", "model/registry.py", "model/errors.py")
#: The model modules whose formulas :func:`kernel` registers with numba: the kernel's own and those of the steppers
#: compiled by :func:`compile_stepper` (their edits move the cache directory too: they are in ``SOURCES``).
REGISTRY_MODULES = ("arcs", "friction", "parts", "planar", "planar_slip")
#: The logger that announces a compilation (and how long it took).
LOGGER = logging.getLogger(__name__)
#: Wall time of compiling the entry points of one solver run on an empty cache, as told to the
#: user before it starts (docs/explanation/performance.md: measured on 2-core machines, 13-17 s).
COMPILE_SECONDS = 15

_kernel = None
_announced = False


class KernelError(SelfalignError, RuntimeError):
    """The compiled event kernel cannot be imported or compiled on this machine.

    The exact and Moreau solvers run compiled code (numba).  On first use the kernel is
    imported and compiled; if numba is missing or compilation fails, every solver call raises
    this error with a message saying why.  It is a :class:`~selfalign.SelfalignError` and a
    RuntimeError.

    See Also
    --------
    simulate : Compiles the kernel on its first call.

    Examples
    --------
    >>> import selfalign as sa
    >>> issubclass(sa.KernelError, sa.SelfalignError), issubclass(sa.KernelError, RuntimeError)
    (True, True)
    """


def cache_root() -> Path:
    """Root of selfalign's compiled-code cache (see the module docstring)."""
    env = os.environ.get("SELFALIGN_CACHE_DIR")
    if env:
        return Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(base) / "selfalign"


def cache_dir(numba_version: str) -> Path:
    """The cache directory of this kernel build: the root, then a digest of the sources."""
    package = Path(__file__).resolve().parents[1]
    digest = hashlib.sha256()
    for part in (numba_version, sys.version, platform.machine(), platform.processor()):
        digest.update(part.encode())
    for name in SOURCES:
        digest.update((package / name).read_bytes())
    return cache_root() / f"numba-{digest.hexdigest()[:16]}"


def kernel():
    """The engine's entry points (:mod:`selfalign.solvers.engine.entries`), imported (not yet
    compiled) on the first call."""
    global _kernel
    if _kernel is not None:
        return _kernel
    try:
        import numba
        from numba.extending import register_jitable
    except ImportError as exc:
        raise KernelError(f"the exact and Moreau solvers run compiled code and need numba: {exc}; "
                          "install it with `pip install numba`") from None
    from ..model.registry import FORMULAS, HELPERS
    from . import records

    for name in REGISTRY_MODULES:
        import_module(f"{__package__.rpartition('.')[0]}.model.{name}")      # they fill the registry
    for func in FORMULAS + HELPERS:
        register_jitable(func)
    for func in records.LAYOUT:
        register_jitable(func)
    previous = numba.config.CACHE_DIR
    numba.config.CACHE_DIR = str(cache_dir(numba.__version__))
    try:
        from .engine import entries as module
    finally:
        numba.config.CACHE_DIR = previous
    _kernel = module
    return module


def compile_stepper(function, what: str):
    """``function``, a stepper written in Python over the model's formulas, compiled by numba (``nogil``,
    ``error_model="numpy"``, ``cache=True``) after :func:`kernel` registered those formulas, and kept in the
    kernel's cache directory (:func:`cache_dir`, keyed by the content of the model's sources; numba itself
    checks only the time stamp of ``function``'s file), so that a later process loads it.  Returns a callable
    that turns a numba compilation failure into :class:`KernelError` naming ``what``; its ``compiled``
    attribute is numba's dispatcher."""
    kernel()
    import numba
    from numba import njit
    from numba.core.errors import NumbaError

    previous = numba.config.CACHE_DIR
    numba.config.CACHE_DIR = str(cache_dir(numba.__version__))
    try:
        compiled = njit(nogil=True, error_model="numpy", cache=True)(function)
    finally:
        numba.config.CACHE_DIR = previous

    def run(*args):
        try:
            return compiled(*args)
        except NumbaError as exc:
            first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
            raise KernelError(f"{what} failed to compile: {first}") from exc
    run.compiled = compiled
    return run


def _uncached(function) -> bool:
    """Whether ``function`` (a kernel entry point) has not run in this process and has no entry in
    the compiled-code cache on disk, so that calling it compiles it."""
    if getattr(function, "signatures", True):            # compiled in this process, or run uncompiled
        return False
    index = getattr(getattr(getattr(function, "_cache", None), "_cache_file", None), "_index_path", None)
    return index is not None and not os.path.exists(index)


def announce_compile(function) -> None:
    """Tell :data:`LOGGER` (once per process) that ``function`` is about to compile, and where to."""
    global _announced
    if _announced or not _uncached(function):
        return
    _announced = True
    LOGGER.info("compiling the event kernel (once per machine and version, ~%d s); cached in %s",
                COMPILE_SECONDS, os.path.dirname(function._cache._cache_file._index_path))


def call(function, *args):
    """Call a kernel entry point (announcing a compilation first, :func:`announce_compile`); a numba
    compilation failure becomes a :class:`KernelError`."""
    from numba.core.errors import NumbaError

    announce_compile(function)
    start = time.perf_counter()
    try:
        result = function(*args)
        misses = getattr(function, "stats", None)
        if LOGGER.isEnabledFor(logging.DEBUG) and misses and sum(misses.cache_misses.values()):
            LOGGER.debug("%s compiled in %.1f s", function.__name__, time.perf_counter() - start)
        return result
    except NumbaError as exc:
        import numba

        first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
        raise KernelError(f"the compiled event kernel failed to compile ({function.__name__}, numba "
                          f"{numba.__version__}): {first}") from exc
