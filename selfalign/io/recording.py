"""Headless rerun recordings (``.rrd``) of simulated time series, their events and their scene.

A recording is a browsable companion of an HDF5 result: open it with
``rerun file.rrd`` to scrub through the series of a run with its events marked.
:class:`Recording` says what a file holds, :func:`write_recording` writes it.
Nothing here starts a viewer; files are written through
:func:`selfalign.io.hdf5.atomic_path`, so a failed write leaves nothing.

rerun is imported inside the functions because it is heavy and only needed
when a scene asks for a recording.
"""

from __future__ import annotations

import hashlib
import re
import uuid
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import NamedTuple

import numpy as np

from ..model.errors import require_extra
from .hdf5 import atomic_path

#: Entity names: path segments rerun needs no escaping for, joined by "/".
_NAME = re.compile(r"[A-Za-z0-9_.\-]+(/[A-Za-z0-9_.\-]+)*")
_SCALARS = "Scalars:scalars"
#: Text-log levels the viewer knows (it colours and filters by them).
LEVELS = ("TRACE", "DEBUG", "INFO", "WARN", "ERROR", "CRITICAL")
MEDIA_TYPES = ("text/plain", "text/markdown")
#: The sequence timeline of period numbers written beside the time timeline when a period is given.
PERIOD_TIMELINE = "period"


class LogEntries(NamedTuple):
    """Text-log lines: one time (seconds), text and level (:data:`LEVELS`) per line."""

    times: np.ndarray
    texts: list[str]
    levels: list[str]


class Boxes(NamedTuple):
    """Axis-aligned boxes moving along x (several parts on one line): ``centres`` x of each box at each time,
    shape (times, boxes); ``half_widths`` per box, shape (boxes,); ``half_height`` their common half height
    (the boxes sit on y = 0).  Boxes moving in the plane give ``centres`` (x, y) of shape (times, boxes, 2)
    instead.  Drawn in a 2-D view, one entity per name."""

    centres: np.ndarray
    half_widths: np.ndarray
    half_height: float


def default_groups(names) -> dict[str, list[str]]:
    """One plot per first path segment: "position/table" and "position/part" share a plot."""
    groups: dict[str, list[str]] = {}
    for name in names:
        groups.setdefault(name.split("/", 1)[0], []).append(name)
    return groups


def _check_name(what: str, name) -> str:
    if not isinstance(name, str) or not _NAME.fullmatch(name):
        raise ValueError(f"{what} name {name!r}: use letters, digits, '_', '.', '-' and '/' between segments")
    return name


def _check_times(what: str, times) -> np.ndarray:
    times = np.asarray(times, dtype=float)
    if times.ndim != 1 or not np.all(np.isfinite(times)):
        raise ValueError(f"{what} must be a one-dimensional array of finite numbers")
    return times


@dataclass(frozen=True)
class Recording:
    """What a recording holds.

    * ``series``: name -> values at ``times`` (seconds), each the scalar entity ``/<name>``
      drawn as a line;
    * ``markers``: name -> (times, values), scalar entities drawn as points (events on a plot);
    * ``logs``: name -> :class:`LogEntries`, text-log entities;
    * ``documents``: name -> (text, media type of :data:`MEDIA_TYPES`), static text entities;
    * ``period``: the period length; if given, every time also gets its period number
      floor(t / period) on the sequence timeline :data:`PERIOD_TIMELINE`;
    * ``view_titles``: plot (first path segment of series and markers) -> title; titled plots
      come first, in this order, then the others in order of appearance;
    * ``boxes``: name -> :class:`Boxes` at ``times``, drawn in one 2-D view per first path segment;
    * ``lines``: name -> static polylines in the plane, shape (lines, points, 2), drawn in the 2-D view of
      their first path segment (the outlines of a surface under moving boxes).

    The default blueprint stacks one time-series view per plot vertically (so that they share
    the time axis, linked), beside the documents and one text-log view of all logs.
    """

    times: np.ndarray
    series: dict[str, np.ndarray]
    timeline: str = "time"
    period: float | None = None
    markers: dict[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)
    logs: dict[str, LogEntries] = field(default_factory=dict)
    documents: dict[str, tuple[str, str]] = field(default_factory=dict)
    view_titles: dict[str, str] = field(default_factory=dict)
    application_id: str = "selfalign"
    boxes: dict[str, Boxes] = field(default_factory=dict)
    lines: dict[str, np.ndarray] = field(default_factory=dict)

    def __post_init__(self):
        times = _check_times("times", self.times)
        series = {}
        for name, values in self.series.items():
            values = np.asarray(values, dtype=float)
            if values.shape != times.shape:
                raise ValueError(f"series {name!r} has shape {values.shape}, times have {times.shape}")
            series[_check_name("series", name)] = values
        markers = {}
        for name, (at, values) in self.markers.items():
            at, values = _check_times(f"times of marker {_check_name('marker', name)!r}", at), np.asarray(values, float)
            if values.shape != at.shape:
                raise ValueError(f"marker {name!r} has {values.size} values at {at.size} times")
            markers[name] = (at, values)
        logs = {}
        for name, (at, texts, levels) in self.logs.items():
            at = _check_times(f"times of log {_check_name('log', name)!r}", at)
            texts, levels = [str(t) for t in texts], list(levels)
            if not len(texts) == len(levels) == at.size:
                raise ValueError(f"log {name!r} has {at.size} times, {len(texts)} texts, {len(levels)} levels")
            unknown = sorted(set(levels) - set(LEVELS))
            if unknown:
                raise ValueError(f"log {name!r}: unknown level(s) {unknown}; allowed: {list(LEVELS)}")
            logs[name] = LogEntries(at, texts, levels)
        for name, (text, media_type) in self.documents.items():
            if not isinstance(text, str) or media_type not in MEDIA_TYPES:
                raise ValueError(f"document {_check_name('document', name)!r} must be (text, media type) with a "
                                 f"media type of {list(MEDIA_TYPES)}, got ({type(text).__name__}, {media_type!r})")
        boxes = {}
        for name, (centres, half_widths, half_height) in self.boxes.items():
            centres, half_widths = np.asarray(centres, float), np.asarray(half_widths, float)
            _check_name("boxes", name)
            planar = centres.ndim == 3 and centres.shape[2:] == (2,)
            if (centres.ndim != 2 and not planar) or centres.shape[0] != times.size \
                    or half_widths.shape != centres.shape[1:2]:
                raise ValueError(f"boxes {name!r}: centres must have shape (times, boxes) = "
                                 f"({times.size}, n), or (times, boxes, 2) in the plane, and half_widths (n,), "
                                 f"got {centres.shape} and {half_widths.shape}")
            if not (np.all(np.isfinite(centres)) and np.all(half_widths > 0) and half_height > 0):
                raise ValueError(f"boxes {name!r}: centres must be finite, half_widths and half_height > 0")
            boxes[name] = Boxes(centres, half_widths, float(half_height))
        lines = {}
        for name, strips in self.lines.items():
            strips = np.asarray(strips, float)
            if strips.ndim != 3 or strips.shape[1] < 2 or strips.shape[2] != 2 or not np.all(np.isfinite(strips)):
                raise ValueError(f"lines {_check_name('lines', name)!r}: must have shape (lines, points >= 2, 2) "
                                 f"and be finite, got {strips.shape}")
            lines[name] = strips
        entities = [*series, *markers, *logs, *self.documents, *boxes, *lines]
        repeated = sorted({n for n in entities if entities.count(n) > 1})
        if repeated:
            raise ValueError(f"entity name(s) {repeated} used twice (series, markers, logs, documents, boxes and "
                             "lines)")
        unknown = sorted(set(self.view_titles) - set(default_groups([*series, *markers])))
        if unknown:
            raise ValueError(f"view_titles name plots that are not recorded: {unknown}")
        if self.period is not None and not (np.isfinite(self.period) and self.period > 0):
            raise ValueError(f"period must be a positive finite number or None, got {self.period!r}")
        for key, value in (("times", times), ("series", series), ("markers", markers), ("logs", logs),
                           ("boxes", boxes), ("lines", lines)):
            object.__setattr__(self, key, value)

    def plots(self) -> dict[str, str]:
        """Plot (first path segment) -> view title, in display order."""
        groups = default_groups([*self.series, *self.markers])
        return {**self.view_titles, **{g: g for g in groups if g not in self.view_titles}}

    def indexes(self, times: np.ndarray) -> list:
        """rerun time columns of ``times``: the duration timeline (rounded to the nearest ns, where
        rerun itself would truncate) and, with a period, the period numbers."""
        import rerun as rr

        columns = [rr.TimeColumn(self.timeline, duration=np.round(times * 1e9).astype("timedelta64[ns]"))]
        if self.period is not None:
            columns.append(rr.TimeColumn(PERIOD_TIMELINE, sequence=np.floor(times / self.period).astype(np.int64)))
        return columns

    def blueprint(self):
        """The default layout: the plots stacked with linked time axes, beside documents and logs."""
        import rerun.blueprint as rrb

        linked = rrb.archetypes.TimeAxis(link=rrb.components.LinkAxis.LinkToGlobal)
        plots = rrb.Vertical(*(rrb.TimeSeriesView(name=title, origin=f"/{plot}", axis_x=linked)
                               for plot, title in self.plots().items()))
        side = [rrb.Spatial2DView(name=scene, origin=f"/{scene}") for scene in default_groups([*self.boxes,
                                                                                               *self.lines])]
        side += [rrb.TextDocumentView(name=name, origin=f"/{name}") for name in self.documents]
        if self.logs:
            side.append(rrb.TextLogView(name="log", origin="/", contents=[f"/{name}" for name in self.logs]))
        if not side:
            return rrb.Blueprint(plots)
        return rrb.Blueprint(rrb.Horizontal(plots, rrb.Vertical(*side), column_shares=[2, 1]))


def write_recording(path, recording: Recording) -> Path:
    """Write ``recording`` to the rrd file ``path`` with its default blueprint.

    Series and markers are sent as columns (no per-sample Python loop); the recording id is
    :func:`content_id`.
    """
    require_extra("rerun", "rerun", "writing a rerun recording")
    import rerun as rr

    if not isinstance(recording, Recording):
        raise TypeError(f"write_recording needs a Recording, got {type(recording).__name__}")
    with atomic_path(path) as tmp:
        rec = rr.RecordingStream(recording.application_id, recording_id=content_id(recording))
        rec.save(tmp, default_blueprint=recording.blueprint())
        try:
            for name, (text, media_type) in recording.documents.items():
                rec.log(f"/{name}", rr.TextDocument(text, media_type=media_type), static=True)
            index = recording.indexes(recording.times)
            for name, values in recording.series.items():
                rec.send_columns(f"/{name}", indexes=index, columns=rr.Scalars.columns(scalars=values))
            for name, (at, values) in recording.markers.items():
                rec.log(f"/{name}", rr.SeriesPoints(markers="circle", marker_sizes=4.0), static=True)
                rec.send_columns(f"/{name}", indexes=recording.indexes(at),
                                 columns=rr.Scalars.columns(scalars=values))
            for name, strips in recording.lines.items():
                rec.log(f"/{name}", rr.LineStrips2D(list(strips)), static=True)
            for name, (centres, half_widths, half_height) in recording.boxes.items():
                count = centres.shape[1]
                xy = (centres.reshape(-1, 2) if centres.ndim == 3 else
                      np.stack([centres.ravel(), np.full(centres.size, half_height)], axis=1))
                half = np.stack([np.tile(half_widths, centres.shape[0]), np.full(len(xy), half_height)], axis=1)
                rec.send_columns(f"/{name}", indexes=index, columns=rr.Boxes2D.columns(
                    centers=xy, half_sizes=half).partition(lengths=np.full(centres.shape[0], count)))
            for name, entries in recording.logs.items():
                rec.send_columns(f"/{name}", indexes=recording.indexes(entries.times),
                                 columns=rr.TextLog.columns(text=entries.texts, level=entries.levels))
        finally:
            rec.disconnect()
    return Path(path)


def _feed(digest, value) -> None:
    """Add ``value`` to ``digest`` unambiguously (type tag and length before every part)."""
    if isinstance(value, dict):
        digest.update(b"d%d;" % len(value))
        for key in sorted(value):
            _feed(digest, key)
            _feed(digest, value[key])
    elif isinstance(value, (list, tuple)):
        digest.update(b"l%d;" % len(value))
        for item in value:
            _feed(digest, item)
    elif isinstance(value, np.ndarray):
        data = np.ascontiguousarray(value)
        digest.update(f"a{data.dtype.str}{data.shape};".encode() + data.tobytes())
    else:
        text = repr(value).encode()
        digest.update(b"s%d;" % len(text) + text)


def content_id(recording: Recording) -> uuid.UUID:
    """The recording id of these contents: a UUID from the SHA-256 of every field of ``recording``,
    so that the same inputs give the same recording (the viewer shows two writes of one scene as
    one recording).  rerun itself still stamps each write with its own chunk ids and start time,
    so the file bytes differ between writes; the data read back do not."""
    digest = hashlib.sha256()
    for item in fields(recording):
        _feed(digest, item.name)
        _feed(digest, getattr(recording, item.name))
    return uuid.UUID(bytes=digest.digest()[:16], version=5)


def _chunks(path):
    require_extra("rerun", "rerun", "reading a rerun recording")
    from rerun.chunk import RrdReader

    return RrdReader(path).store().stream().to_chunks()


def _index_values(batch, timeline: str) -> np.ndarray:
    """A timeline's column: seconds for a duration timeline, integers for a sequence."""
    import pyarrow as pa

    column = batch.column(timeline)
    values = column.cast("int64").to_numpy(zero_copy_only=False)
    return values / 1e9 if pa.types.is_duration(column.type) else values


def _timed(path, timeline: str, *components: str) -> dict[str, tuple[np.ndarray, list]]:
    """name -> (index, one arrow list array per component), sorted by index (stable), of the
    entities that hold ``components`` on ``timeline``; static data is skipped."""
    import pyarrow as pa

    parts: dict[str, list[tuple[np.ndarray, list]]] = {}
    for chunk in _chunks(path):
        if chunk.is_static or timeline not in chunk.timeline_names:
            continue
        batch = chunk.to_record_batch()
        if components[0] in batch.schema.names:
            parts.setdefault(chunk.entity_path.lstrip("/"), []).append(
                (_index_values(batch, timeline), [batch.column(c) for c in components]))
    out = {}
    for name, pieces in parts.items():
        index = np.concatenate([p[0] for p in pieces])
        order = pa.array(np.argsort(index, kind="stable"))
        out[name] = (index[order.to_numpy()],
                     [pa.concat_arrays([p[1][k] for p in pieces]).take(order) for k in range(len(components))])
    return out


def read_recording(path, *, timeline: str = "time") -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Scalar series and markers of an rrd file: name -> (index, values), sorted by index.

    The index is the time in seconds on a duration timeline, the integer on a sequence timeline
    (:data:`PERIOD_TIMELINE`).  Used to check what a recording holds.
    """
    out = {}
    for name, (index, (scalars,)) in _timed(path, timeline, _SCALARS).items():
        if np.any(scalars.value_lengths().to_numpy(zero_copy_only=False) != 1):
            raise ValueError(f"{path}: {name} holds more than one scalar per time")
        out[name] = (index, scalars.flatten().to_numpy(zero_copy_only=False))
    return out


def read_logs(path, *, timeline: str = "time") -> dict[str, LogEntries]:
    """Text logs of an rrd file: name -> :class:`LogEntries` sorted by time (stable)."""
    return {name: LogEntries(index, texts.flatten().to_pylist(), levels.flatten().to_pylist())
            for name, (index, (texts, levels)) in _timed(path, timeline, "TextLog:text", "TextLog:level").items()}


def read_documents(path) -> dict[str, str]:
    """Text documents of an rrd file: name -> text."""
    out = {}
    for chunk in _chunks(path):
        batch = chunk.to_record_batch()
        if "TextDocument:text" in batch.schema.names:
            (text,) = batch.column("TextDocument:text").flatten().to_pylist()
            out[chunk.entity_path.lstrip("/")] = text
    return out


def read_boxes(path, *, timeline: str = "time") -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Boxes of an rrd file: name -> (index, centres (times, boxes, 2), half sizes (times, boxes, 2)), sorted by
    index.  Used to check what a recording holds."""
    out = {}
    for name, (index, (centres, half)) in _timed(path, timeline, "Boxes2D:centers", "Boxes2D:half_sizes").items():
        count = int(centres.value_lengths().to_numpy(zero_copy_only=False)[0])
        shape = (index.size, count, 2)
        out[name] = (index, np.asarray(centres.flatten().flatten().to_numpy(zero_copy_only=False)).reshape(shape),
                     np.asarray(half.flatten().flatten().to_numpy(zero_copy_only=False)).reshape(shape))
    return out


def read_lines(path) -> dict[str, list[np.ndarray]]:
    """Static polylines of an rrd file (``Recording.lines``): name -> one (points, 2) array per line.  Used to
    check what a recording holds."""
    out = {}
    for chunk in _chunks(path):
        batch = chunk.to_record_batch()
        if "LineStrips2D:strips" in batch.schema.names:
            (strips,) = batch.column("LineStrips2D:strips").to_pylist()
            out[chunk.entity_path.lstrip("/")] = [np.asarray(line, float) for line in strips]
    return out
