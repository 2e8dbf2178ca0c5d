"""The design tool and positioning under the effects beyond the paper (docs/tutorials/design-station.md
): Stribeck friction and finite jerk, simulated with the most exact method that can.

Independent checks use Moreau time-stepping at a 4x finer step than the tool's fallback (or
solve_ivp) on runs the tool does not make: the part from rest at several distances before the strip.
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
import yaml

from selfalign.analysis.design import design, friction_at, ramp_at, scale
from selfalign.analysis.positioning import positioning
from selfalign.io.design_report import design_report
from selfalign.io.design_spec import DesignSpecError, design_spec_from_dict
from selfalign.model.design_spec import DesignGrid, DesignSpec
from selfalign.model.friction import FrictionLaw, StopZone
from selfalign.model.profiles import FiniteJerkProfile, ThreePhaseProfile
from selfalign.model.scene import Scene
from selfalign.solvers.driver import simulate, simulate_batch
from selfalign.solvers.methods import FALLBACK_STEPS_PER_PERIOD, most_exact_method
from selfalign.solvers.outcomes import STATUS_CODES, Status
from selfalign.solvers.tables import setting_profile

ROOT = Path(__file__).resolve().parents[1]
STOP = (STATUS_CODES[Status.REST], STATUS_CODES[Status.ACCUMULATION])
#: A small problem without accumulation (a Moreau-checked design costs seconds per candidate): a fixed
#: 80 ms period and 1 mm stroke, 6 x 6 accelerations = 36 designs.
SMALL = dict(mu=0.2, mu_uncertainty=0.05, c_mu=(2.5, 2.5), width=2e-3, max_stroke=1e-3, min_stroke=1e-3,
             max_acceleration=6.0, period=(0.08, 0.08), distance=5e-3, tolerance=150e-6, name="small",
             grid=DesignGrid(periods=1, strokes=1, accelerations=6, entries=256, mu_samples=3, max_verified=8))
STRIBECK = FrictionLaw("stribeck", 1.2, v_s=2e-3, delta=2.0)   # v_s in m/s in a design spec
#: End positions of the independent check may differ from the tool's by Moreau's step error (h = dt / 2000
#: against dt / 8000): a few um on a part 2 mm wide.
END_TOL = 5e-6
#: At the finer step an accumulation reaches x_stick_min to round-off before 1e-12 (the default) is
#: confirmed and the repeating state reads as periodic; 1e-9 of the width (2 nm) decides it.
ACCUMULATION_TOL = 1e-9


def from_rest_ends(spec: DesignSpec, result, mu: float, n: int = 12):
    """(status, end position past the strip's edge [m]) of the chosen design at ``mu``, the part
    starting from rest at n distances D + k vbar dt / n before the strip (entries at n phases),
    by Moreau at a 4x finer step than the tool's fallback."""
    s = scale(spec, mu)
    profile = result.profile_at(mu)
    ramp = ramp_at(spec, mu)
    table_profile = setting_profile(profile.dt, profile.dy, profile.y2, profile.y3, ramp)
    advance = result.vbar_min / s.unit("velocity") * profile.dt
    x0 = -spec.distance / s.L - advance * np.arange(n) / n
    res = simulate_batch(table_profile, x0, 0.0, x_mu=0.0, w=1.0, c_mu=result.c_mu, until="rest",
                         max_periods=20_000, method="moreau", steps_per_period=4 * FALLBACK_STEPS_PER_PERIOD,
                         accumulation_tol=ACCUMULATION_TOL, friction=friction_at(spec, mu))
    return res.status, res.x_end * s.L


@pytest.mark.parametrize("effect, method", [({"friction": STRIBECK}, "moreau (h = dt / 2000"),
                                            ({"ramp": 1e-3}, "exact")], ids=["stribeck", "finite_jerk"])
def test_effect_design_guarantee_holds_under_finer_simulation(effect, method):
    """Hypothesis: a design guaranteed under an effect (Stribeck friction r = 1.2, v_s = 2 mm/s,
    checked by Moreau since the exact solver refuses it; or 1 ms y'' ramps, checked by the exact
    solver's jerk arcs) holds at both mu extremes: every run from rest at 12 phases, simulated
    independently by Moreau at a 4x finer step than the fallback's, ends at rest within the
    tolerance of x_d (plus END_TOL for the step error)."""
    spec = DesignSpec(**SMALL, **effect)
    result = design(spec, progress="quiet")
    assert result.found, result.explanation
    assert result.verification.method.startswith(method)
    for mu in spec.mu_range:
        status, end = from_rest_ends(spec, result, mu)
        assert np.all(np.isin(status, STOP))
        assert np.max(np.abs(end - result.x_d)) <= spec.tolerance + END_TOL


@pytest.mark.parametrize("limit, paper", [
    ({"friction": FrictionLaw("stribeck", 1.2, v_s=1e-7)}, {"friction": FrictionLaw("static_kinetic", 1.2)}),
    ({"ramp": 1e-9}, {}),
], ids=["v_s_to_0", "ramp_to_0"])
def test_effect_limit_gives_the_paper_design(limit, paper):
    """Hypothesis: with v_s = 0.1 um/s (the Stribeck law is static/kinetic friction for every slip
    the Moreau step resolves) the design is the static/kinetic design, and with 1 ns ramps it is
    the paper's design: the same profile and c_mu, an end position x_d within END_TOL and the
    same guarantee."""
    effect = design(DesignSpec(**SMALL, **limit), progress="quiet")
    reference = design(DesignSpec(**SMALL, **paper), progress="quiet")
    assert reference.verification.method.startswith("exact")
    assert (effect.period, effect.stroke, effect.y2, effect.y3, effect.c_mu) == \
        (reference.period, reference.stroke, reference.y2, reference.y3, reference.c_mu)
    assert effect.found == reference.found
    assert effect.x_d == pytest.approx(reference.x_d, abs=END_TOL)


@pytest.mark.parametrize("where, value, message", [
    ("friction", {"kind": "stribeck", "mu_s_over_mu_k": 1.2},
     r"friction\.v_s \(the Stribeck velocity\) is required with kind stribeck"),
    ("friction", {"kind": "stribeck", "mu_s_over_mu_k": 1.2, "v_s": -1e-3}, r"friction\.v_s: .*"),
    ("friction", {"kind": "stribeck", "mu_s_over_mu_k": 0.9, "v_s": 1e-3}, r"friction\.mu_s_over_mu_k: .*"),
    ("friction", {"kind": "static_kinetic", "mu_s_over_mu_k": 1.2, "v_s": 1e-3},
     r"friction\.v_s is a parameter of kind stribeck, not of static_kinetic"),
    ("ramp", -1e-3, r"actuator\.ramp: .*"),
    ("ramp", 0.05, r"actuator\.ramp must be shorter than a third of the longest period \(0\.1 s"),
])
def test_bad_effect_values_are_one_line_errors(where, value, message):
    """Hypothesis: a bad effect value is refused before any work in one line naming the file and the key."""
    data = yaml.safe_load((ROOT / "workflow/designs/smd_steel_table.yaml").read_text())
    if where == "ramp":
        data["actuator"]["ramp"] = value
    else:
        data[where] = value
    with pytest.raises(DesignSpecError, match=rf"^spec\.yaml: {message}") as info:
        design_spec_from_dict(data, "spec.yaml")
    assert "\n" not in str(info.value)


def test_spec_reads_stribeck_in_si_and_scales_it_per_mu():
    """Hypothesis: a Stribeck block is read with v_s in m/s and the model sees v_s / sqrt(mu g L)
    at each mu; a ramp is read in s and seen as ramp / T(mu)."""
    data = yaml.safe_load((ROOT / "workflow/designs/smd_steel_table.yaml").read_text())
    data["friction"] = {"kind": "stribeck", "mu_s_over_mu_k": 1.2, "v_s": 2e-3, "delta": 1.5}
    data["actuator"]["ramp"] = 1e-3
    spec = design_spec_from_dict(data, "spec.yaml")
    assert spec.friction == FrictionLaw("stribeck", 1.2, v_s=2e-3, delta=1.5) and spec.ramp == 1e-3
    law = friction_at(spec, 0.21)
    assert law.v_s == pytest.approx(2e-3 / np.sqrt(0.21 * 9.81 * 2e-3), rel=1e-15)
    assert ramp_at(spec, 0.21) == pytest.approx(1e-3 / np.sqrt(2e-3 / (0.21 * 9.81)), rel=1e-15)


def test_method_choice_follows_the_refusals():
    """Hypothesis: the exact solver is chosen for the paper's scene and for static/kinetic friction,
    Moreau with iteration exact and a stated step for Stribeck friction, and the refusal is the
    exact solver's own message."""
    zone, profile = StopZone(0.0, 1.0, 2.5), ThreePhaseProfile(2.0, 0.3, 2.0, 1.5)
    assert most_exact_method(profile, zone, FrictionLaw()).method == "exact"
    assert most_exact_method(profile, zone, FrictionLaw("static_kinetic", 1.3)).method == "exact"
    choice = most_exact_method(profile, zone, FrictionLaw("stribeck", 1.3, v_s=0.05))
    assert (choice.method, choice.options) == ("moreau", {"steps_per_period": FALLBACK_STEPS_PER_PERIOD,
                                                          "iteration": "exact"})
    assert "Stribeck" in choice.refusal and "h = dt / 2000" in choice.describe()


def test_positioning_with_stribeck_agrees_with_ivp():
    """Hypothesis: positioning accepts Stribeck friction (it ran Moreau) and the end of each of 4
    entries agrees with solve_ivp (rtol 1e-10) run from the same start to within 1e-3 of the part's
    width (Moreau's step error at h = dt / 2000), with the same outcome."""
    law = FrictionLaw("stribeck", 1.2, v_s=0.05)
    profile = ThreePhaseProfile(2.0, 0.3, 2.0, 1.5)
    pos = positioning(profile, w=1.0, c_mu=2.5, n_entries=4, friction=law)
    assert pos.method.startswith("moreau")
    for x0, x_end, status in zip(pos.x0, pos.x_end, pos.status):
        scene = Scene(profile, surface=pos.zone, friction=law, x0=float(x0), v0=pos.v0, until="rest",
                      max_periods=2000)
        run = simulate(scene, "ivp", rtol=1e-10, atol=1e-12)
        assert run.x_end == pytest.approx(x_end, abs=1e-3)
        assert (STATUS_CODES[run.status] in STOP) == (status in STOP)


def test_finite_jerk_positioning_ramp_to_zero_is_the_papers():
    """Hypothesis: positioning with 1e-9 ramps (the exact solver's jerk arcs, first order in the
    ramp) gives the paper's outcome fractions and end positions within 1e-6 of the width, and
    refuses ramps that do not fit in one line."""
    profile = ThreePhaseProfile(2.0, 0.3, 2.0, 1.5)
    paper = positioning(profile, w=1.0, c_mu=2.5, n_entries=8)
    ramped = positioning(profile, w=1.0, c_mu=2.5, n_entries=8, ramp=1e-9)
    assert paper.method.startswith("exact") and ramped.method.startswith("exact")
    assert (ramped.frac_accumulate, ramped.frac_stop) == (paper.frac_accumulate, paper.frac_stop)
    assert np.allclose(ramped.x_end, paper.x_end, rtol=0.0, atol=1e-6)
    with pytest.raises(ValueError, match="too long"):
        positioning(profile, w=1.0, c_mu=2.5, n_entries=8, ramp=0.9)
    assert isinstance(setting_profile(2.0, 0.3, 2.0, 1.5, 0.1), FiniteJerkProfile)


def test_infeasible_report_states_the_criterion_apart_from_the_finding():
    """Hypothesis (the criterion must not read as a finding): a design that is not guaranteed prints
    what was found after "NO, found:" and the criterion after "Criterion:", never "NO (...): every one"."""
    spec = DesignSpec(**{**SMALL, "grid": replace(SMALL["grid"], max_verified=1)}, accumulation=True,
                      friction=FrictionLaw("static_kinetic", 1.3))
    text = design_report(design(spec, progress="quiet"))
    assert "guarantee: NO, found: entries that do not accumulate" in text
    assert ". Criterion: every one of 256 steady-state entries" in text and "NO (" not in text
