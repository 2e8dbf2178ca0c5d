"""A design as text (:func:`design_report`): what the command line prints, the workflow logs and
the result file keeps (attribute ``report``).  Presentation only: every number is the design's
(:class:`selfalign.analysis.design.Design`), read from its fields."""

from __future__ import annotations

from ..model.design_spec import DENSE_MU


def design_report(design, *, timed: bool = True) -> str:
    """A design (:class:`selfalign.analysis.design.Design`) as text: inputs, profile, performance,
    guarantee, assumptions; ``timed``: end with the search's wall-clock time (a measurement, left
    out of result files)."""
    lines = [f"design {design.spec.name}: {design.spec.describe()}"]
    if not design.found:
        lines.append(f"NO GUARANTEED DESIGN: {design.explanation}")
    if design.verification is None:
        return "\n".join(lines)
    v = design.verification
    lines += [
        ("" if design.found else "the fastest candidate checked, NOT guaranteed: ") +
        f"profile ({_FAMILY_NAMES[design.family]}): period {1e3 * design.period:.4g} ms ({design.frequency:.4g} Hz), "
        f"stroke {1e3 * design.stroke:.4g} mm, "
        f"y2'' = {design.y2:.4g} m/s^2, y3'' = {design.y3:.4g} m/s^2, c_mu = {design.c_mu:.4g}",
        _phases(design),
        f"case {design.case} ({design.case_label}) at mu = {design.spec.mu:g}; vbar = {1e3 * design.vbar:.4g} mm/s "
        f"(slowest over the mu range {1e3 * design.vbar_min:.4g} mm/s)",
        f"process time from rest {1e3 * design.spec.distance:g} mm before the strip at t = 0: first within "
        f"{1e6 * design.spec.tolerance:g} um of x_d after {design.t_arrive:.4g} s, at rest after {design.t_rest:.4g} s "
        f"(worst over {v.mu.size} mu samples, simulated); at most {design.t_worst:.4g} s over the mu interval "
        f"(bound)",
        f"end position x_d = {1e6 * design.x_d:.4g} um past the strip's edge, error +-{1e6 * design.error:.4g} um "
        f"over every entry phase and mu in the interval (bound; +-{1e6 * float(v.sampled_error[0]):.4g} um over "
        f"the simulated entries); x_stick_min = "
        + ", ".join(f"{1e6 * x:.4g}" for x in v.x_stick_min[0]) + " um at mu = "
        + ", ".join(f"{m:.4g}" for m in v.mu),
        "Delta_x_d (eq. 39) per mu: " + ", ".join(f"{1e6 * x:.3g}" for x in v.dx_d[0]) + " um; accumulating "
        "entries: " + ", ".join(f"{100 * a:.0f} %" for a in v.frac_accumulate[0]),
        "sufficient condition of Sect. 7.3 per mu: "
        + ", ".join({1: "holds", 0: "fails", -1: "n/a"}[int(s)] for s in v.sufficient[0]),
        ("guarantee: yes, every criterion holds" if v.guaranteed[0] else f"guarantee: NO, found: {v.failure[0]}")
        + f". Criterion: every one of {design.search['entries']} steady-state entries at each of {v.mu.size} mu "
        f"in [{v.mu[0]:.4g}, {v.mu[-1]:.4g}] ends at rest" + (" by accumulation" if design.spec.accumulation else "")
        + f", within +-{1e6 * design.spec.tolerance:g} um, and the process run ends"
        + ("" if design.spec.max_process_time is None else f" within {design.spec.max_process_time:g} s")
        + "; bounds over the mu interval and every entry phase: no end below x_stick_min(mu_max) (eq. 41), "
        "the largest end and the process time with the sampling's allowance (analysis.design.end_bounds)"
        + f"; closed forms at {DENSE_MU} mu; robustness margin +-{100 * design.margin:.0f} % of mu",
        f"effects: {design.spec.effects()}; simulated with {v.method}",
        "assumes: " + "; ".join(design.assumptions),
        f"search: {design.search['designs']} designs"
        + (f", {design.search['ramps_do_not_fit']} physical ones dropped (the ramps do not fit)" if design.spec.ramp
           else "")
        + f", {design.search['screened']} pass the closed forms (the paper's model: a heuristic ranking where "
        f"effects are declared), {design.search['verified']} simulated"
        + (f", {design.search['seconds']:.2g} s" if timed else ""),
    ]
    if design.gain is not None:
        lines.append(gain_line(design.gain))
    return "\n".join(lines)


#: The families in words.
_FAMILY_NAMES = {"three_phase": "the paper's three-phase family", "optimal": "the optimal family"}


def _phases(design) -> str:
    """The pieces of the profile as text."""
    if design.motion is None:
        t = design.times
        return (f"phases: y'' = 0 on [0, {1e3 * float(t.t1):.4g}) ms, -y2'' on [.., {1e3 * float(t.t2):.4g}) ms, "
                f"+y3'' on [.., {1e3 * design.period:.4g}) ms; y_ini = {1e3 * float(t.y_ini):.4g} mm, "
                f"y'_ini = {float(t.yd_ini):.4g} m/s")
    m = design.motion
    return (f"pieces ({m.family}): " + ", ".join(f"y'' = {a:.4g} m/s^2 until {1e3 * b:.4g} ms"
                                                 for a, b in zip(m.accels, m.breaks[1:]))
            + "; the part sticks on the base at the last level of each sub-cycle")


def gain_line(gain: dict) -> str:
    """The two families compared (``Design.gain``) as one line."""
    parts = []
    for family in ("three_phase", "optimal"):
        g = gain[family]
        parts.append(f"{family}: vbar {1e3 * g['vbar']:.4g} mm/s, first arrival {g['t_arrive']:.4g} s, rest "
                     f"{g['t_rest']:.4g} s" if g["found"] else f"{family}: none guaranteed ({g['why_not']})")
    ratio = (f"; gain of the optimal family: first arrival x{gain['arrive_ratio']:.3g}, rest x{gain['rest_ratio']:.3g}"
             if gain["three_phase"]["found"] and gain["optimal"]["found"] else "")
    return "families (simulated, worst over the mu samples): " + "; ".join(parts) + ratio
