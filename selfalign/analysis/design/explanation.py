"""Why no design meets a spec: the constraint that empties the set of designs, and what would have to
change."""

from __future__ import annotations

import math

import numpy as np

from ...model.design_spec import DesignSpec
from .candidates import Candidates
from .screening import Screen, end_spread, slip_frequency, slip_phase
from .verification import FAILURES, Verification


def _explain(spec: DesignSpec, cand: Candidates, scr: Screen, checked: Verification | None) -> str:
    """Which constraint empties the set of designs, and what would have to change."""
    lo, hi = spec.mu_range
    amax = spec.max_acceleration
    if not scr.physical.any():
        p = spec.period[1]
        largest = p * p * amax / 16  # q <= 1 with y2'' = y3'' = amax
        return (f"no physical profile in the limits (Sect. 5.1: 8 dy (1/y2'' + 1/y3'') <= dt^2): at the longest "
                f"period {1e3 * p:.4g} ms and |y''| = {amax:g} m/s^2 the stroke must be <= {1e3 * largest:.4g} mm, "
                f"the grid's smallest is {1e3 * float(cand.stroke.min()):.4g} mm")
    c_max = spec.c_mu[1]
    if not (scr.physical & scr.moves & scr.holds).any():
        if amax <= hi * spec.g:
            return (f"the part moves forward at every mu only if y2'' > mu (1 + delta) g = {hi * spec.g:.4g} m/s^2; "
                    f"the actuator allows at most {amax:g} m/s^2")
        if c_max * lo <= hi:
            return (f"stopping needs max(y2'', y3'') <= c_mu mu (1 - delta) g = {c_max * lo * spec.g:.4g} m/s^2 and "
                    f"moving needs y2'' > mu (1 + delta) g = {hi * spec.g:.4g} m/s^2: c_mu must exceed (1 + delta)/"
                    f"(1 - delta) = {hi / lo:.4g} (or delta be below (c_mu - 1)/(c_mu + 1) = "
                    f"{(c_max - 1) / (c_max + 1):.3g})")
        return (f"no profile in the limits both moves the part forward at every mu (closed-form steady state) and "
                f"keeps max(y2'', y3'') <= c_mu mu (1 - delta) g = {c_max * lo * spec.g:.4g} m/s^2")
    base = scr.physical & scr.moves & scr.holds
    if spec.accumulation and not (base & scr.shape).any():
        return (f"accumulation needs y2'' > y3'' with y2'' > mu (1 + delta) g = {hi * spec.g:.4g} m/s^2, and no such "
                f"profile in the limits moves the part at every mu")
    if spec.accumulation and not (base & scr.shape & scr.within).any():
        need = hi * spec.g
        allowed = 2 * spec.tolerance * spec.g * (c_max - 1) / (spec.width * (1 / lo - 1 / hi))
        return (f"with accumulation the end x_stick_min (eq. 41) moves with mu by w y2''/(g (c_mu - 1)) "
                f"(1/mu_min - 1/mu_max); keeping it within +-{1e6 * spec.tolerance:g} um needs y2'' <= "
                f"{allowed:.4g} m/s^2, but moving at mu_max needs y2'' > {need:.4g} m/s^2: widen the tolerance to "
                f"{1e6 * float(end_spread(spec, cand.take(np.flatnonzero(base & scr.shape))).min()):.3g} um, narrow "
                f"the mu uncertainty or raise c_mu")
    if spec.max_process_time is not None and not (scr.ok & (scr.t_estimate <= spec.max_process_time)).any():
        return (f"the fastest design that passes the closed forms needs {float(scr.t_estimate[scr.ok].min()):.4g} s "
                f"(steady state), more than max_process_time = {spec.max_process_time:g} s")
    if checked is None:
        return "no candidate was simulated"
    counts = {why: sum(text.startswith(why) for text in checked.failure) for why in FAILURES}
    summary = "; ".join(f"{n} with {why}" for why, n in counts.items() if n)
    text = f"none of the {len(checked.failure)} best candidates passes the simulated guarantee ({summary})"
    if spec.accumulation and not checked.accumulates.any():
        suff = checked.sufficient
        phase = slip_phase(spec, cand.take(np.flatnonzero(scr.ok)))
        omega = float(slip_frequency(spec, spec.c_mu[0]))
        text += (f". Accumulation needs y2'' > y3'' and, for the sufficient condition of Sect. 7.3 "
                 f"(x_(n+1)(x_mu) < x_stick_min, eq. 59), cos(omega (t2 - t1)) > (y2'' - mu g) / (2 (y2'' + y3'')) > 0 "
                 f"with omega = sqrt((c_mu - 1) mu g / w) = {omega:.4g} rad/s at mu_max: omega (t2 - t1) < pi/2; "
                 f"{int((phase < 0.5 * math.pi).sum())} of the {phase.size} designs that move and stop have it "
                 f"(smallest omega (t2 - t1) = {float(phase.min()):.3g} rad) and the condition held at "
                 f"{int((suff == 1).sum())} of {suff.size} simulated (candidate, mu) pairs: a shorter slip window "
                 f"(a smaller stroke or a higher frequency), a lower c_mu, or no accumulation requirement")
    return text
