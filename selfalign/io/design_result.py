"""The result file of a design (:func:`selfalign.analysis.design.design`): ``results/design/<spec>.h5``.

Everything is in SI units (``units`` m, s, m/s, m/s^2; :mod:`selfalign.io.quantities`).
Root attributes: ``spec`` (the spec as a mapping), ``found``, ``explanation``, ``report``
(the text the command line prints, without the search's time), ``assumptions``, ``case``,
``case_label``, ``search`` (the counts of the search), ``effects`` (beyond the paper's model,
in words) and ``method`` (the solver of the guarantee).  The search's wall-clock time is the
root dataset ``design_seconds``, marked as a measurement: the only content that differs
between two runs of one spec.
The root attribute ``family`` names the chosen design's profile family ("three_phase" or "optimal").
Groups: ``profile`` and ``performance`` (scalars of the chosen design; an optimal design's
``profile`` holds its pieces, ``breaks`` and ``accels``, in place of the phase times), ``gain``
(when both families were searched: per family, in the order of its attribute ``families``,
whether a guaranteed design was found, vbar, the simulated times to first arrival and to rest,
why not (attribute ``why_not``), and the ratios three-phase / optimal), ``verification``
(per mu sample), ``front_time_error`` and ``front_time_margin`` (the trade-offs) and,
when given, ``map`` (:func:`selfalign.analysis.design.design_map`).
"""

from __future__ import annotations

from dataclasses import asdict

import numpy as np

from .design_report import design_report

#: Per-mu arrays of a Verification stored in group ``verification``.
VERIFIED = ("mu", "case", "vbar", "frac_accumulate", "frac_stop", "frac_never_stop", "frac_undecided", "dx_d",
            "x_stick_min", "end_min", "end_max", "sufficient", "t_arrive", "t_rest")
#: Arrays of a design map stored in group ``map``.
MAPPED = ("y2", "y3", "case", "physical", "moves", "holds", "screened", "sufficient", "frac_accumulate",
          "frac_stop")


def design_content(design, design_map=None) -> tuple[dict, dict, dict]:
    """(datasets, attrs, groups) for :func:`selfalign.io.hdf5.write_h5`."""
    spec = {**asdict(design.spec), "friction": design.spec.friction.params()}
    search = dict(design.search)
    seconds = search.pop("seconds")
    attrs = {"spec": spec, "found": bool(design.found), "explanation": design.explanation,
             "report": design_report(design, timed=False), "assumptions": list(design.assumptions),
             "family": design.family, "case": int(design.case),
             "case_label": design.case_label if design.case or design.motion else "", "search": search,
             "effects": design.spec.effects(),
             "method": "" if design.verification is None else design.verification.method}
    groups = {"front_time_error": {"datasets": {k: np.asarray(v) for k, v in design.front_time_error.items()}},
              "front_time_margin": {"datasets": {k: np.asarray(v) for k, v in design.front_time_margin.items()}}}
    if design.verification is not None:
        profile = {"period": design.period, "stroke": design.stroke, "y2": design.y2, "y3": design.y3,
                   "c_mu": design.c_mu}
        if design.motion is None:
            times = design.times
            profile.update({"t1": float(times.t1), "t2": float(times.t2), "t3": float(times.t3),
                            "y_ini": float(times.y_ini), "yd_ini": float(times.yd_ini)})
        else:
            profile.update({"breaks": np.asarray(design.motion.breaks), "accels": np.asarray(design.motion.accels)})
        groups["profile"] = {"datasets": profile}
        groups["performance"] = {"datasets": {
            "vbar": design.vbar, "vbar_min": design.vbar_min, "margin": design.margin, "t_arrive": design.t_arrive,
            "t_rest": design.t_rest, "t_worst": design.t_worst, "x_d": design.x_d, "error": design.error}}
        groups["verification"] = {"datasets": {k: np.asarray(getattr(design.verification, k)[0] if k != "mu"
                                                              else design.verification.mu) for k in VERIFIED}}
    gain = design.gain
    if gain is not None:
        families = ("three_phase", "optimal")
        groups["gain"] = {
            "datasets": {**{k: np.array([gain[f][k] for f in families]) for k in ("found", "vbar", "t_arrive",
                                                                                  "t_rest")},
                         "arrive_ratio": np.float64(gain["arrive_ratio"]),
                         "rest_ratio": np.float64(gain["rest_ratio"])},
            "attrs": {"families": list(families), "why_not": [gain[f]["why_not"] for f in families]}}
    if design_map is not None:
        groups["map"] = {"datasets": {k: np.asarray(getattr(design_map, k)) for k in MAPPED}}
    return {"design_seconds": np.float64(seconds)}, attrs, groups
