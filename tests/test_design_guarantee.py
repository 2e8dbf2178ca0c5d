"""The design guarantee holds over the whole mu interval and every entry phase, not only at the
samples (selfalign.analysis.design.end_bounds, phase_sup, mu_sup, worst_process_time).

Hypotheses come from the paper and the docstrings' derivations: no part rests below
x_stick_min (eq. 41), so the lowest end over [mu (1 - delta), mu (1 + delta)] is x_stick_min at
mu_max; accumulating entries end exactly there (Sect. 7.3, eq. 60 = eq. 41), so an
accumulating design's error is the range of eq. 41 over the interval; the end position
against entry phase is a sawtooth (Sect. 7.1: entries over one steady period), whose
largest value the sampling bounds with the allowance of phase_sup.  The dense checks simulate
61 mu values x 432 entries at offsets the tool does not use.
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from selfalign.analysis.design import (
    Candidates,
    design,
    design_map,
    dimensionless,
    end_spread,
    friction_at,
    mu_sup,
    mu_values,
    phase_sup,
    verify,
)
from selfalign.analysis.positioning import positioning
from selfalign.io.design_spec import load_design_spec
from selfalign.model.design_spec import DesignGrid, DesignSpec
from selfalign.model.profiles import ThreePhaseProfile
from selfalign.solvers.driver import simulate_batch
from selfalign.solvers.tables import three_phase_table

ROOT = Path(__file__).resolve().parents[1]
#: Dense check: mu values over the interval and entries per mu (26,352 runs).
DENSE_MU, DENSE_ENTRIES = 61, 432
#: End positions are event-located by the exact solver to ~1e-12 w; 1 nm covers the rounding.
END_TOL = 1e-9


def paper_spec(name: str) -> DesignSpec:
    """The example spec ``name`` of workflow/designs/ restricted to the paper's three-phase family."""
    return dataclasses.replace(load_design_spec(ROOT / f"workflow/designs/{name}.yaml"), families=("three_phase",))


def chosen(result) -> Candidates:
    return Candidates(*(np.array([getattr(result, k)]) for k in ("period", "stroke", "y2", "y3", "c_mu")))


def dense_ends(spec: DesignSpec, cand: Candidates, offset: float = 0.37) -> np.ndarray:
    """End positions [m past the strip's edge] of DENSE_ENTRIES steady-state entries at each of
    DENSE_MU values of mu (Sect. 7.1, at an offset the tool does not use); NaN where one does not stop."""
    ends = []
    for mu in mu_values(spec, DENSE_MU):
        profile = ThreePhaseProfile(*(float(a[0]) for a in dimensionless(spec, cand, mu)))
        pos = positioning(profile, w=1.0, c_mu=float(cand.c_mu[0]), n_entries=DENSE_ENTRIES, offset=offset,
                          friction=friction_at(spec, mu))
        ends.append(pos.overshoot * spec.width)
    return np.array(ends)


def test_phase_sup_bounds_sawtooth_peaks_and_jumps_between_samples():
    """Hypothesis (phase_sup's derivation): from 64 samples of a period, the bound is at least the
    maximum over 200,001 points for a rising sawtooth (top just before a jump), a smooth peak
    midway between samples, and a sawtooth whose samples next to a jump fall on the wrong side
    (a solver's step error), and it exceeds the maximum by at most two samples' change."""
    n = 64
    s = (np.arange(n) + 0.5) / n
    fine = np.linspace(0.0, 1.0, 200_001)
    saw = lambda x: 3.0 * np.mod(x + 0.3, 1.0 / 3.0)  # noqa: E731  three teeth, slope 3
    peak = lambda x: np.cos(2 * np.pi * (x - s[10] - 0.5 / n))  # noqa: E731  peak midway between samples
    for f, step in ((saw, 3.0 / n), (peak, 2 * np.pi / n)):
        bound = float(phase_sup(f(s)))
        assert f(fine).max() <= bound <= f(fine).max() + 2 * step
    noisy = saw(s)
    top = int(np.argmax(noisy))
    noisy[(top + 1) % n] = noisy[top] - 1e-3  # the first sample past the jump still on the tooth
    noisy[(top + 2) % n] = saw(s[(top + 2) % n])
    assert float(phase_sup(noisy)) >= saw(fine).max()
    assert float(phase_sup(noisy)) <= saw(fine).max() + 2 * 3.0 / n


def test_mu_sup_is_exact_for_a_trend_and_covers_a_peak():
    """Hypothesis (mu_sup's derivation): on 5 samples a linear trend gives its largest sample (no
    allowance), and a parabola peaking between samples stays below the bound."""
    mu = np.linspace(0.19, 0.21, 5)
    assert float(mu_sup(3.0 - 10.0 * mu)) == pytest.approx(3.0 - 10.0 * 0.19, rel=1e-15)
    fine = np.linspace(0.19, 0.21, 10_001)
    parabola = lambda m: -((m - 0.1962) ** 2)  # noqa: E731
    assert float(mu_sup(parabola(mu))) >= parabola(fine).max()


def test_accumulating_design_error_is_the_eq41_range_over_the_interval():
    """Hypothesis (eq. 41, Sect. 7.3): when every entry accumulates, the ends are x_stick_min(mu),
    which falls with mu, so the bound is exactly [x_stick_min(mu_max), x_stick_min(mu_min)]: the
    error equals the closed-form half-range end_spread and x_d its middle."""
    spec = paper_spec("smd_steel_table")
    result = design(spec, progress="quiet")
    assert result.found and result.verification.accumulates[0]
    assert result.error == pytest.approx(float(end_spread(spec, chosen(result))[0]), rel=1e-9)
    xs = result.verification.x_stick_min[0]
    assert result.x_d == pytest.approx(0.5 * (xs[0] + xs[-1]), rel=1e-9)


def test_tolerance_between_sampled_and_dense_spread_is_not_guaranteed():
    """Hypothesis: the cam drive's fastest design without accumulation (Fig. 17's stick-slip
    region, 4.07 Hz, 10 mm) has sampled ends spread +-1351.6 um, while no end lies below
    x_stick_min(mu_max) = 941.7 um (eq. 41) and dense entries reach 943.7 um: a tolerance of
    1353 um in between is not guaranteed, and every dense end lies inside x_d +- error."""
    spec = dataclasses.replace(paper_spec("cam_drive"), accumulation=False)
    cand = chosen(design(spec, progress="quiet"))
    tight = dataclasses.replace(spec, tolerance=1353e-6)
    ver = verify(tight, cand)
    assert ver.stops[0] and not ver.guaranteed[0]
    assert ver.failure[0].startswith("end positions spread beyond the tolerance")
    assert ver.sampled_error[0] < tight.tolerance < ver.error[0]
    ends = dense_ends(spec, cand)
    assert not np.isnan(ends).any()
    assert np.abs(ends - ver.x_d[0]).max() <= ver.error[0] + END_TOL


def test_max_process_time_is_checked_over_the_mu_interval():
    """Hypothesis: the process time bound (worst_process_time) is at least the process time of the
    run from rest at 61 values of mu over the interval, and a max_process_time between the worst
    sample and that bound is not guaranteed (smd_robust's design, accumulation)."""
    spec = paper_spec("smd_robust")
    result = design(spec, progress="quiet")
    cand = chosen(result)
    limit = result.t_arrive + 1e-3
    checked = verify(dataclasses.replace(spec, max_process_time=limit), cand)
    assert not checked.guaranteed[0] and checked.failure[0] == "process time beyond max_process_time"
    level = (result.x_d - spec.tolerance) / spec.width
    times = []
    for mu in mu_values(spec, DENSE_MU):
        dt, dy, y2, y3 = dimensionless(spec, cand, mu)
        res = simulate_batch(three_phase_table(dt, dy, y2, y3), -spec.distance / spec.width, 0.0, 0.0,
                             profile_index=np.zeros(1, int), x_mu=np.zeros(1), w=np.ones(1), c_mu=cand.c_mu,
                             levels=np.array([[level]]), until="rest", max_periods=5000)
        times.append(float(res.crossing_time(2)[0]) * result.period)
    assert max(times) <= checked.t_worst[0]


def test_realistic_design_holds_under_dense_simulation():
    """Hypothesis: smd_realistic's guaranteed design (static/kinetic friction r = 1.2, no
    accumulation: every end at rest above x_stick_min, eq. 41) has every one of 61 mu x 432
    dense entries end at rest inside x_d +- error, and error <= tolerance."""
    spec = paper_spec("smd_realistic")
    result = design(spec, progress="quiet")
    assert result.found and result.error <= spec.tolerance
    ends = dense_ends(spec, chosen(result))
    assert not np.isnan(ends).any()
    assert np.abs(ends - result.x_d).max() <= result.error + END_TOL


def test_design_map_beyond_the_positioning_limits_names_the_spec_keys():
    """Hypothesis: a design map too large for positioning's memory limit is refused before any
    work, naming search.accelerations, refine and entries (not positioning's n_entries)."""
    spec = DesignSpec(mu=0.2, mu_uncertainty=0.05, c_mu=(2.5, 2.5), width=2e-3, max_stroke=1e-3, min_stroke=1e-3,
                      max_acceleration=6.0, period=(0.08, 0.08), distance=5e-3, tolerance=150e-6,
                      grid=DesignGrid(periods=1, strokes=1, accelerations=6, mu_samples=3, max_verified=8))
    result = design(spec, progress="quiet")
    with pytest.raises(ValueError, match=r"search\.accelerations x refine.*entries") as info:
        design_map(result, refine=400, entries=1000)
    assert "n_entries" not in str(info.value) and "\n" not in str(info.value)
