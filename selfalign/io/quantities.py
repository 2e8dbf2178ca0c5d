"""Units and meaning of every dataset in a result file (docs/reference/results.md).

:func:`selfalign.io.hdf5.write_h5` looks every dataset up here and stores
``units`` and ``description`` as its attributes (and ``legend`` for a coded
one); it refuses a dataset it does not find, so that no quantity reaches a
result file undocumented.  A dataset is found by ``"<group>/<name>"`` (its
parent group's name; ``*`` matches any text, as in ``entry_*/t``) and
otherwise by its name alone.

Units.  The model is dimensionless (Sect. 3.2): lengths are in units of a
characteristic length L and times in units of T = sqrt(L / (mu g)), so the
``units`` of a physical quantity name its dimension in L and T and say that
they are model units, e.g. ``"L/T (dimensionless model units, Sect. 3.2)"``.
Pure numbers read ``"1 (dimensionless)"``, counts ``"1 (count)"``, coded
values ``"1 (code; see legend)"``.  When the file was made from a scene
with an SI scale (:class:`selfalign.model.units.SIScale`), a dataset of one
physical dimension also gets ``si_units`` (e.g. ``"m/s"``) and ``si_factor``,
the SI value of one model unit (stored value x si_factor = SI value).

Measurements.  A result holds what follows from its inputs, which two runs reproduce bit for
bit, and at most a few measured values (CPU and wall-clock times and what is derived from
them), which differ between runs and machines.  A measured value is always a dataset of a
:class:`Quantity` with ``measurement=True``, never an attribute: its dataset gets the attribute
``measurement = True`` and its description ends with :data:`MEASUREMENT_NOTE`.  So two writes
of one result are byte-identical once the data of the marked datasets are set aside
(:func:`selfalign.io.hdf5.reproducible_bytes`).
"""

from __future__ import annotations

import fnmatch
from collections.abc import Mapping
from dataclasses import dataclass

from ..model.profiles import CASE_LABELS, RAMPS_TOO_LONG
from ..model.units import SIScale
from ..solvers.outcomes import MODE_NAMES, STATUS_CODES, EventKind, Reason

#: Exponents of L and T of each physical kind; V = (v1 - v2)^2 / 2 is an energy per unit mass.
DIMENSIONS = {"length": (1, 0), "time": (0, 1), "velocity": (1, -1), "acceleration": (1, -2),
              "energy": (2, -2), "power": (2, -3)}
_MODEL = " (dimensionless model units, Sect. 3.2)"
#: ``units`` of the kinds that are no single physical dimension.
LABELS = {
    "number": "1 (dimensionless)",
    "count": "1 (count)",
    "code": "1 (code; see legend)",
    "boolean": "1 (boolean)",
    "text": "text",
    "cpu_time": "s (CPU time)",
    "wall_time": "s (wall-clock time)",
    "cpu_rate": "1/s (per second of CPU time)",
    "friction": "1 (dimensionless: in units of the maximum friction force mu m g)",
    "state": "L for x, L/T for x'" + _MODEL,
    "monodromy": "[[1, T], [1/T, 1]] for (x, x')" + _MODEL,
    "si_length": "m (SI)",
    "si_time": "s (SI)",
    "si_velocity": "m/s (SI)",
    "si_acceleration": "m/s^2 (SI)",
    "si_rate": "1/s (SI)",
}

MODE_LEGEND = dict(MODE_NAMES)
EVENT_LEGEND = {int(k): k.name for k in EventKind}
STATUS_LEGEND = {code: status.value for status, code in STATUS_CODES.items()}
REASON_LEGEND = {int(r): r.name.lower() for r in Reason}
CASE_LEGEND = dict(CASE_LABELS)
#: Kinds that only a measurement has.
MEASURED_KINDS = ("cpu_time", "wall_time", "cpu_rate")
#: Dataset attribute that marks a measured value, and the sentence its description ends with.
MEASUREMENT_ATTR = "measurement"
MEASUREMENT_NOTE = ("A measured value: it differs between runs and machines (everything else in the file is "
                    "reproduced bit for bit).")


@dataclass(frozen=True)
class Quantity:
    """One dataset's kind (a key of DIMENSIONS or LABELS), meaning, for codes its legend, and
    whether it is a measured value (module docstring; the :data:`MEASURED_KINDS` always are)."""

    kind: str
    description: str
    legend: Mapping[int, str] | None = None
    measurement: bool = False

    def __post_init__(self):
        if self.kind not in DIMENSIONS and self.kind not in LABELS:
            raise ValueError(f"unknown quantity kind {self.kind!r}; allowed: {sorted({**DIMENSIONS, **LABELS})}")
        if (self.kind == "code") != (self.legend is not None):
            raise ValueError(f"{self.description!r}: a legend goes with kind 'code' and only with it")
        if self.kind in MEASURED_KINDS and not self.measurement:
            raise ValueError(f"{self.description!r}: kind {self.kind!r} is measured: pass measurement=True")

    def attrs(self, si: SIScale | None = None) -> dict:
        """The dataset attributes: ``units``, ``description``, ``legend``, ``measurement`` (only
        on a measured value) and, with ``si``, the SI unit."""
        description = f"{self.description}. {MEASUREMENT_NOTE}" if self.measurement else self.description
        out = {"units": _symbol(self.kind, "L", "T") + _MODEL if self.kind in DIMENSIONS else LABELS[self.kind],
               "description": description}
        if self.legend is not None:
            out["legend"] = {str(code): name for code, name in self.legend.items()}
        if self.measurement:
            out[MEASUREMENT_ATTR] = True
        if si is not None and self.kind in DIMENSIONS:
            length, time = DIMENSIONS[self.kind]
            out["si_units"] = _symbol(self.kind, "m", "s")
            out["si_factor"] = si.L**length * si.T**time
        return out


def _symbol(kind: str, length: str, time: str) -> str:
    """e.g. ``L/T^2`` for an acceleration."""
    powers = dict(zip((length, time), DIMENSIONS[kind]))
    up = [f"{s}^{p}" if p > 1 else s for s, p in powers.items() if p > 0]
    down = [f"{s}^{-p}" if p < -1 else s for s, p in powers.items() if p < 0]
    return " ".join(up or ["1"]) + "".join(f"/{d}" for d in down)


def _table_motion(prefix: str, what: str) -> dict[str, Quantity]:
    return {f"{prefix}y": Quantity("length", f"table position y of {what}"),
            f"{prefix}yd": Quantity("velocity", f"table velocity y' of {what}"),
            f"{prefix}ydd": Quantity("acceleration", f"table acceleration y'' of {what}")}


def _steady_motion(prefix: str, what: str) -> dict[str, Quantity]:
    return {f"{prefix}_motion_t": Quantity("time", f"time t of three steady periods from x(0) = 0, {what}"),
            f"{prefix}_motion_v": Quantity("velocity", f"relative velocity x', {what}"),
            f"{prefix}_motion_y": Quantity("length", f"table position y, {what}"),
            f"{prefix}_motion_x_abs": Quantity("length", f"absolute mass position x + y, {what}")}


def _per_run(group: str) -> dict[str, Quantity]:
    """The per-run datasets of the accuracy study, the same in groups moreau and ivp."""
    return {
        f"{group}/cpu_time": Quantity("cpu_time", "CPU time of one simulate call per run (fastest of the repeats)",
                                      measurement=True),
        f"{group}/err_end_position": Quantity("length", "|x(N) - x_ref(N)| per run (several parts: the largest "
                                                         "over the parts)"),
        f"{group}/err_vbar": Quantity("velocity", "|vbar - vbar_ref| per run, vbar = (x(N) - x(N-1)) / dt (several "
                                                 "parts: the largest over the parts)"),
        f"{group}/x_end": Quantity("length", "end position x(N) per run (several parts: per run and part)"),
        f"{group}/vbar": Quantity("velocity", "vbar = (x(N) - x(N-1)) / dt per run (several parts: per run and part)"),
        f"{group}/steps": Quantity("count", "the solver's steps per run"),
        f"{group}/events": Quantity("count", "the solver's events per run"),
        f"{group}/status": Quantity("text", "the run's status (horizon, rest, accumulation, never_stops, error)"),
        f"{group}/fast_forward_periods": Quantity("count", "periods the driver fast-forwarded per run"),
    }


def _method_pair(suffix: str, kind: str, description: str) -> dict[str, Quantity]:
    """A polynomial-sweep quantity computed by the exact solver and by Moreau (Figs. 4, 5)."""
    return {f"{suffix}_{method}": Quantity(kind, f"{description}, {solver}")
            for method, solver in (("exact", "exact solver"), ("moreau", "Moreau time-stepping"))}


_SWEEP = {**_method_pair("vbar", "velocity", "steady average velocity vbar (eq. 10)"),
          **_method_pair("f", "number", "objective f = 1 / (c vbar^2), c = 1e4 (eq. 11)"),
          **_method_pair("residual", "velocity", "change of x'(0) over the steady period"),
          **_method_pair("periods", "count", "periods simulated to reach the steady state")}

#: Every dataset a selfalign result file may hold: "<group>/<name>" or "<name>" -> Quantity.
QUANTITIES: dict[str, Quantity] = {
    # time and table motion (trajectory, convergence, fig06, series)
    "t": Quantity("time", "time t of each sample"),
    **_table_motion("", "each sample"),
    "switch_times": Quantity("time", "times within [0, dt) at which y'' jumps"),
    # axes and settings
    "y2": Quantity("acceleration", "the axis y2'' (table acceleration of the second phase)"),
    "y3": Quantity("acceleration", "the axis y3'' (table acceleration of the third phase)"),
    "dt": Quantity("time", "period dt of the table motion (swept or fixed)"),
    "dy": Quantity("length", "stroke dy of the table motion (swept or fixed)"),
    "case": Quantity("code", "case of Table 1 (0: no physical profile)", CASE_LEGEND),
    "vbar": Quantity("velocity", "steady average velocity vbar (eq. 10), NaN in case 0"),
    "f": Quantity("number", "objective f = 1 / (c vbar^2), c = 1e4 (eq. 11; inf in pure stick), NaN in case 0"),
    "vbar_simulated": Quantity("velocity", "vbar from the batched exact solver, from x'(0) = 0"),
    **_SWEEP,
    # simulation result (selfalign.io.simulation_result)
    "series/t": Quantity("time", "time t of each recorded sample (samples_per_period per period plus every event)"),
    "series/x": Quantity("length", "relative position x of the mass"),
    "series/v": Quantity("velocity", "relative velocity x' of the mass"),
    **_table_motion("series/", "each recorded sample"),
    "series/friction": Quantity("friction", "friction force F_f (eq. 5)"),
    "series/mode": Quantity("code", "mode of the motion", MODE_LEGEND),
    "events/kind": Quantity("code", "kind of each event", EVENT_LEGEND),
    "events/period": Quantity("count", "period n of each event"),
    "events/tau": Quantity("time", "time tau within the period of each event"),
    "events/t": Quantity("time", "time t = n dt + tau of each event"),
    "events/x": Quantity("length", "relative position x at each event"),
    "events/v": Quantity("velocity", "relative velocity x' at each event"),
    "events/mode_before": Quantity("code", "mode before each event", MODE_LEGEND),
    "events/mode": Quantity("code", "mode after each event", MODE_LEGEND),
    "events/acc_before": Quantity("acceleration", "relative acceleration x'' just before each event"),
    "events/acc_after": Quantity("acceleration", "relative acceleration x'' just after each event"),
    "stats/cpu_time": Quantity("cpu_time", "CPU time of the simulate call", measurement=True),
    "info/part_sticks": Quantity("count", "stick events of each part (several parts, rear-most first)"),
    "info/part_slips": Quantity("count", "slip starts of each part (several parts, rear-most first)"),
    "info/part_impacts": Quantity("count", "contact closings each part took part in (rear-most first)"),
    "info/part_openings": Quantity("count", "contact openings each part took part in (rear-most first)"),
    "info/part_crossings": Quantity("count", "crossings of each part's transition boundaries, x_mu and "
                                             "x_mu + w (rear-most first)"),
    "info/part_held": Quantity("boolean", "each part sticks for good at the end: its cluster is at rest and no "
                                          "table acceleration of the profile moves it (rear-most first)"),
    # accuracy study (selfalign.analysis.accuracy)
    "moreau/h": Quantity("time", "Moreau step h = dt / n of each run"),
    "moreau/steps_per_period": Quantity("count", "Moreau steps per period n of each run"),
    "ivp/rtol": Quantity("number", "relative tolerance of each solve_ivp run"),
    "ivp/atol": Quantity("state", "absolute tolerance of each solve_ivp run"),
    **_per_run("moreau"),
    **_per_run("ivp"),
    "exact/cpu_time": Quantity("cpu_time", "CPU time of one simulate call of the reference (fastest of the repeats)",
                               measurement=True),
    "exact/events_run_cpu_time": Quantity("cpu_time", "CPU time of one simulate call of the reference with the "
                                                      "event log on (no fast-forward; fastest of the repeats)",
                                          measurement=True),
    "moreau_cpu_at_target": Quantity("cpu_time", "CPU time at which Moreau reaches the target error (interpolated "
                                                 "on the log-log curve of CPU time against h)", measurement=True),
    "speed_ratio_at_target": Quantity("number", "moreau_cpu_at_target over the reference's CPU time",
                                      measurement=True),
    "exact_events_per_second": Quantity("cpu_rate", "events per CPU second of the reference with the event log on",
                                        measurement=True),
    # stability (selfalign.stages.stability)
    "methods": Quantity("text", "the methods, the reference first: analytic, saltation, numeric_exact, "
                                "numeric_moreau"),
    "monodromy": Quantity("monodromy", "per method: monodromy matrix M (2 x 2) of (x, x') over the periodic motion"),
    "multipliers": Quantity("number", "per method: Floquet multipliers, eigenvalues of M by decreasing modulus"),
    "monodromy_error": Quantity("monodromy", "per method: largest absolute difference of M from the reference"),
    "multiplier_error": Quantity("number", "per method: largest absolute multiplier difference from the reference"),
    "moreau_steps": Quantity("count", "Moreau scan: steps per period N (h = dt / N)"),
    "moreau_eps": Quantity("state", "Moreau scan: finite-difference step eps in x and x'"),
    "moreau_monodromy": Quantity("monodromy", "Moreau scan: M per steps x eps"),
    "moreau_multipliers": Quantity("number", "Moreau scan: multipliers per steps x eps"),
    "moreau_multiplier_error": Quantity("number", "Moreau scan: multiplier error from the reference per steps x eps"),
    # convergence (selfalign.stages.convergence)
    "v1": Quantity("velocity", "relative velocity x' of trajectory 1"),
    "v2": Quantity("velocity", "relative velocity x' of trajectory 2"),
    "V": Quantity("energy", "V = (v1 - v2)^2 / 2 (eq. 35)"),
    "dV": Quantity("power", "V'(t+)"),
    "interval_start": Quantity("time", "start of each interval of Fig. 13"),
    "interval_end": Quantity("time", "end of each interval of Fig. 13"),
    "interval_equal": Quantity("boolean", "true for a '=' interval (v1 = v2), false for a '!=' one"),
    "period_t": Quantity("time", "period boundaries"),
    "period_V": Quantity("energy", "V at the period boundaries"),
    # Fourier optimisation, Fig. 6 (selfalign.stages.classification.fig06_results)
    **_table_motion("fourier_", "the optimal Fourier profile over one period (shifted to zero mean)"),
    **_table_motion("start_", "the SQP start profile over one period (shifted to zero mean)"),
    **_table_motion("three_phase_", "the best three-phase profile over one period (shifted to zero mean)"),
    **_steady_motion("fourier", "optimal Fourier profile"),
    **_steady_motion("three_phase", "best three-phase profile"),
    "history_f": Quantity("number", "f at the start and after every SQP iteration"),
    "cos_coeffs": Quantity("length", "cosine coefficients a_k of the optimum (time-shifted)"),
    "sin_coeffs": Quantity("length", "sine coefficients b_k of the optimum (time-shifted)"),
    "start_cos_coeffs": Quantity("length", "cosine coefficients a_k of the SQP start"),
    "start_sin_coeffs": Quantity("length", "sine coefficients b_k of the SQP start"),
    # positioning, Fig. 17 (selfalign.stages.accumulation)
    "dx_d": Quantity("length", "dx_d (eq. 39) over the entries that stop; NaN where none stops"),
    "frac_accumulate": Quantity("number", "fraction of the entries that accumulate"),
    "frac_stop": Quantity("number", "fraction of the entries that come to rest"),
    "frac_never_stop": Quantity("number", "fraction of the entries that never stop"),
    "frac_undecided": Quantity("number", "fraction of the entries that stay undecided"),
    "x_stick_min": Quantity("length", "x_stick_min (eq. 41), relative to x_mu"),
    "overshoot_min": Quantity("length", "smallest overshoot of the entries that stop, relative to x_mu"),
    "overshoot_max": Quantity("length", "largest overshoot of the entries that stop, relative to x_mu"),
    "contraction": Quantity("number", "median ratio of the last two stick increments of the accumulating entries"),
    "levels": Quantity("number", "the levels p"),
    "level_from_first_stick": Quantity("count", "worst-case periods from the first stick in the zone until "
                                                "x >= x_mu + p (x_stick_min - x_mu)"),
    "level_from_entry": Quantity("count", "worst-case periods from the entry until x >= x_mu + p (x_stick_min - x_mu)"),
    "level_sticks": Quantity("count", "worst-case zone stick events before x >= x_mu + p (x_stick_min - x_mu)"),
    # portraits, Figs. 14-16 (one group per setting)
    "s": Quantity("length", "per entry: offset s_j"),
    "x0": Quantity("length", "per entry: start position x0 = -s_j"),
    "status": Quantity("code", "per entry: status", STATUS_LEGEND),
    "reason": Quantity("code", "per entry: reason behind the status (selfalign.solvers.outcomes.Reason)",
                       REASON_LEGEND),
    "x_end": Quantity("length", "per entry: end position (the limit for an accumulation)"),
    "overshoot": Quantity("length", "per entry: x_end - x_mu (NaN unless it stops)"),
    "first_stick_x": Quantity("length", "per entry: first stick position at x >= x_mu"),
    "entry_*/t": Quantity("time", "time t of the entry's dense trajectory (400 samples per period plus every event)"),
    "entry_*/x": Quantity("length", "relative position x of the entry"),
    "entry_*/v": Quantity("velocity", "relative velocity x' of the entry"),
    "entry_*/stick_x": Quantity("length", "positions of all the entry's STICK events, in order"),
    # stick map, Fig. 18
    "x_n": Quantity("length", "stick positions x_n on [x_mu, x_mu + w]"),
    "x_next_formula": Quantity("length", "x_{n+1} by eq. (59)"),
    "x_next_simulated": Quantity("length", "x_{n+1} by the exact solver"),
    "valid": Quantity("boolean", "where the assumptions of eq. (59) hold"),
    "cobweb_accumulate": Quantity("length", "start and stick positions of a run started stuck just above x_c"),
    "cobweb_rest": Quantity("length", "start and stick positions of a run started stuck just below x_c"),
    # static/kinetic friction, results/effects/static_friction.h5 (selfalign.stages.effects)
    "maps/ratio": Quantity("number", "r = mu_s / mu_k of each map (1: the paper's Coulomb friction)"),
    "maps/frac_accumulate": Quantity("number", "[r, y2, y3]: fraction of the entries that accumulate"),
    "maps/frac_never_stop": Quantity("number", "[r, y2, y3]: fraction of the entries that never stop"),
    "maps/frac_undecided": Quantity("number", "[r, y2, y3]: fraction of the entries that stay undecided"),
    "maps/dx_d": Quantity("length", "[r, y2, y3]: dx_d (eq. 39) over the entries that stop; NaN where none stops"),
    "sweep/ratio": Quantity("number", "r = mu_s / mu_k of each sweep column (the first: 1, Coulomb)"),
    "sweep/y2": Quantity("acceleration", "y2'' of each sweep setting"),
    "sweep/y3": Quantity("acceleration", "y3'' of each sweep setting"),
    "sweep/dx_d": Quantity("length", "[setting, r]: dx_d (eq. 39) over the entries that stop"),
    "sweep/frac_accumulate": Quantity("number", "[setting, r]: fraction of the entries that accumulate"),
    # Stribeck friction, results/effects/stribeck.h5 (selfalign.stages.effects): [setting, v_s]
    "v_s_fraction": Quantity("number", "Stribeck velocity v_s in units of each profile's velocity swing"),
    "stribeck_*/y2": Quantity("acceleration", "y2'' of each setting"),
    "stribeck_*/y3": Quantity("acceleration", "y3'' of each setting"),
    "stribeck_*/velocity_swing": Quantity("velocity", "max y' - min y' of each setting (the unit of v_s)"),
    "stribeck_steady/vbar": Quantity("velocity", "[setting, v_s]: steady average velocity vbar (eq. 10), Moreau"),
    "stribeck_steady/vbar_static_kinetic": Quantity("velocity", "vbar under static/kinetic friction (the limit "
                                                                "v_s -> 0), exact solver"),
    "stribeck_steady/vbar_coulomb": Quantity("velocity", "vbar under the paper's Coulomb friction, exact solver"),
    "stribeck_stopping/frac_accumulate": Quantity("number", "[setting, v_s]: fraction of the entries that "
                                                            "accumulate, Moreau"),
    "stribeck_stopping/frac_rest": Quantity("number", "[setting, v_s]: fraction of the entries that come to rest, "
                                                      "Moreau"),
    "stribeck_stopping/dx_d": Quantity("length", "[setting, v_s]: dx_d (eq. 39) over the entries that stop, Moreau"),
    "stribeck_stopping/frac_accumulate_*": Quantity("number", "fraction of the entries that accumulate under "
                                                              "static/kinetic or Coulomb friction, exact solver"),
    "stribeck_stopping/dx_d_*": Quantity("length", "dx_d (eq. 39) under static/kinetic or Coulomb friction, exact "
                                                   "solver"),
    # finite jerk (selfalign.stages.finite_jerk): grids of shape (ramp fractions, y2'', y3'')
    "ramp_fractions": Quantity("number", "ramp time of y'' at each switch as a fraction of dt (0: the paper's "
                                         "profile)"),
    "steady_*/case": Quantity("code", "case of Table 1 of the steady state, exact solver (0: no physical profile)",
                              {**CASE_LEGEND, RAMPS_TOO_LONG: "ramps longer than their phases"}),
    "steady_*/vbar": Quantity("velocity", "steady average velocity vbar (eq. 10), exact solver; NaN without a "
                                          "profile"),
    "stopping/frac_accumulate": Quantity("number", "fraction of the steady-state entries into the stop zone that "
                                                   "accumulate; NaN where the mass does not move forward"),
    "stopping/frac_rest": Quantity("number", "fraction of the steady-state entries into the stop zone that come to "
                                             "rest; NaN where the mass does not move forward"),
    "stopping/dx_d": Quantity("length", "dx_d (eq. 39) over the entries that stop; NaN where none stops"),
    # Fig. 6 revisited, results/optimal_motion/fig06_revisited.h5 (selfalign.stages.optimal_motion)
    "comparison/entry": Quantity("text", "the answers at Fig. 6's limits: paper (its caption's f), three_phase (best "
                                         "of Sect. 4.4.3), fourier_<N> (SQP of order N), optimal (optimal_profile), "
                                         "bound (v* of the acceleration limit alone)"),
    "comparison/vbar": Quantity("velocity", "per entry: steady average velocity vbar (eq. 10), exact solver from rest; "
                                            "the paper's from its f, the bound's v*"),
    "comparison/f": Quantity("number", "per entry: objective f = 1 / (c vbar^2), c = 1e4 (eq. 11)"),
    "comparison/peak_acceleration": Quantity("acceleration", "per entry: max |y''| of the table motion (NaN: not "
                                                             "known)"),
    "comparison/peak_velocity": Quantity("velocity", "per entry: max |y'| of the table motion, y' of zero mean (NaN: "
                                                     "not known)"),
    "comparison/stroke": Quantity("length", "per entry: stroke max y - min y of the table motion (NaN: not known)"),
    "comparison/binding": Quantity("text", "per entry: the limits the motion uses within 0.1 %, comma-separated"),
    "comparison/forward_slides": Quantity("count", "per entry: forward slides (runs of x' > 0) in a steady period "
                                                   "(NaN: not known)"),
    "comparison/backward_slides": Quantity("count", "per entry: backward slides (runs of x' < 0) in a steady period "
                                                    "(NaN: not known)"),
    "comparison/backward_loss": Quantity("number", "per entry: int max(-x', 0) dt over int max(x', 0) dt in a steady "
                                                   "period, the share of the advance backward slides take back"),
    "comparison/share_of_optimum": Quantity("number", "per entry: vbar over the optimum's vbar"),
    "truncation/orders": Quantity("count", "harmonics N kept of the optimum at Fig. 6's limits"),
    "truncation/scale": Quantity("number", "factor the N-harmonic truncation is scaled by to meet the limits"),
    "truncation/vbar": Quantity("velocity", "vbar (eq. 10) of the scaled truncation, exact solver from rest"),
    "accel_sweep/accel_max": Quantity("acceleration", "the axis: acceleration limit a = max |y''|"),
    "stroke_sweep/stroke_max": Quantity("length", "the axis: stroke limit S = max y - min y"),
    "*_sweep/orders": Quantity("count", "Fourier orders N of the rows of vbar_truncated and vbar_fourier"),
    "*_sweep/vbar_optimal": Quantity("velocity", "vbar (eq. 10) of the fastest motion found (optimal_profile)"),
    "*_sweep/vbar_bound": Quantity("velocity", "v*, the proven bound of the acceleration limit alone"),
    "*_sweep/vbar_three_phase": Quantity("velocity", "vbar (closed form) of the best three-phase profile meeting the "
                                                     "limits, its stroke searched"),
    "*_sweep/three_phase_stroke": Quantity("length", "stroke dy of that three-phase profile"),
    "*_sweep/vbar_truncated": Quantity("velocity", "[order, point]: vbar of the fastest motion truncated to N "
                                                   "harmonics and scaled into the limits, exact solver"),
    "*_sweep/vbar_fourier": Quantity("velocity", "[order, point]: vbar of the Fourier SQP optimum of order N (NaN "
                                                 "where the SQP was not run)"),
}

#: Axes and profile of a design (results/design/<spec>.h5), in SI.
_DESIGN_PROFILE = {
    "period": Quantity("si_time", "period of the table motion"),
    "stroke": Quantity("si_length", "stroke of the table motion"),
    "y2": Quantity("si_acceleration", "magnitude of the table deceleration y2'' of the second phase"),
    "y3": Quantity("si_acceleration", "table acceleration y3'' of the third phase"),
    "c_mu": Quantity("number", "friction ratio c_mu of the strip"),
}
_MAP_CODES = {"physical": "a physical profile (q <= 1, Sect. 5.1)",
              "moves": "the part moves forward at every mu of the range (closed form)",
              "holds": "the strip can hold the part at every mu (max(y2'', y3'') <= c_mu mu_min g, eq. 41)",
              "screened": "every closed-form condition of the design search holds"}
QUANTITIES.update({
    "design_seconds": Quantity("wall_time", "wall-clock time of the design search (screening, simulation of the "
                                            "candidates, trade-offs)", measurement=True),
    **{f"profile/{k}": q for k, q in _DESIGN_PROFILE.items()},
    **{f"front_time_*/{k}": q for k, q in _DESIGN_PROFILE.items()},
    "profile/t1": Quantity("si_time", "end of the zero-acceleration phase (start of -y2'')"),
    "profile/t2": Quantity("si_time", "end of the -y2'' phase (start of +y3'')"),
    "profile/t3": Quantity("si_time", "end of the period"),
    "profile/y_ini": Quantity("si_length", "table position at t = 0 (its minimum is 0)"),
    "profile/yd_ini": Quantity("si_velocity", "table velocity at t = 0"),
    "profile/breaks": Quantity("si_time", "optimal family: the times at which y'' changes, from 0 to the period"),
    "profile/accels": Quantity("si_acceleration", "optimal family: the table acceleration y'' on each piece"),
    "gain/found": Quantity("boolean", "[three_phase, optimal]: a guaranteed design of the family exists"),
    "gain/vbar": Quantity("si_velocity", "[three_phase, optimal]: vbar (eq. 10) of the family's design at the "
                                         "nominal mu"),
    "gain/t_arrive": Quantity("si_time", "[three_phase, optimal]: worst simulated time until within the tolerance "
                                         "of x_d (NaN: no guaranteed design)"),
    "gain/t_rest": Quantity("si_time", "[three_phase, optimal]: worst simulated time until rest or accumulation "
                                       "(NaN: no guaranteed design)"),
    "gain/arrive_ratio": Quantity("number", "t_arrive of the three-phase design over that of the optimal one"),
    "gain/rest_ratio": Quantity("number", "t_rest of the three-phase design over that of the optimal one"),
    "performance/vbar": Quantity("si_velocity", "steady average velocity vbar (eq. 10) at the nominal mu"),
    "performance/vbar_min": Quantity("si_velocity", "slowest vbar over the mu range (closed form)"),
    "performance/margin": Quantity("number", "robustness margin: relative mu deviation the closed forms allow"),
    "performance/t_arrive": Quantity("si_time", "worst simulated time from the start until within the tolerance of "
                                                "x_d"),
    "performance/t_rest": Quantity("si_time", "worst simulated time from the start until rest or accumulation"),
    "performance/x_d": Quantity("si_length", "end position x_d past the strip's edge (middle of the end band)"),
    "performance/error": Quantity("si_length", "half-width of the bound on the end positions over the mu interval "
                                               "and every entry phase"),
    "performance/t_worst": Quantity("si_time", "bound on the time until within the tolerance of x_d over the mu "
                                               "interval"),
    "verification/mu": Quantity("number", "the mu samples"),
    "verification/case": Quantity("code", "case of Table 1 at each mu", CASE_LEGEND),
    "verification/vbar": Quantity("si_velocity", "steady average velocity vbar at each mu"),
    "verification/frac_*": Quantity("number", "fraction of the entries with that outcome at each mu"),
    "verification/dx_d": Quantity("si_length", "Delta_x_d (eq. 39) at each mu"),
    "verification/x_stick_min": Quantity("si_length", "x_stick_min (eq. 41) past the strip's edge at each mu"),
    "verification/end_min": Quantity("si_length", "smallest end position past the strip's edge at each mu"),
    "verification/end_max": Quantity("si_length", "largest end position past the strip's edge at each mu"),
    "verification/sufficient": Quantity("code", "sufficient condition of Sect. 7.3 at each mu",
                                        {1: "holds", 0: "fails", -1: "eq. 59 does not apply"}),
    "verification/t_arrive": Quantity("si_time", "simulated time until within the tolerance of x_d at each mu"),
    "verification/t_rest": Quantity("si_time", "simulated time until rest or accumulation at each mu"),
    "front_time_*/t_estimate": Quantity("si_time", "closed-form process time (D + x_stick_min(mu_max) - tolerance) "
                                                   "/ vbar_min"),
    "front_time_error/spread": Quantity("si_length", "half the range of x_stick_min (eq. 41) over the mu range"),
    "front_time_error/t_arrive": Quantity("si_time", "simulated worst time until within the tolerance of x_d (NaN: "
                                                     "not simulated)"),
    "front_time_error/error": Quantity("si_length", "simulated robust positioning error (NaN: not simulated)"),
    "front_time_error/guaranteed": Quantity("boolean", "the engine certifies the design"),
    "front_time_margin/margin": Quantity("number", "robustness margin: relative mu deviation the closed forms allow"),
    "map/y2": Quantity("si_acceleration", "the axis y2''"),
    "map/y3": Quantity("si_acceleration", "the axis y3''"),
    "map/case": Quantity("code", "case of Table 1 at the nominal mu", CASE_LEGEND),
    **{f"map/{k}": Quantity("boolean", text) for k, text in _MAP_CODES.items()},
    "map/sufficient": Quantity("code", "sufficient condition of Sect. 7.3 at the nominal mu",
                               {1: "holds", 0: "fails", -1: "eq. 59 does not apply"}),
    "map/frac_accumulate": Quantity("number", "fraction of the entries that accumulate at the nominal mu"),
    "map/frac_stop": Quantity("number", "fraction of the entries that come to rest at the nominal mu"),
})


_QUEUE_STATUS = {0: "rest", 1: "settled", 2: "horizon", 3: "error"}
#: The queue study of several parts at the stop zone (selfalign.analysis.queue, docs/explanation/queue.md).
QUANTITIES.update({
    "queue/x_single": Quantity("length", "rest position of one part from the front part's start (simulated)"),
    "queue/tolerance": Quantity("length", "the front part counts as at the single-part position within this"),
    "queue/x_mu": Quantity("length", "start x_mu of the stop zone"),
    "queue/spacing": Quantity("length", "the axis: gap between neighbouring parts at t = 0"),
    "queue/restitution": Quantity("number", "the axis: Newton's coefficient of restitution e"),
    "queue/spread": Quantity("number", "the axis: half range of the friction factors k_i"),
    "queue/n": Quantity("count", "the axis: number of parts N"),
    "queue/x_end": Quantity("length", "end front position of each part, the front-most first (NaN beyond N)"),
    "queue/error": Quantity("length", "end front position minus the single-part rest position, the front-most "
                                      "first"),
    "queue/pooled": Quantity("length", "front position of each part at the pooled rest of the touching cluster "
                                       "(mass-weighted mean of k_i mu_bar_i = max|y''|), the front-most first"),
    "queue/friction_factor": Quantity("number", "friction factor k_i of each part, the front-most first"),
    "queue/status": Quantity("code", "how the queue's run ended", _QUEUE_STATUS),
    "queue/t_end": Quantity("time", "time of rest (or settling, or the horizon) of the queue"),
    "queue/periods": Quantity("count", "periods simulated"),
    "queue/events": Quantity("count", "events of the exact solver"),
    "queue/front_at_single": Quantity("boolean", "the front part ends at the single-part rest position (within "
                                                 "the tolerance)"),
    "queue/in_zone": Quantity("count", "parts whose front ends past x_mu"),
    "queue/front_through": Quantity("boolean", "the front part ends past x_mu + w, or the queue does not come "
                                               "to rest"),
    "queue_motion/t": Quantity("time", "period ends of the recorded queue"),
    "queue_motion/x": Quantity("length", "front position of each part at the period ends, the rear-most first"),
    "queue_motion/width": Quantity("length", "width of each part"),
    "queue_motion/events": Quantity("count", "events of each part in each period, shape (periods, parts, kinds), "
                                             "the kinds in the attribute event_kinds"),
    "design_queue/n": Quantity("count", "the axis: number of parts N"),
    "design_queue/x_end": Quantity("si_length", "end front position of each part past the strip's edge, the "
                                                "front-most first (NaN beyond N)"),
    "design_queue/error": Quantity("si_length", "end front position minus the single part's, the front-most "
                                                "first"),
    "design_queue/t_aligned": Quantity("si_time", "time from the start after which each part stays within the "
                                                  "spec's tolerance of its end position, the front-most first"),
    "design_queue/throughput": Quantity("si_rate", "parts aligned per second: N over the last part's t_aligned"),
    "design_queue/status": Quantity("code", "how the queue's run ended", _QUEUE_STATUS),
    "design_queue/x_single": Quantity("si_length", "rest position of one part past the strip's edge (simulated)"),
    "design_queue/x_stick_min": Quantity("si_length", "x_stick_min (eq. 41) past the strip's edge"),
    "design_queue/width": Quantity("si_length", "width of each part (the spec's)"),
    "design_queue/spacing": Quantity("si_length", "gap between neighbouring parts at t = 0"),
    "design_queue/tolerance": Quantity("si_length", "the spec's positioning tolerance"),
})


#: The planar study (selfalign.analysis.planar_drift, selfalign.analysis.planar_alignment,
#: docs/explanation/planar-alignment.md): vectors in the plane are stored with a last axis (x, y).
_CORNER_FIRST = {0: "the first strip (normal turned by +half_angle)", 1: "the second strip (-half_angle)"}
QUANTITIES.update({
    "drift_*/offset": Quantity("number", "the axis: phase offset (lag) of the y motion in periods"),
    "drift_*/amplitude": Quantity("number", "the axis: amplitude of the y motion over that of the x motion"),
    "drift_*/v_bar": Quantity("velocity", "steady mean velocity vector v_bar (x, y) (eq. 10 in the plane)"),
    "drift_*/speed": Quantity("velocity", "|v_bar|"),
    "drift_*/direction": Quantity("number", "angle of v_bar from the x axis [rad]"),
    "drift_*/periods": Quantity("count", "periods from rest until the period-boundary velocity repeats"),
    "drift_*/converged": Quantity("boolean", "the period-boundary velocity repeated within the tolerance"),
    "drift_*/max_acceleration": Quantity("acceleration", "max|Y''| of the table motion"),
    "symmetric/orbit": Quantity("text", "the orbit (Y(t + dt/2) = -Y(t))"),
    "symmetric/v_bar": Quantity("velocity", "steady mean velocity vector v_bar (x, y), zero by the symmetry"),
    "symmetric/periods": Quantity("count", "periods from rest until the period-boundary velocity repeats"),
    "symmetric/max_acceleration": Quantity("acceleration", "max|Y''| of the orbit"),
    "low_acceleration/scale": Quantity("number", "factor on the table motion"),
    "low_acceleration/max_acceleration": Quantity("acceleration", "max|Y''| of the scaled motion (<= 1: the part "
                                                                  "sticks)"),
    "low_acceleration/v_bar": Quantity("velocity", "steady mean velocity vector v_bar (x, y)"),
    "limit_*/scale": Quantity("number", "factor on the table motion"),
    "limit_*/max_acceleration": Quantity("acceleration", "max|Y''| of the scaled motion"),
    "limit_*/v_bar": Quantity("velocity", "steady mean velocity vector v_bar (x, y), simulated"),
    "limit_*/v_limit": Quantity("velocity", "the high-acceleration limit: the geometric median of Y'(t)"),
    "limit_*/error": Quantity("number", "|v_bar - v_limit| over the table's peak speed max|Y'|"),
    "limit_*/periods": Quantity("count", "periods from rest to the steady state"),
    "limit_*/slope": Quantity("number", "exponent p of the least-squares fit error = C max|Y''|^p (-1 by the "
                                        "asymptotic order)"),
    "limit_*/constant": Quantity("number", "factor C of that fit"),
    "limit_*/local_slope": Quantity("number", "exponent between the two largest scales"),
    "line_*/angle": Quantity("number", "the axis: angle between the drift and the strip's normal [rad]"),
    "line_*/normal": Quantity("number", "unit normal n (x, y) of the strip at each angle"),
    "line_*/v_bar": Quantity("velocity", "steady mean velocity vector v_bar (x, y) on the uniform surface"),
    "line_*/depth": Quantity("length", "n.x_end - x_mu of each entry at each angle"),
    "line_*/along": Quantity("length", "t.x_end minus lateral, t the strip's direction: where along the strip the "
                                       "entry ends from where its drift line meets the edge"),
    "line_*/lateral": Quantity("length", "t.p, p where the entry's drift line meets the strip's edge"),
    "line_*/x_end": Quantity("length", "end position (x, y) of each entry at each angle"),
    "line_*/stopped": Quantity("boolean", "the entry came to rest or accumulated at x_stick_min"),
    "line_*/dx_d_normal": Quantity("length", "Delta x_d (eq. 39) along n at each angle"),
    "line_*/dx_d_along": Quantity("length", "Delta x_d along the strip at each angle (half the range of t.x_end)"),
    "line_*/dx_d_slide": Quantity("length", "half the range of along at each angle: the spread the motion adds to "
                                            "that of the entry lines"),
    "line_*/at_limit": Quantity("number", "fraction of the entries that end at x_stick_min along n (accumulated)"),
    "line_*/stick_depth": Quantity("length", "x_stick_min - x_mu along n (eq. 41)"),
    "corner/normal": Quantity("number", "unit normals n (x, y) of the two strips"),
    "corner/corner": Quantity("length", "the point (x, y) where both strips' x_stick_min lines meet"),
    "corner/start": Quantity("length", "start position (x, y) of each entry"),
    "corner/x_end": Quantity("length", "end position (x, y) of each entry"),
    "corner/stopped": Quantity("boolean", "the entry came to rest or accumulated at x_stick_min of a strip"),
    "corner/first": Quantity("code", "the strip that holds each entry", _CORNER_FIRST),
    "corner/distance": Quantity("length", "distance of each entry's end from the corner point"),
    "corner/spread_radius": Quantity("length", "largest distance of an end from the corner point"),
    "corner/dx_d": Quantity("length", "Delta x_d (eq. 39) along x and along y"),
    "corner/stick_depth": Quantity("length", "x_stick_min - x_mu along each normal (eq. 41)"),
    "example_*/t": Quantity("time", "time t of each sample of the example path"),
    "example_*/x": Quantity("length", "relative position (x, y) of the part"),
    "example_*/normal": Quantity("number", "unit normal n (x, y) of each strip"),
    "example_*/x_mu": Quantity("length", "edge x_mu of each strip along its normal"),
})

def quantity(path: str) -> Quantity:
    """The Quantity of the dataset at ``path`` (e.g. ``"series/mode"``); ValueError if undocumented."""
    parts = path.strip("/").split("/")
    if len(parts) > 1:
        scoped = "/".join(parts[-2:])
        for key, found in QUANTITIES.items():
            if "/" in key and fnmatch.fnmatchcase(scoped, key):
                return found
    try:
        return QUANTITIES[parts[-1]]
    except KeyError:
        raise ValueError(f"dataset {path!r} has no units and description: add it to "
                         "selfalign.io.quantities.QUANTITIES") from None
