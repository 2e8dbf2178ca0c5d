"""Result files of the workflow stage "trajectory": the table motion of a scene sampled so that
y' is exactly linear and y'' exactly constant between neighbouring samples, and Fig. 7 drawn
from it.
"""

from __future__ import annotations

import numpy as np

from ..model.profiles import ThreePhaseProfile
from ..model.scene import Scene


def sampled_periods(scene: Scene) -> int:
    """Periods the trajectory stage samples: the scene's horizon, or one period for ``until: rest``."""
    return int(scene.periods) if scene.until == "periods" else 1


def sample_phases(scene: Scene) -> tuple[np.ndarray, np.ndarray]:
    """(period index n, time tau within the period) of every sample.

    ``samples_per_period`` uniform samples per period from ``t = phase * dt``
    over :func:`sampled_periods` periods (both ends included), plus every
    switch time of the profile in that window, so that y' is exactly linear
    and y'' exactly constant between neighbouring samples.  Times are kept
    as (n, tau) so that a sample at a switch time evaluates the piece that
    starts there (y'' is right-continuous) whatever the period index.
    """
    profile = scene.profile
    periods = sampled_periods(scene)
    spp = int(scene.record.samples_per_period)
    # Uniform grid, in periods from t = 0.
    u = scene.phase + np.arange(periods * spp + 1) / spp
    n = np.floor(u)
    tau = (u - n) * profile.dt
    switches = np.asarray(profile.switch_times, dtype=float)
    if switches.size:
        # phase < 1, so the window [phase, phase + periods] (in periods) meets periods 0..periods.
        sn, stau = np.meshgrid(np.arange(periods + 1, dtype=float), switches, indexing="ij")
        sn, stau = sn.ravel(), stau.ravel()
        at = sn + stau / profile.dt
        inside = (at >= scene.phase) & (at <= scene.phase + periods)
        n = np.concatenate([n, sn[inside]])
        tau = np.concatenate([tau, stau[inside]])
    pairs = np.unique(np.stack([n, tau], axis=1), axis=0)  # sorted by (n, tau), duplicates dropped
    return pairs[:, 0], pairs[:, 1]


def profile_samples(scene: Scene) -> tuple[dict, dict]:
    """Datasets and attributes of ``results/trajectory/<scene>.h5``.

    Datasets: ``t`` (absolute time), ``y``, ``yd``, ``ydd`` (table position,
    velocity, acceleration at ``t``; at a switch time y'' is the value of the
    piece that starts there) and ``switch_times`` (times within a period at
    which y'' jumps).  Attributes: every entry of ``profile.params()`` (``kind``
    is the profile kind), the three-phase profile's zero-velocity times
    ``t_top``, ``t_bottom`` and feasibility ``q``, ``max_abs_acceleration``,
    the sampling (``periods``, ``samples_per_period``) and ``scene``, the
    scene as YAML text.  :func:`selfalign.io.hdf5.write_h5` adds the
    package version.
    """
    import yaml

    profile = scene.profile
    n, tau = sample_phases(scene)
    datasets = {
        "t": n * profile.dt + tau,
        "y": np.asarray(profile.position(tau), dtype=float),
        "yd": np.asarray(profile.velocity(tau), dtype=float),
        "ydd": np.asarray(profile.acceleration(tau), dtype=float),
        "switch_times": np.asarray(profile.switch_times, dtype=float),
    }
    attrs = dict(profile.params())
    if isinstance(profile, ThreePhaseProfile):
        attrs.update(t_top=profile.t_top, t_bottom=profile.t_bottom, q=profile.feasibility)
    attrs.update(
        max_abs_acceleration=float(profile.max_abs_acceleration),
        periods=sampled_periods(scene),
        samples_per_period=int(scene.record.samples_per_period),
        scene_name=scene.name,
        scene=yaml.safe_dump(scene.to_dict(), sort_keys=False),
    )
    return datasets, attrs


