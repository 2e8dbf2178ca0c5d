"""Kernel profile tables: the rows the compiled engine reads a profile from, for one profile,
a list of them, or a vectorised sweep of the paper's three-phase settings (Sect. 4.4.3).

A row is built once per profile object and solver (cached on the profile); a
:class:`ProfileTable` holds the rows of a batch, all for one kernel method code.
"""

from __future__ import annotations

import numpy as np

from ..model.friction import FrictionLaw
from ..model.profiles import FiniteJerkProfile, Profile, ThreePhaseProfile, three_phase_times
from . import exact, moreau
from . import records as R
from .exact import piecewise_rows
from .methods import MethodChoice, most_exact_method, resolve


def kernel_row(method: str, profile: Profile, phase: float, options: dict) -> tuple[int, np.ndarray]:
    """(kernel method code, profile row), cached on the profile object."""
    key = (method, phase, options.get("h"), options.get("steps_per_period")) if method == "moreau" else (method,)
    cache = profile.__dict__.setdefault("_kernel_rows", {})
    if key not in cache:
        if method == "moreau":
            cache[key] = (R.MOREAU, moreau.profile_row(profile, phase, options))
        else:
            cache[key] = exact.profile_row(profile)
    return cache[key]


class ProfileTable:
    """Profile rows for a batch: ``rows`` (P, width) of the kernel's profile table, all of
    one kernel method ``code``.  Build it from profiles (:func:`profile_table`) or, for a
    vectorised sweep, from arrays (:func:`selfalign.solvers.exact.piecewise_rows`)."""

    def __init__(self, rows: np.ndarray, code: int):
        self.rows = np.ascontiguousarray(rows, dtype=float)
        self.code = int(code)

    @property
    def size(self) -> int:
        return self.rows.shape[0]


def profile_table(profiles, method: str, phase, options: dict) -> ProfileTable:
    """The :class:`ProfileTable` of ``profiles`` (one, a sequence, or a table already) for ``method``."""
    if isinstance(profiles, ProfileTable):
        if method == "moreau" and profiles.code != R.MOREAU or method == "exact" and profiles.code == R.MOREAU:
            raise ValueError(f"the profile table was built for another method than {method!r}")
        return profiles
    one = isinstance(profiles, (Profile, str)) or not np.iterable(profiles)
    profiles = [profiles] if one else list(profiles)
    wrong = sorted({type(p).__name__ for p in profiles if not isinstance(p, Profile)})
    if wrong:
        raise TypeError(f"profiles: give a selfalign profile, a sequence of them, or a ProfileTable; got {wrong}")
    if not profiles:
        raise ValueError("profiles: give a selfalign profile, a non-empty sequence of them, or a ProfileTable")
    phase0 = float(np.ravel(phase)[0]) if np.size(phase) else 0.0
    rows = [kernel_row(method, p, phase0, options) for p in profiles]
    codes = {code for code, _ in rows}
    if len(codes) > 1:
        raise ValueError("a batch runs one kind of profile: all piecewise-constant, or all Fourier")
    return ProfileTable(R.pack_profiles([row for _, row in rows]), codes.pop())


def three_phase_table(dt, dy, y2, y3) -> ProfileTable:
    """Kernel profile table of three-phase profiles (flat arrays; every one physical)."""
    times = three_phase_times(dt, dy, y2, y3)
    if not np.all(times.feasible):
        raise ValueError("three-phase profiles: every (dt, dy, y2, y3) must be physical (q <= 1)")
    zero = np.zeros_like(times.t1)
    breaks = np.stack([zero, times.t1, times.t2, times.t3], axis=-1)
    accels = np.stack([zero, -np.broadcast_to(y2, zero.shape), np.broadcast_to(y3, zero.shape)], axis=-1)
    return ProfileTable(piecewise_rows(breaks, accels), R.EXACT_PIECEWISE)


def setting_profile(dt: float, dy: float, y2: float, y3: float, ramp: float):
    """The paper's three-phase profile (``ramp`` 0) or its finite-jerk version with y'' ramps of time ``ramp``."""
    return ThreePhaseProfile(dt, dy, y2, y3) if ramp == 0.0 else FiniteJerkProfile(dt, dy, y2, y3, ramp=ramp)


def setting_method(dt, dy, y2, y3, ramp: float, surface, friction: FrictionLaw) -> MethodChoice:
    """:func:`~selfalign.solvers.methods.most_exact_method` of the settings (flat arrays, at least one;
    every setting is of one kind, so the first decides)."""
    return most_exact_method(setting_profile(float(dt[0]), float(dy[0]), float(y2[0]), float(y3[0]), ramp),
                             surface, friction)


def setting_table(dt, dy, y2, y3, ramp: float, choice: MethodChoice) -> ProfileTable:
    """Kernel profile table of the settings (flat arrays) for the method ``choice``: the vectorised
    :func:`three_phase_table` for the exact solver without ramps, otherwise one row per profile."""
    if ramp == 0.0 and choice.method == "exact":
        return three_phase_table(dt, dy, y2, y3)
    profiles = [setting_profile(*(float(a) for a in values), ramp) for values in zip(dt, dy, y2, y3)]
    return profile_table(profiles, choice.method, 0.0, resolve(choice.method, choice.options))
