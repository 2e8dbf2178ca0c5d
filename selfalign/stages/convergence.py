"""Result files of the workflow stage "convergence" (Sect. 6.2, docs/explanation/stability.md): two
velocity transients and the Lyapunov function V of eq. (35), and their rerun recording.
"""

from __future__ import annotations

import numpy as np

from ..analysis.lyapunov import scene_trace
from ..io.recording import Recording
from ..model.profiles import ThreePhaseProfile
from ..model.scene import Scene


def convergence_result(scene: Scene, v20: float) -> tuple[dict, dict]:
    """Datasets and attributes of ``results/convergence/<scene>.h5`` (docs/reference/results.md).

    Datasets: the samples ``t``, ``v1``, ``v2``, ``V``, ``dV`` of :class:`LyapunovTrace`,
    the labelled intervals ``interval_start``, ``interval_end``, ``interval_equal``, and
    ``period_t``, ``period_V`` (V at the period boundaries).  Attributes: the profile's
    parameters, ``v10``, ``v20``, ``periods``, ``samples_per_period``,
    ``converged_time``, for a three-phase profile ``case`` and the analytic ``lambda2``
    (eq. 33), and the scene.
    """
    import yaml

    trace = scene_trace(scene, v20)
    profile = scene.profile
    periods = int(scene.periods)
    datasets = {
        "t": trace.t, "v1": trace.v1, "v2": trace.v2, "V": trace.V, "dV": trace.dV,
        "interval_start": trace.interval_start, "interval_end": trace.interval_end,
        "interval_equal": trace.interval_equal,
        "period_t": profile.dt * (scene.phase + np.arange(periods + 1)), "period_V": trace.period_V,
    }
    attrs = dict(profile.params())
    if isinstance(profile, ThreePhaseProfile):
        from ..analysis.steady_state import floquet_multipliers_analytic, steady_state

        attrs.update(case=steady_state(profile).case, lambda2=float(floquet_multipliers_analytic(profile)[1]))
    attrs.update(v10=scene.v0, v20=float(v20), periods=periods,
                 samples_per_period=int(scene.record.samples_per_period),
                 converged_time=trace.converged_time, scene_name=scene.name,
                 scene=yaml.safe_dump(scene.to_dict(), sort_keys=False))
    return datasets, attrs


def convergence_recording(result: dict) -> Recording:
    """The rerun recording of a convergence result: the two velocities share one view, V has
    its own; period numbers beside the time."""
    d = result["datasets"]
    return Recording(d["t"], {"velocity/v1": d["v1"], "velocity/v2": d["v2"], "lyapunov/V": d["V"]},
                     period=float(result["attrs"]["dt"]))
