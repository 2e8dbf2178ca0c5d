"""Headless rerun recordings (``.rrd``) of simulated time series.

A recording is a browsable companion of an HDF5 result: open it with
``rerun file.rrd`` to scrub through position, velocity, friction force and
mode of a run.  Nothing here starts a viewer; files are written through
:func:`selfalign.io.hdf5.atomic_path`, so a failed write leaves nothing.

rerun is imported inside the functions because it is heavy and only needed
when a scene asks for a recording.
"""

from __future__ import annotations

import hashlib
import re
import uuid
from pathlib import Path

import numpy as np

from ..model.errors import require_extra
from .hdf5 import atomic_path

require_extra("rerun", "rerun", "selfalign.io.recording")

#: Series names: entity-path segments rerun needs no escaping for, joined by "/".
_NAME = re.compile(r"[A-Za-z0-9_.\-]+(/[A-Za-z0-9_.\-]+)*")
_SCALARS = "Scalars:scalars"


def default_groups(names) -> dict[str, list[str]]:
    """One plot per first path segment: "position/table" and "position/part" share a plot."""
    groups: dict[str, list[str]] = {}
    for name in names:
        groups.setdefault(name.split("/", 1)[0], []).append(name)
    return groups


def write_recording(path, times, series: dict, *, timeline: str = "time",
                    application_id: str = "selfalign",
                    blueprint_groups: dict[str, list[str]] | None = None) -> Path:
    """Write ``series`` (name -> values at ``times``, in seconds) to an rrd file.

    Every series becomes the scalar entity ``/<name>`` on the duration
    timeline ``timeline``, sent as one column (no per-sample Python loop).
    rerun stores durations in integer nanoseconds, so times are rounded to
    the nearest nanosecond (rerun itself would truncate).  The recording
    carries a default blueprint with one time-series view per entry of
    ``blueprint_groups`` (view name -> series names), stacked vertically so
    that the views share the time axis; by default series are grouped by
    :func:`default_groups`.
    """
    import rerun as rr
    import rerun.blueprint as rrb

    times = np.asarray(times, dtype=float)
    if times.ndim != 1 or not np.all(np.isfinite(times)):
        raise ValueError("times must be a one-dimensional array of finite numbers")
    columns = {}
    for name, values in series.items():
        if not isinstance(name, str) or not _NAME.fullmatch(name):
            raise ValueError(f"series name {name!r}: use letters, digits, '_', '.', '-' and '/' between segments")
        values = np.asarray(values, dtype=float)
        if values.shape != times.shape:
            raise ValueError(f"series {name!r} has shape {values.shape}, times have {times.shape}")
        columns[name] = values
    groups = default_groups(columns) if blueprint_groups is None else blueprint_groups
    unknown = sorted({n for names in groups.values() for n in names} - set(columns))
    if unknown:
        raise ValueError(f"blueprint_groups name series that are not recorded: {unknown}")

    blueprint = rrb.Blueprint(
        rrb.Vertical(*(rrb.TimeSeriesView(name=view, origin="/", contents=[f"/{n}" for n in names])
                       for view, names in groups.items())),
    )
    index = rr.TimeColumn(timeline, duration=np.round(times * 1e9).astype("timedelta64[ns]"))
    with atomic_path(path) as tmp:
        rec = rr.RecordingStream(application_id, recording_id=content_id(application_id, timeline, times, columns))
        rec.save(tmp, default_blueprint=blueprint)
        try:
            for name, values in columns.items():
                rec.send_columns(f"/{name}", indexes=[index], columns=rr.Scalars.columns(scalars=values))
        finally:
            rec.disconnect()
    return Path(path)


def content_id(application_id: str, timeline: str, times: np.ndarray, columns: dict) -> uuid.UUID:
    """The recording id of these contents: a UUID from the SHA-256 of the application id, the
    timeline, the times and every series (name and float64 bytes), so that the same inputs
    give the same recording (the viewer shows two writes of one scene as one recording).
    rerun itself still stamps each write with its own chunk ids and start time, so the file
    bytes differ between writes; the data read back (:func:`read_recording`) do not."""
    digest = hashlib.sha256()
    for part in (application_id, timeline):
        digest.update(part.encode() + b"\0")
    digest.update(np.ascontiguousarray(times, dtype=float).tobytes())
    for name in sorted(columns):
        digest.update(name.encode() + b"\0" + np.ascontiguousarray(columns[name], dtype=float).tobytes())
    return uuid.UUID(bytes=digest.digest()[:16], version=5)


def read_recording(path, *, timeline: str = "time") -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Scalar series of an rrd file: name -> (times in seconds, values), sorted by time.

    The inverse of :func:`write_recording`, used to check what a recording
    holds; static data such as recording properties is skipped.
    """
    from rerun.chunk import RrdReader

    parts: dict[str, list[tuple[np.ndarray, np.ndarray]]] = {}
    for chunk in RrdReader(path).store().stream().to_chunks():
        if chunk.is_static or timeline not in chunk.timeline_names:
            continue
        batch = chunk.to_record_batch()
        if _SCALARS not in batch.schema.names:
            continue
        scalars = batch.column(_SCALARS)
        if np.any(scalars.value_lengths().to_numpy(zero_copy_only=False) != 1):
            raise ValueError(f"{path}: {chunk.entity_path} holds more than one scalar per time")
        t_ns = batch.column(timeline).cast("int64").to_numpy(zero_copy_only=False)
        parts.setdefault(chunk.entity_path.lstrip("/"), []).append(
            (t_ns, scalars.flatten().to_numpy(zero_copy_only=False)))
    out = {}
    for name, pieces in parts.items():
        t_ns = np.concatenate([p[0] for p in pieces])
        values = np.concatenate([p[1] for p in pieces])
        order = np.argsort(t_ns, kind="stable")
        out[name] = (t_ns[order] / 1e9, values[order])
    return out
