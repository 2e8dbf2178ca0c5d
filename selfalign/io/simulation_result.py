"""Simulation results as HDF5 content and rerun recordings, and back.

The simulation stage stores one :class:`~selfalign.solvers.outcomes.Trajectory` per
scene in ``results/simulation/<scene>.h5`` through
:func:`selfalign.io.hdf5.write_h5`; :func:`trajectory_content` builds what is
written and :func:`trajectory_from_result` rebuilds the Trajectory from
:func:`selfalign.io.hdf5.read_h5`'s output, so that later stages and figures
work on the same object a direct ``simulate`` call returns.

Layout (docs/reference/results.md):

* root attributes: ``scene_name``, ``scene`` (YAML text of ``scene.to_dict()``),
  ``method``, ``options`` (the solver options used), ``status``, ``reason``, ``message``,
  ``x_end``, ``v_end``, ``period_end``, ``tau_end``, ``t_end`` (= period_end
  dt + tau_end, for plotting), ``dt``; ``selfalign_version`` is added by
  ``write_h5``;
* group ``stats``: one attribute per entry of ``Trajectory.stats`` (events,
  steps, ...) except ``cpu_time``, a measured value, which is the dataset
  ``stats/cpu_time`` (marked ``measurement = True``: the one content of the
  file that differs between two runs); group ``info``: likewise for
  ``Trajectory.info``, whose arrays (the events per part of a scene with several parts, shape (N,),
  rear-most first) are datasets;
* group ``series`` (only if the scene recorded series): one dataset per series
  (``t`` plus the recorded names), attribute ``samples_per_period``;
* group ``events`` (only if the scene recorded the event log): the columns of
  the structured event array (``kind``, ``period``, ``tau``, ``x``, ``v``,
  ``mode_before``, ``mode``, ``acc_before``, ``acc_after``) as datasets, plus
  ``t`` = period dt + tau, and the attribute
  ``kinds`` mapping each :class:`~selfalign.solvers.outcomes.EventKind` name to its code.
"""

from __future__ import annotations

import numpy as np

from ..model.scene import Scene
from ..solvers.outcomes import FORWARD_SLIP, EventKind, Reason, Status
from ..solvers.records import EVENT_DTYPE
from ..solvers.results import Trajectory
from .recording import LogEntries, Recording
from .scene_files import scene_from_dict

#: Rerun entity path of each recordable series, "<plot>/<name>": one plot per quantity kind.
RERUN_ENTITIES = {
    "x": "position/x",
    "y": "position/y",
    "v": "velocity/v",
    "yd": "velocity/yd",
    "ydd": "acceleration/ydd",
    "friction": "friction/force",
    "mode": "mode/mode",
}
#: Title of each plot, top to bottom.
RERUN_PLOTS = {
    "position": "position x, table y",
    "velocity": "velocity x', table y'",
    "acceleration": "table acceleration y''",
    "friction": "friction force F_f, coefficient mu_bar(x)",
    "mode": "mode (1 forward slip, 0 stick, -1 backward slip)",
}
#: Entries of ``Trajectory.stats`` that are measured, stored as datasets of group ``stats``.
MEASURED_STATS = ("cpu_time",)
#: Where each event is marked: the plot and the event-log column of its value.
EVENT_MARKS = {"position": "x", "velocity": "v"}

def event_datasets(events: np.ndarray, dt: float) -> dict[str, np.ndarray]:
    """The columns of an event log (``EVENT_DTYPE``) as datasets, plus the absolute time ``t``."""
    events = np.asarray(events)
    if events.dtype != EVENT_DTYPE:
        raise ValueError(f"event log must have dtype EVENT_DTYPE {EVENT_DTYPE}, got {events.dtype}")
    out = {name: events[name].copy() for name in EVENT_DTYPE.names}
    out["t"] = events["period"] * dt + events["tau"]
    return out


def events_from_datasets(datasets: dict) -> np.ndarray:
    """The structured event log back from :func:`event_datasets` columns (``t`` is dropped)."""
    missing = [name for name in EVENT_DTYPE.names if name not in datasets]
    if missing:
        raise ValueError(f"event datasets miss column(s) {missing}; need {list(EVENT_DTYPE.names)}")
    size = np.asarray(datasets["kind"]).shape[0]
    events = np.empty(size, dtype=EVENT_DTYPE)
    for name in EVENT_DTYPE.names:
        events[name] = datasets[name]
    return events


def trajectory_content(traj: Trajectory, scene: Scene) -> tuple[dict, dict, dict]:
    """(datasets, attrs, groups) of ``results/simulation/<scene>.h5`` for :func:`write_h5`."""
    import yaml

    dt = float(scene.profile.dt)
    attrs = {
        "scene_name": scene.name,
        "scene": yaml.safe_dump(scene.to_dict(), sort_keys=False),
        "method": traj.method,
        "options": dict(traj.options),
        "status": Status(traj.status).value,
        "reason": Reason(traj.reason).name.lower(),
        "message": traj.message,
        "x_end": _end_state(traj.x_end),
        "v_end": _end_state(traj.v_end),
        "period_end": int(traj.period_end),
        "tau_end": float(traj.tau_end),
        "t_end": int(traj.period_end) * dt + float(traj.tau_end),
        "dt": dt,
    }
    stats = dict(traj.stats)
    measured = {name: np.float64(stats.pop(name)) for name in MEASURED_STATS if name in stats}
    per_part = {name: np.asarray(value) for name, value in traj.info.items() if np.ndim(value) == 1}
    info = {name: value for name, value in traj.info.items() if name not in per_part}
    groups = {"stats": {"attrs": stats, "datasets": measured}, "info": {"attrs": info, "datasets": per_part}}
    if traj.series:
        groups["series"] = {"datasets": {k: np.asarray(v) for k, v in traj.series.items()},
                            "attrs": {"samples_per_period": int(scene.record.samples_per_period)}}
    if traj.events is not None:
        groups["events"] = {"datasets": event_datasets(traj.events, dt),
                            "attrs": {"kinds": {k.name: int(k.value) for k in EventKind}}}
    return {}, attrs, groups


def _end_state(value):
    """An end position or velocity as stored: a float, or for several parts a list of floats (rear-most
    first)."""
    return float(value) if np.ndim(value) == 0 else [float(v) for v in np.asarray(value)]


def _stored_end_state(value):
    """The end position or velocity :func:`_end_state` stored, as the Trajectory holds it (an array for
    several parts)."""
    return value if np.ndim(value) == 0 else np.asarray(value, dtype=float)


def trajectory_from_result(result: dict) -> Trajectory:
    """The Trajectory stored in a simulation result (:func:`read_h5` layout)."""
    a, g = result["attrs"], result["groups"]
    series = dict(g["series"]["datasets"]) if "series" in g else {}
    events = events_from_datasets(g["events"]["datasets"]) if "events" in g else None
    return Trajectory(
        x_end=_stored_end_state(a["x_end"]), v_end=_stored_end_state(a["v_end"]),
        period_end=a["period_end"], tau_end=a["tau_end"],
        status=Status(a["status"]), reason=Reason[a["reason"].upper()], message=a["message"], method=a["method"],
        options=dict(a["options"]),
        series=series, events=events, info={**g["info"]["attrs"], **g["info"].get("datasets", {})},
        stats={**g["stats"]["attrs"], **{k: float(v) for k, v in g["stats"]["datasets"].items()}},
    )


def scene_from_result(result: dict) -> Scene:
    """The scene a result was computed from (stored as YAML text in the ``scene`` attribute)."""
    import yaml

    a = result["attrs"]
    return scene_from_dict(yaml.safe_load(a["scene"]), source=f"stored scene {a.get('scene_name')!r}")


def event_label(kind: int, mode: int) -> str:
    """What an event is called in a recording: its kind, with the direction of the motion after
    it for slips and reversals, and for zone crossings whether the mass enters (moving forward)
    or leaves."""
    kind = EventKind(kind)
    if kind in (EventKind.SLIP, EventKind.REVERSAL):
        return f"{kind.name.lower()}_{'forward' if mode == FORWARD_SLIP else 'backward'}"
    if kind is EventKind.ZONE:
        return "zone_entry" if mode == FORWARD_SLIP else "zone_exit"
    return kind.name.lower()


def _event_log(events: dict, surface) -> tuple[list[str], list[str], list[str]]:
    """(labels, texts, levels) of the events of a result (:func:`event_datasets` columns)."""
    labels, texts, levels = [], [], []
    for kind, period, x, v, mode, before, after in zip(
            *(events[c].tolist() for c in ("kind", "period", "x", "v", "mode", "acc_before", "acc_after"))):
        label = event_label(kind, mode)
        if kind == EventKind.SWITCH:
            text = f"table switch: x'' {before:.10g} -> {after:.10g}"
        elif kind == EventKind.ZONE:
            boundary = "x_mu" if abs(x - surface.x_mu) <= abs(x - surface.x_end) else "x_mu + w"
            text = f"{label.replace('_', ' ')} at {boundary} = {x:.10g}, x' = {v:.10g}"
        else:
            text = f"{label.replace('_', ' ')} at x = {x:.10g}, x' = {v:.10g}"
        labels.append(label)
        texts.append(f"period {period}: {text}")
        # switches are the table's, three or more a period: below the mass's events
        levels.append("DEBUG" if kind == EventKind.SWITCH else "INFO")
    return labels, texts, levels


def _parameters(attrs: dict, scene_dict: dict) -> str:
    """The key parameters of a result as a markdown table: every scene block, then the outcome."""
    rows = [(key, ", ".join(f"{k} = {v}" for k, v in value.items()) if isinstance(value, dict) else value)
            for key, value in scene_dict.items() if key not in ("name", "description", "record")]
    rows += [("outcome", f"{attrs['status']}: {attrs['message']}"),
             ("end", f"t = {attrs['t_end']:.10g}, x = {attrs['x_end']:.10g}, x' = {attrs['v_end']:.10g}")]
    lines = [f"# {attrs['scene_name']}", "", scene_dict.get("description", ""), "", "| | |", "|---|---|"]
    return "\n".join(lines + [f"| {key} | {value} |" for key, value in rows]) + "\n"


def simulation_recording(result: dict) -> Recording:
    """The rerun recording of a simulation result (:func:`read_h5` layout), for :func:`write_recording`.

    * the recorded series as ``<plot>/<name>`` (:data:`RERUN_ENTITIES`), with mu_bar(x) of the
      scene's surface as ``friction/mu_bar`` when x is recorded, on the timelines ``time`` and
      ``period``; plots titled and ordered by :data:`RERUN_PLOTS`;
    * every event of the event log (if recorded) as a line of the text log ``events`` and,
      except table switches, as a point ``<plot>/events/<label>`` (:func:`event_label`) on the
      x and x' plots (:data:`EVENT_MARKS`);
    * the outcome as the text log ``outcome`` and a point ``position/events/<status>`` at
      (t_end, x_end) (``accumulation_limit`` for an accumulation, whose x_end is the limit);
    * the documents ``scene`` (the stored scene YAML) and ``parameters`` (a markdown table).

    Raises ValueError if nothing was recorded.
    """
    import yaml

    attrs, groups = result["attrs"], result["groups"]
    if "series" not in groups:
        raise ValueError("the result has no recorded series; a rerun recording needs record.series")
    recorded = groups["series"]["datasets"]
    series = {RERUN_ENTITIES[name]: values for name, values in recorded.items() if name != "t"}
    surface = scene_from_result(result).surface
    if "x" in recorded:
        series["friction/mu_bar"] = surface.coefficient(recorded["x"])
    markers, logs = {}, {}
    if "events" in groups:
        events = groups["events"]["datasets"]
        labels, texts, levels = _event_log(events, surface)
        logs["events"] = LogEntries(events["t"], texts, levels)
        marked = [(plot, column) for plot, column in EVENT_MARKS.items() if RERUN_ENTITIES[column] in series]
        for label in sorted(set(labels) - {"switch"}):
            chosen = np.asarray(labels) == label
            for plot, column in marked:
                markers[f"{plot}/events/{label}"] = (events["t"][chosen], events[column][chosen])
    status = Status(attrs["status"])
    end_label = "accumulation_limit" if status is Status.ACCUMULATION else status.value
    logs["outcome"] = LogEntries(np.array([attrs["t_end"]]), [attrs["message"]],
                                 ["ERROR" if status is Status.ERROR else "INFO"])
    if "x" in recorded:
        markers[f"position/events/{end_label}"] = (np.array([attrs["t_end"]]), np.array([attrs["x_end"]]))
    documents = {"scene": (attrs["scene"], "text/plain"),
                 "parameters": (_parameters(attrs, yaml.safe_load(attrs["scene"])), "text/markdown")}
    plots = {name.split("/")[0] for name in series}
    return Recording(recorded["t"], series, period=float(attrs["dt"]), markers=markers, logs=logs,
                     documents=documents, view_titles={p: t for p, t in RERUN_PLOTS.items() if p in plots})
