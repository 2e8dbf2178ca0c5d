"""Result file of the workflow stage "planar" (docs/explanation/planar-alignment.md): the drift of a part under
a planar table motion and its self-alignment at a strip and at a corner of two strips (the paper's Sect. 8,
recommendation 4) into ``results/planar/planar.h5``, and one entry recorded in the plane into
``results/rerun/planar_motion.rrd``.

Groups (dimensionless, Sect. 3.2): ``drift_three_phase`` and ``drift_harmonic``, the maps of v_bar over the
phase offset and the amplitude ratio of two three-phase profiles and of a two-harmonic orbit
(:func:`selfalign.analysis.planar_drift.drift_map`); ``symmetric``, orbits with Y(t + dt/2) = -Y(t) (a
circle, an ellipse, a line at an angle), which never drift; ``low_acceleration``, motions with max|Y''| <= 1;
``limit_three_phase`` and ``limit_harmonic``, v_bar against the high-acceleration limit as the motion is
scaled up; ``line_along`` and ``line_planar``, entries onto a strip at a range of angles for a motion along
the drift and for a planar one; ``corner``, entries onto the corner of two strips; ``example_line`` and
``example_corner``, one entry's path in the plane.  Every number follows from the settings (no times are
measured), so two runs write the same bytes.
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis.planar_alignment import CornerAlignment, LineAlignment, corner_alignment, line_alignment
from ..analysis.planar_drift import (
    AccelerationLimit,
    DriftMap,
    acceleration_limit,
    drift_map,
    harmonic_orbit,
    steady_drift,
    three_phase_pair,
)
from ..io.recording import Boxes, Recording
from ..model.planar import Strip
from ..model.scene import Record, Scene
from ..solvers.driver import simulate

#: Samples per period of the example paths (figure and recording).
EXAMPLE_SAMPLES = 40
#: Drawn size of the part in the recording, in strip widths.
PART_SIZE_WIDTHS = 0.5


def _map_group(m: DriftMap, attrs: dict) -> dict:
    return {"datasets": {"offset": m.offsets, "amplitude": m.amplitudes, "v_bar": m.v_bar, "speed": m.speed,
                         "direction": m.direction, "periods": m.periods, "converged": m.converged,
                         "max_acceleration": m.max_acceleration}, "attrs": attrs}


def _limit_group(scales, fit: AccelerationLimit, attrs: dict) -> dict:
    local = math.log(fit.error[-1] / fit.error[-2]) / math.log(fit.max_acceleration[-1] / fit.max_acceleration[-2])
    return {"datasets": {"scale": np.asarray(scales, float), "max_acceleration": fit.max_acceleration,
                         "v_bar": fit.v_bar, "v_limit": fit.v_limit, "error": fit.error, "periods": fit.periods,
                         "slope": fit.slope, "constant": fit.constant, "local_slope": local},
            "attrs": attrs}


def _line_group(a: LineAlignment, attrs: dict) -> dict:
    return {"datasets": {"angle": a.angles, "normal": a.normals, "v_bar": a.drift.v_bar, "depth": a.depth,
                         "along": a.along, "lateral": a.lateral, "x_end": a.x_end, "stopped": a.stopped,
                         "reason": a.reason, "dx_d_normal": a.dx_d_normal, "dx_d_along": a.dx_d_along,
                         "dx_d_slide": a.dx_d_slide, "at_limit": a.at_limit, "stick_depth": a.stick_depth},
            "attrs": {**attrs, "x_mu": a.x_mu, "w": a.w, "c_mu": a.c_mu}}


def _corner_group(c: CornerAlignment, attrs: dict) -> dict:
    e = c.entries
    return {"datasets": {"normal": np.array([s.normal for s in c.strips]), "corner": c.corner, "start": e.start,
                         "x_end": e.x_end, "stopped": e.stopped, "reason": e.reason, "first": c.first,
                         "distance": c.distance_to_corner, "spread_radius": c.spread_radius, "dx_d": e.spread(),
                         "stick_depth": c.stick_depth},
            "attrs": {**attrs, "x_mu": 0.0, "w": c.strips[0].w, "c_mu": c.strips[0].c_mu}}


def _example(profile, surface, start, v_start, strips, settings: dict, method: str, options: dict,
             attrs: dict) -> dict:
    """One entry's path in the plane, sampled EXAMPLE_SAMPLES times per period until rest."""
    run = simulate(Scene(profile, surface=surface, x0=tuple(start), v0=tuple(v_start), until="rest",
                         max_periods=settings["periods"], method=method, solver_options=options,
                         record=Record(series=("x",), samples_per_period=EXAMPLE_SAMPLES)))
    return {"datasets": {"t": np.asarray(run.series["t"], float), "x": np.asarray(run.series["x"], float),
                         "normal": np.array([s.normal for s in strips]),
                         "x_mu": np.array([s.x_mu for s in strips])},
            "attrs": {**attrs, "w": strips[0].w, "c_mu": strips[0].c_mu, "dt": profile.dt,
                      "reason": int(run.reason)}}


def planar_results(settings: dict) -> tuple[dict, dict, dict]:
    """(datasets, attrs, groups) of results/planar/planar.h5.

    Parameters
    ----------
    settings : dict
        The config block ``stages: planar:`` (workflow/config/config.yaml).

    Returns
    -------
    tuple of (dict, dict, dict)
        For :func:`selfalign.io.hdf5.write_h5`.

    Raises
    ------
    TypeError, ValueError
        As the functions of :mod:`selfalign.analysis.planar_drift` and
        :mod:`selfalign.analysis.planar_alignment` for a bad setting.

    Examples
    --------
    A shrunk study (the workflow's config is larger):

    >>> from selfalign.stages.planar import planar_results
    >>> tp = {"dt": 1.05, "dy": 0.084, "y2": 2.2, "y3": 0.9}
    >>> settings = {"method": "exact", "solver_options": {}, "tol": 1e-10,
    ...     "max_periods": 5000, "three_phase": tp, "offsets": 1,
    ...     "ratios": [0.0], "harmonic": {"dt": 1.0, "a": 0.05, "second": 0.3}, "harmonic_ratios": [0.0],
    ...     "symmetric": {"a": 0.05, "ratios": [1.0], "angle": 0.5}, "low_scales": [0.4],
    ...     "limit": {"scales": [8.0, 16.0], "three_phase": {"dt": 1.0, "dy": 0.064, "y2": 3.0, "y3": 1.5,
    ...               "ratio": 0.5, "offset": 0.3}, "harmonic": {"ratio": 0.4, "offset": 0.25}},
    ...     "alignment": {"w": 0.05, "c_mu": 2.5, "planar": {"ratio": 0.4, "offset": 0.5}, "angles": [30.0],
    ...                   "distance": 0.1, "starts": 1, "lateral": [0.0], "max_periods": 400,
    ...                   "corner": {"half_angle": 45.0, "starts": 1, "lateral": [0.0]},
    ...                   "example": {"angle": 30.0, "periods": 60}}}
    >>> datasets, attrs, groups = planar_results(settings)
    >>> groups["line_along"]["datasets"]["at_limit"].tolist()
    [1.0]
    """
    method, tol, max_periods = settings["method"], float(settings["tol"]), int(settings["max_periods"])
    options = dict(settings.get("solver_options") or {})
    steady = {"method": method, "tol": tol, "max_periods": max_periods, "solver_options": options}
    tp, hm = settings["three_phase"], settings["harmonic"]
    offsets = np.arange(int(settings["offsets"])) / int(settings["offsets"])
    pair = lambda p, r: three_phase_pair(tp["dt"], tp["dy"], tp["y2"], tp["y3"], ratio=r, offset=p)  # noqa: E731
    orbit = lambda p, r: harmonic_orbit(hm["dt"], hm["a"], r * hm["a"], offset=p, second=hm["second"])  # noqa: E731
    groups = {
        "drift_three_phase": _map_group(drift_map(pair, offsets, settings["ratios"], **steady), tp),
        "drift_harmonic": _map_group(drift_map(orbit, offsets, settings["harmonic_ratios"], **steady), hm),
    }
    sym = settings["symmetric"]
    orbits = [harmonic_orbit(hm["dt"], sym["a"], r * sym["a"]) for r in sym["ratios"]]
    orbits.append(harmonic_orbit(hm["dt"], sym["a"], 0.0, angle=sym["angle"]))
    names = [f"ellipse b/a = {r:g}" for r in sym["ratios"]] + [f"line at {sym['angle']:g} rad"]
    drifts = [steady_drift(p, **steady) for p in orbits]
    groups["symmetric"] = {"datasets": {"orbit": np.array(names), "v_bar": np.array([d.v_bar for d in drifts]),
                                        "periods": np.array([d.periods for d in drifts]),
                                        "max_acceleration": np.array([p.max_abs_acceleration for p in orbits])},
                           "attrs": {"dt": hm["dt"], "a": sym["a"]}}
    low = [three_phase_pair(tp["dt"], tp["dy"], tp["y2"], tp["y3"], ratio=0.5, offset=0.3, scale=s)
           for s in settings["low_scales"]]
    groups["low_acceleration"] = {"datasets": {
        "scale": np.asarray(settings["low_scales"], float),
        "max_acceleration": np.array([p.max_abs_acceleration for p in low]),
        "v_bar": np.array([steady_drift(p, **steady).v_bar for p in low])}, "attrs": {**tp, "ratio": 0.5,
                                                                                     "offset": 0.3}}
    lim = settings["limit"]
    lt, lh, scales = lim["three_phase"], lim["harmonic"], lim["scales"]
    groups["limit_three_phase"] = _limit_group(scales, acceleration_limit(
        [three_phase_pair(lt["dt"], lt["dy"], lt["y2"], lt["y3"], ratio=lt["ratio"], offset=lt["offset"], scale=s)
         for s in scales], **steady), lt)
    groups["limit_harmonic"] = _limit_group(scales, acceleration_limit(
        [harmonic_orbit(hm["dt"], s * hm["a"], s * lh["ratio"] * hm["a"], offset=lh["offset"], second=hm["second"])
         for s in scales], **steady), {**hm, **lh})
    al = settings["alignment"]
    starts = np.arange(int(al["starts"])) / int(al["starts"])
    planar_attrs = {**tp, **al["planar"]}
    motions = {"line_along": (three_phase_pair(tp["dt"], tp["dy"], tp["y2"], tp["y3"], ratio=0.0, offset=0.0),
                              {**tp, "ratio": 0.0, "offset": 0.0}),
               "line_planar": (three_phase_pair(tp["dt"], tp["dy"], tp["y2"], tp["y3"], **al["planar"]), planar_attrs)}
    line = {"w": al["w"], "c_mu": al["c_mu"], "distance": al["distance"], "method": method,
            "max_periods": al["max_periods"], "solver_options": options}
    for name, (profile, attrs) in motions.items():
        groups[name] = _line_group(line_alignment(profile, angles=np.radians(al["angles"]), offsets=starts,
                                                  lateral=al["lateral"], **line), attrs)
    planar = motions["line_planar"][0]
    co = al["corner"]
    corner = corner_alignment(planar, half_angle=math.radians(co["half_angle"]),
                              offsets=np.arange(int(co["starts"])) / int(co["starts"]), lateral=co["lateral"], **line)
    groups["corner"] = _corner_group(corner, {**planar_attrs, "half_angle": math.radians(co["half_angle"])})
    ex = al["example"]
    example = line_alignment(planar, angles=[math.radians(ex["angle"])], offsets=[0.0], lateral=[0.0], **line)
    strip = Strip(normal=tuple(example.normals[0]), x_mu=0.0, w=al["w"], c_mu=al["c_mu"])
    groups["example_line"] = _example(planar, strip, example.start[0, 0], example.drift.v_start, (strip,), ex,
                                      method, options, {**planar_attrs, "angle": math.radians(ex["angle"])})
    groups["example_corner"] = _example(planar, list(corner.strips), corner.entries.start[0],
                                        example.drift.v_start, corner.strips, ex, method, options,
                                        {**planar_attrs, "half_angle": math.radians(co["half_angle"])})
    return {}, {"method": method}, groups


def _edges(normals, x_mu, w: float, reach: float) -> np.ndarray:
    """The two edges n.x = x_mu and n.x = x_mu + w of each strip as segments of half length ``reach`` about
    the origin's foot point, shape (2 strips, 2, 2)."""
    out = []
    for n, edge in zip(np.asarray(normals, float), np.asarray(x_mu, float)):
        t = np.array([-n[1], n[0]])
        out.extend([(edge + d) * n + np.outer([-reach, reach], t) for d in (0.0, w)])
    return np.array(out)


def planar_recording(result: dict) -> Recording:
    """The rerun recording of the ``example_line`` and ``example_corner`` groups of a planar result (read_h5
    layout): the part as a small square moving in the plane over the edges of the strips (n.x = x_mu, where
    the transition of eqs. 7-9 starts, and n.x = x_mu + w, where c_mu is reached), and its coordinates as
    series.

    Parameters
    ----------
    result : dict
        results/planar/planar.h5 read with :func:`selfalign.io.hdf5.read_h5`.

    Returns
    -------
    Recording
        Boxes ``line/part`` and ``corner/part``, lines ``line/strip`` and ``corner/strips``, series
        ``line_position/x``, ``line_position/y``, ``corner_position/x``, ``corner_position/y``.  The
        shorter path is held at its end position until the longer one ends.

    Raises
    ------
    KeyError
        If the result has no ``example_line`` or ``example_corner`` group.

    Examples
    --------
    >>> import numpy as np
    >>> from selfalign.stages.planar import planar_recording
    >>> path = {"t": np.array([0.0, 0.5, 1.0]), "x": np.array([[-0.1, 0.0], [-0.05, 0.0], [0.0, 0.0]]),
    ...         "normal": np.array([[1.0, 0.0]]), "x_mu": np.array([0.0])}
    >>> attrs = {"w": 0.05, "c_mu": 2.5, "dt": 1.0, "reason": 4}
    >>> example = {"datasets": path, "attrs": attrs}
    >>> recording = planar_recording({"groups": {"example_line": example, "example_corner": example}})
    >>> recording.boxes["line/part"].centres[-1].tolist(), recording.lines["line/strip"].shape
    ([[0.0, 0.0]], (2, 2, 2))
    """
    line, corner = result["groups"]["example_line"], result["groups"]["example_corner"]
    paths = [np.asarray(g["datasets"]["x"], float) for g in (line, corner)]
    times = max((np.asarray(g["datasets"]["t"], float) for g in (line, corner)), key=len)
    paths = [np.concatenate([p, np.repeat(p[-1:], times.size - len(p), axis=0)]) for p in paths]
    w = float(line["attrs"]["w"])
    size = PART_SIZE_WIDTHS * w / 2.0
    boxes, lines, series = {}, {}, {}
    for name, strips, group, path in (("line", "strip", line, paths[0]), ("corner", "strips", corner, paths[1])):
        d = group["datasets"]
        reach = float(np.max(np.abs(path))) + 2.0 * w
        boxes[f"{name}/part"] = Boxes(path[:, None, :], np.array([size]), size)
        lines[f"{name}/{strips}"] = _edges(d["normal"], d["x_mu"], w, reach)
        series[f"{name}_position/x"], series[f"{name}_position/y"] = path[:, 0], path[:, 1]
    text = (f"A point part on a table moving in the plane (docs/explanation/planar-alignment.md) drifts onto a "
            f"strip of width w = {w:g} and c_mu = {float(line['attrs']['c_mu']):g} (view line) and onto the "
            f"corner of two such strips (view corner); the lines are the strips' edges n.x = x_mu and "
            f"n.x = x_mu + w.  The part sticks for good where mu_bar(x) >= max|Y''|.")
    return Recording(times, series, period=float(line["attrs"]["dt"]), boxes=boxes, lines=lines,
                     documents={"planar": (text, "text/plain")})
