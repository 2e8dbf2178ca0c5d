"""Simulation results as HDF5 content and rerun series, and back.

The simulation stage stores one :class:`~selfalign.solvers.outcomes.Trajectory` per
scene in ``results/simulation/<scene>.h5`` through
:func:`selfalign.io.hdf5.write_h5`; :func:`trajectory_content` builds what is
written and :func:`trajectory_from_result` rebuilds the Trajectory from
:func:`selfalign.io.hdf5.read_h5`'s output, so that later stages and figures
work on the same object a direct ``simulate`` call returns.

Layout (README "Results"):

* root attributes: ``scene_name``, ``scene`` (YAML text of ``scene.to_dict()``),
  ``method``, ``options`` (the solver options used), ``status``, ``reason``, ``message``,
  ``x_end``, ``v_end``, ``period_end``, ``tau_end``, ``t_end`` (= period_end
  dt + tau_end, for plotting), ``dt``; ``selfalign_version`` is added by
  ``write_h5``;
* group ``stats``: one attribute per entry of ``Trajectory.stats`` (events,
  steps, cpu_time, ...); group ``info``: likewise for ``Trajectory.info``;
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
from ..solvers.outcomes import EventKind, Reason, Status
from ..solvers.records import EVENT_DTYPE
from ..solvers.results import Trajectory
from .scene_files import scene_from_dict

#: Rerun entity path of each recordable series: one plot per quantity kind.
RERUN_ENTITIES = {
    "x": "position/x",
    "y": "position/y",
    "v": "velocity/v",
    "yd": "velocity/yd",
    "ydd": "acceleration/ydd",
    "friction": "force/friction",
    "mode": "mode/mode",
}


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
        "x_end": float(traj.x_end),
        "v_end": float(traj.v_end),
        "period_end": int(traj.period_end),
        "tau_end": float(traj.tau_end),
        "t_end": int(traj.period_end) * dt + float(traj.tau_end),
        "dt": dt,
    }
    groups = {"stats": {"attrs": dict(traj.stats)}, "info": {"attrs": dict(traj.info)}}
    if traj.series:
        groups["series"] = {"datasets": {k: np.asarray(v) for k, v in traj.series.items()},
                            "attrs": {"samples_per_period": int(scene.record.samples_per_period)}}
    if traj.events is not None:
        groups["events"] = {"datasets": event_datasets(traj.events, dt),
                            "attrs": {"kinds": {k.name: int(k.value) for k in EventKind}}}
    return {}, attrs, groups


def trajectory_from_result(result: dict) -> Trajectory:
    """The Trajectory stored in a simulation result (:func:`read_h5` layout)."""
    a, g = result["attrs"], result["groups"]
    series = dict(g["series"]["datasets"]) if "series" in g else {}
    events = events_from_datasets(g["events"]["datasets"]) if "events" in g else None
    return Trajectory(
        x_end=a["x_end"], v_end=a["v_end"], period_end=a["period_end"], tau_end=a["tau_end"],
        status=Status(a["status"]), reason=Reason[a["reason"].upper()], message=a["message"], method=a["method"],
        options=dict(a["options"]),
        series=series, events=events, stats=dict(g["stats"]["attrs"]), info=dict(g["info"]["attrs"]),
    )


def scene_from_result(result: dict) -> Scene:
    """The scene a result was computed from (stored as YAML text in the ``scene`` attribute)."""
    import yaml

    a = result["attrs"]
    return scene_from_dict(yaml.safe_load(a["scene"]), source=f"stored scene {a.get('scene_name')!r}")


def rerun_series(traj: Trajectory) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """(times, {entity path: values}) of the recorded series, for :func:`write_recording`.

    Entities are named by :data:`RERUN_ENTITIES` (``position/x``, ``velocity/v``,
    ``force/friction``, ...), so the recording's default blueprint draws one plot
    per quantity kind.  Raises ValueError if nothing was recorded.
    """
    if not traj.series:
        raise ValueError("the trajectory has no recorded series; a rerun recording needs record.series")
    series = {RERUN_ENTITIES[name]: np.asarray(values, dtype=float)
              for name, values in traj.series.items() if name != "t"}
    return np.asarray(traj.series["t"], dtype=float), series
