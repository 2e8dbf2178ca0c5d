"""Steps every workflow script shares: logging to the job's log, writing a figure, the rows of
a shard and the values of a config range.

The stage modules beside this one build the content of each stage's result files;
every workflow script reads its inputs, calls one or two of their functions and writes
its outputs, so that tests run the same steps without Snakemake.  Nothing here knows
about Snakemake objects.
"""

from __future__ import annotations

import logging
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from ..io.hdf5 import atomic_write
from ..plots.encode import figure_bytes
from ..plots.style import DPI, print_check


def save_figure(fig, path, dpi: int = DPI) -> Path:
    """Write ``fig`` atomically in the format of the suffix of ``path`` (png, pdf or svg;
    :func:`selfalign.plots.encode.figure_bytes`: the same drawing gives the same bytes).

    A figure that does not meet the figure standard (:func:`selfalign.plots.style.print_check`:
    print width, fonts at print size, no titles but panel letters) is refused with a
    ValueError naming every problem, before anything is written.  The check draws the figure
    at its own resolution, so every file starts from the same laid-out state whichever format
    was written before it (constrained layout settles slightly differently after a draw at
    the PNG's resolution)."""
    problems = print_check(fig)
    if problems:
        raise ValueError(f"{Path(path).name} does not meet the figure standard: " + "; ".join(problems))
    data = figure_bytes(fig, Path(path).suffix.lstrip(".").lower(), dpi)
    return atomic_write(path, lambda tmp: Path(tmp).write_bytes(data))


@contextmanager
def logged(path, name: str = "selfalign"):
    """Log to ``path`` for the duration of a workflow step, including the traceback of a failure.

    Snakemake shows a failed job's log, so the reason of a failure must be there.
    """
    log = logging.getLogger(name)
    handler = logging.FileHandler(path, mode="w")
    handler.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(message)s"))
    log.addHandler(handler)
    log.setLevel(logging.INFO)
    try:
        yield log
    except BaseException:
        log.exception("step failed")
        raise
    finally:
        log.removeHandler(handler)
        handler.close()


def shard_rows(rows: int, shards: int, index: int, *, interleaved: bool = False) -> slice:
    """Rows (y2 indices) of shard ``index`` of ``shards``: contiguous, sizes differing by at most one;
    with ``interleaved`` every ``shards``-th row from ``index`` instead, which balances the jobs of a
    sweep whose cost is concentrated in part of the y2 range (Fig. 17)."""
    if isinstance(shards, bool) or not isinstance(shards, (int, np.integer)) or shards < 1:
        raise ValueError(f"shards must be an integer >= 1, got {shards!r}")
    if not 0 <= index < shards:
        raise ValueError(f"shard index must lie in [0, {shards}), got {index!r}")
    if interleaved:
        return slice(index, int(rows), int(shards))
    base, extra = divmod(int(rows), int(shards))
    start = index * base + min(index, extra)
    return slice(start, start + base + (index < extra))


def range_values(spec: dict) -> np.ndarray:
    """The values of a config range ``{from, to, count, scale}`` (config schema ``$defs/range``):
    ``count`` values from ``from`` to ``to``, both included, evenly spaced (``linear``) or in
    geometric progression (``log``)."""
    space = {"linear": np.linspace, "log": np.geomspace}
    if spec["scale"] not in space:
        raise ValueError(f"range scale must be one of {sorted(space)}, got {spec['scale']!r}")
    return space[spec["scale"]](float(spec["from"]), float(spec["to"]), int(spec["count"]))
