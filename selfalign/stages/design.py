"""Result files of the workflow stage "design" (docs/tutorials/design-station.md):
each spec of ``workflow/designs/`` designed (:func:`selfalign.analysis.design.design`) with its
design map (of the three-phase design, the map's family) into ``results/design/<spec>.h5``, with
the gain of the optimal family over the paper's where the spec searches both (group ``gain``, and
a line of the log), and the chosen design's stop at the nominal mu as a rerun recording.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import yaml

from ..analysis.design import design, design_map
from ..analysis.optimal_motion import centred_motion
from ..io.design_result import design_content
from ..io.design_spec import load_design_spec
from ..io.recording import Recording
from ..io.simulation_result import _parameters, simulation_recording, trajectory_content
from ..model.friction import StopZone
from ..model.profiles import PiecewiseConstantProfile, ThreePhaseProfile
from ..model.scene import Record, Scene
from ..model.units import SIScale
from ..solvers.driver import simulate

#: Samples per period of the recorded stop.
SAMPLES_PER_PERIOD = 100


def design_results(spec_path, *, map_refine: int, map_entries: int, progress: str = "auto"):
    """((datasets, attrs, groups) of results/design/<spec>.h5, the Design) of the spec file."""
    result = design(load_design_spec(spec_path), progress=progress)
    paper = result if result.family == "three_phase" else result.other
    chart = design_map(paper, refine=map_refine, entries=map_entries, progress=progress) \
        if paper is not None and paper.verification is not None else None
    return design_content(result, chart), result


def stop_scene(result: dict) -> Scene:
    """The chosen design's process run at the nominal mu as a scene (read_h5 layout of a design
    result): the part at rest the spec's distance before the strip at t = 0, until rest; in model
    units with the SI scale L = the part's width."""
    spec = result["attrs"]["spec"]
    profile = result["groups"]["profile"]["datasets"]
    scale = SIScale(mu=spec["mu"], g=spec["g"], L=spec["width"])
    accel = scale.unit("acceleration")
    if "breaks" in profile:  # the optimal family
        breaks, accels = np.asarray(profile["breaks"]) / scale.T, np.asarray(profile["accels"]) / accel
        y_start, yd_start, _, _ = centred_motion(breaks, accels)
        dimensionless = PiecewiseConstantProfile(breaks, accels, y_start=y_start, yd_start=yd_start)
    else:
        dimensionless = ThreePhaseProfile(float(profile["period"]) / scale.T, float(profile["stroke"]) / scale.L,
                                          float(profile["y2"]) / accel, float(profile["y3"]) / accel)
    t_rest = float(result["groups"]["performance"]["datasets"]["t_rest"])
    periods = 2 * math.ceil(t_rest / float(profile["period"])) + 1000
    return Scene(dimensionless, StopZone(x_mu=0.0, w=1.0, c_mu=float(profile["c_mu"])),
                 x0=-spec["distance"] / scale.L, v0=0.0, phase=0.0, until="rest", max_periods=periods,
                 record=Record(series=("x", "v", "ydd", "friction", "mode"), samples_per_period=SAMPLES_PER_PERIOD,
                               events=True, rerun=True),
                 name=f"design_{spec['name']}", si=scale,
                 description=f"the stop of design {spec['name']} at the nominal mu")


def stop_recording(result: dict) -> Recording:
    """The rerun recording of the chosen design's stop (:func:`stop_scene`).

    A scene file holds no piecewise-constant profile, so for a design of the optimal family the
    recording is built with the surface of a stand-in scene (same stop zone and period) and its
    documents give the true scene, the motion's pieces included."""
    scene = stop_scene(result)
    datasets, attrs, groups = trajectory_content(simulate(scene), scene)
    if result["attrs"].get("family", "three_phase") == "three_phase":
        return simulation_recording({"datasets": datasets, "attrs": attrs, "groups": groups})
    stored = scene.to_dict()
    stored["profile"] = {"kind": "piecewise_constant", "dt": float(scene.profile.dt),
                         "breaks": scene.profile.breaks.tolist(), "accels": scene.profile.accels.tolist()}
    stand_in = {**{k: v for k, v in stored.items() if k != "record"}, "solver": {"method": "moreau"},
                "profile": {"kind": "fourier", "dt": float(scene.profile.dt), "cos_coeffs": [0.0], "sin_coeffs": [1.0]}}
    recording = simulation_recording({"datasets": datasets, "attrs": {**attrs, "scene": yaml.safe_dump(stand_in)},
                                      "groups": groups})
    return replace(recording, documents={"scene": (yaml.safe_dump(stored, sort_keys=False), "text/plain"),
                                         "parameters": (_parameters(attrs, stored), "text/markdown")})
