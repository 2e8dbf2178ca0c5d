"""Result file of the workflow stage "parts" (docs/explanation/queue.md): a queue of parts at the stop zone
(the paper's Sect. 8, recommendation 5, on the zone of Sect. 7) into ``results/parts/queue.h5``, and one
queue recorded as boxes into ``results/rerun/parts_queue.rrd``.

Three groups: ``queue``, the study of :func:`selfalign.analysis.queue.queue_study` on the Fig. 18 setting
(dimensionless, Sect. 3.2); ``queue_motion``, one queue's fronts at every period end (its figure and its
recording); ``design_queue``, queues of N = 1..n_max parts on the design that the design stage chose for a
spec (its result file is this stage's input), in SI units through the spec's scales (Sect. 3.2): end
positions past the strip's edge, errors against the single part, the time after which each part stays within
the spec's tolerance, and the parts aligned per second.  Every number follows from the settings and the
design file (no times are measured), so two runs write the same bytes.
"""

from __future__ import annotations

import numpy as np

from ..analysis.queue import (
    QUEUE_EVENTS,
    STATUSES,
    aligned_times,
    queue_parts,
    queue_study,
    run_queue,
    single_rest,
)
from ..io.recording import Boxes, LogEntries, Recording
from ..model.friction import StopZone
from ..model.profiles import ThreePhaseProfile
from .design import stop_scene


def _setting(settings: dict, zone: dict) -> tuple[ThreePhaseProfile, StopZone]:
    s = settings["setting"]
    return (ThreePhaseProfile(dt=s["dt"], dy=s["dy"], y2=s["y2"], y3=s["y3"]),
            StopZone(x_mu=settings["x_mu"], w=zone["w"], c_mu=zone["c_mu"]))


def _design_queue(design: dict, settings: dict) -> dict:
    """The ``design_queue`` group: queues of N = 1..n_max parts on the chosen design of a design result
    (read_h5 layout), in SI units."""
    scene = stop_scene(design)
    spec = design["attrs"]["spec"]
    profile, zone, si = scene.profile, scene.surface, scene.si
    n_max, distance = settings["n_max"], -scene.x0
    tolerance = spec["tolerance"] / si.L
    x_single = single_rest(profile, zone, distance=distance, max_periods=settings["max_periods"],
                           settle=settings["settle"])
    x_end, t_aligned = np.full((n_max, n_max), np.nan), np.full((n_max, n_max), np.nan)
    status = np.zeros(n_max, np.int64)
    for n in range(1, n_max + 1):
        run = run_queue(profile, zone, queue_parts(n, zone, distance=distance, spacing=settings["spacing_widths"]),
                        max_periods=settings["max_periods"], settle=settings["settle"])
        x_end[n - 1, :n] = run.x_end[::-1]
        t_aligned[n - 1, :n] = aligned_times(run, tolerance)[::-1]
        status[n - 1] = STATUSES.index(run.status)
    return {"datasets": {
        "n": np.arange(1, n_max + 1), "x_end": x_end * si.L, "error": (x_end - x_single) * si.L,
        "t_aligned": t_aligned * si.T, "throughput": np.arange(1, n_max + 1) / (np.nanmax(t_aligned, axis=1) * si.T),
        "status": status, "x_single": x_single * si.L, "x_stick_min": zone.x_stick_min(profile.max_abs_acceleration)
        * si.L, "width": zone.w * si.L, "spacing": settings["spacing_widths"] * si.L, "tolerance": spec["tolerance"]},
        "attrs": {"spec": spec["name"], "family": design["attrs"].get("family", "three_phase"),
                  "period": profile.dt * si.T, "c_mu": zone.c_mu, "max_periods": settings["max_periods"]}}


def queue_results(settings: dict, zone: dict, design: dict) -> tuple[dict, dict, dict]:
    """(datasets, attrs, groups) of results/parts/queue.h5.

    Parameters
    ----------
    settings : dict
        The config block ``stages: parts:`` (workflow/config/config.yaml).
    zone : dict
        ``w`` and ``c_mu`` of the stop zone (the accumulation stage's).
    design : dict
        The design stage's result of the spec (read_h5 layout).

    Returns
    -------
    tuple of (dict, dict, dict)
        For :func:`selfalign.io.hdf5.write_h5`.

    Raises
    ------
    TypeError, ValueError
        As :func:`selfalign.analysis.queue.queue_study` for a bad setting.

    Examples
    --------
    One part, on the Fig. 18 setting and on a design of the Fig. 18 shape for a 2 mm part with mu = 0.2 (the
    workflow reads the design stage's result instead):

    >>> from selfalign.model.units import SIScale
    >>> from selfalign.stages.parts import queue_results
    >>> si = SIScale(mu=0.2, g=9.81, L=0.002)
    >>> a = si.unit("acceleration")
    >>> design = {"attrs": {"spec": {"name": "demo", "mu": 0.2, "g": 9.81, "width": 0.002, "distance": 0.01,
    ...                              "tolerance": 1e-4}},
    ...           "groups": {"profile": {"datasets": {"period": 1.05 * si.T, "stroke": 0.084 * si.L, "y2": 2.2 * a,
    ...                                               "y3": 0.9 * a, "c_mu": 2.5}},
    ...                      "performance": {"datasets": {"t_rest": 1.0}}}}
    >>> settings = {"setting": {"dt": 1.05, "dy": 0.084, "y2": 2.2, "y3": 0.9}, "x_mu": 0.5, "distance": 0.25,
    ...             "n_max": 1, "spacings": [0.0], "restitutions": [0.0], "spreads": [0.0], "max_periods": 1000,
    ...             "settle": 1e-12, "settle_periods": 10, "motion": {"n": 1, "spacing": 0.0, "restitution": 0.0},
    ...             "design": {"n_max": 1, "spacing_widths": 1.0, "max_periods": 1000, "settle": 1e-12}}
    >>> datasets, attrs, groups = queue_results(settings, {"w": 0.05, "c_mu": 2.5}, design)
    >>> sorted(groups), round(float(groups["design_queue"]["datasets"]["x_single"]) * 1e3, 6)
    (['design_queue', 'queue', 'queue_motion'], 1.6)
    """
    profile, stop = _setting(settings, zone)
    study = queue_study(profile, stop, n_max=settings["n_max"], spacings=settings["spacings"],
                        restitutions=settings["restitutions"], spreads=settings["spreads"],
                        distance=settings["distance"], max_periods=settings["max_periods"],
                        settle=settings["settle"], settle_periods=settings["settle_periods"])
    motion = settings["motion"]
    run = run_queue(profile, stop, queue_parts(motion["n"], stop, distance=settings["distance"],
                                               spacing=motion["spacing"]),
                    restitution=motion["restitution"], max_periods=settings["max_periods"],
                    settle=settings["settle"], settle_periods=settings["settle_periods"])
    setting = {**settings["setting"], "x_mu": stop.x_mu, "w": stop.w, "c_mu": stop.c_mu}
    groups = {
        "queue": {"datasets": {**study, "x_mu": stop.x_mu}, "attrs": setting},
        "queue_motion": {"datasets": {"t": run.t, "x": run.x, "width": np.full(motion["n"], stop.w),
                                      "events": run.part_events},
                         "attrs": {**setting, **motion, "status": run.status, "event_kinds": list(QUEUE_EVENTS)}},
        "design_queue": _design_queue(design, settings["design"]),
    }
    return {}, {"setting": setting}, groups


def queue_recording(result: dict) -> Recording:
    """The rerun recording of the ``queue_motion`` group of a queue result (read_h5 layout): one box per part,
    its width, moving over the zone (a static box from x_mu to x_mu + w, the transition of eqs. 7-9),
    and each part's front as a series.

    Parameters
    ----------
    result : dict
        results/parts/queue.h5 read with :func:`selfalign.io.hdf5.read_h5`.

    Returns
    -------
    Recording
        With ``boxes`` ``queue/parts`` and ``queue/zone``, series ``front/part_<i>`` and, where the result
        holds the events per part and period, the log ``queue/events``: at each period end, the events of each
        part in that period (sticks, slips, impacts, openings, zone crossings).

    Raises
    ------
    KeyError
        If the result has no ``queue_motion`` group.

    Examples
    --------
    >>> import numpy as np
    >>> from selfalign.stages.parts import queue_recording
    >>> attrs = {"x_mu": 0.5, "w": 0.05, "c_mu": 2.5, "spacing": 0.05, "restitution": 0.0, "dt": 1.05, "dy": 0.084,
    ...          "y2": 2.2, "y3": 0.9, "status": "settled"}
    >>> motion = {"datasets": {"t": np.array([0.0, 1.05]), "x": np.array([[0.2, 0.3], [0.25, 0.35]]),
    ...                        "width": np.array([0.05, 0.05])}, "attrs": attrs}
    >>> recording = queue_recording({"groups": {"queue_motion": motion}})
    >>> recording.boxes["queue/parts"].centres.round(3).tolist(), sorted(recording.series)
    ([[0.175, 0.275], [0.225, 0.325]], ['front/part_0', 'front/part_1'])
    """
    motion = result["groups"]["queue_motion"]
    t, x, width = (np.asarray(motion["datasets"][k], float) for k in ("t", "x", "width"))
    a = motion["attrs"]
    height = float(np.max(width))
    boxes = {"queue/parts": Boxes(centres=x - width / 2, half_widths=width / 2, half_height=height / 2),
             "queue/zone": Boxes(centres=np.full((t.size, 1), a["x_mu"] + a["w"] / 2),
                                 half_widths=np.array([a["w"] / 2]), half_height=height)}
    series = {f"front/part_{i}": x[:, i] for i in range(x.shape[1])}
    text = (f"{x.shape[1]} parts of width {a['w']:g} queue at the stop zone x_mu = {a['x_mu']:g}, c_mu = "
            f"{a['c_mu']:g} (docs/explanation/queue.md); gap {a['spacing']:g}, e = {a['restitution']:g}; "
            f"Fig. 18 profile dt = {a['dt']:g}, dy = {a['dy']:g}, y2'' = {a['y2']:g}, y3'' = {a['y3']:g}; "
            f"positions at the period ends; the run ends: {a['status']}.")
    logs = {}
    if "events" in motion["datasets"]:
        lines = _event_lines(np.asarray(motion["datasets"]["events"]), list(a["event_kinds"]))
        logs["queue/events"] = LogEntries(times=t[1:][[k for k, _ in lines]], texts=[line for _, line in lines],
                                          levels=["INFO"] * len(lines))
    return Recording(t, series, period=float(a["dt"]), boxes=boxes, documents={"queue": (text, "text/plain")},
                     view_titles={"front": "front positions x_i"}, logs=logs)


def _event_lines(events: np.ndarray, kinds: list[str]) -> list[tuple[int, str]]:
    """(period index, text) of each period with events: per part, its counts of each kind (``events`` of shape
    (periods, N, kinds))."""
    lines = []
    for k, period in enumerate(events):
        parts = ["part " + str(i) + ": " + ", ".join(f"{int(c)} {kind}" for c, kind in zip(row, kinds) if c)
                 for i, row in enumerate(period) if np.any(row)]
        if parts:
            lines.append((k, f"period {k + 1}: " + "; ".join(parts)))
    return lines
