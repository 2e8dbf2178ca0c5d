"""Bad input is refused before any work, in one line naming the parameter, its value and what is
allowed (docs/explanation/robustness.md): TypeError for a wrong type, ValueError for a
wrong value.  Sizes and budgets that scale the work are bounded by documented limits.
"""

from decimal import Decimal
from fractions import Fraction

import numpy as np
import pytest

import selfalign as sa
from selfalign.analysis.positioning import positioning_grid
from selfalign.model.friction import FrictionLaw
from selfalign.model.profiles import FiniteJerkProfile

FIG18 = sa.ThreePhaseProfile(1.05, 0.084, 2.2, 0.9)  # Sect. 5.1 / 7.3 settings, case 1
PROFILE_ARGS = {"dt": 1.05, "dy": 0.05, "y2": 2.2, "y3": 2.4}


def one_line(info) -> str:
    message = str(info.value)
    assert "\n" not in message, message
    return message


# ------------------------------------------------------------------------------------------
# Types: a real number is an int, a float or a numpy scalar; never an array, Decimal or str
# ------------------------------------------------------------------------------------------

BUILDERS = {
    "ThreePhaseProfile": lambda **kw: sa.ThreePhaseProfile(**{**PROFILE_ARGS, **kw}),
    "FiniteJerkProfile": lambda **kw: FiniteJerkProfile(**{**PROFILE_ARGS, "ramp": 1e-3, **kw}),
    "PolynomialProfile": lambda **kw: sa.PolynomialProfile(**{"dt": 1.0, "dy": 0.1, **kw}),
    "FourierProfile": lambda **kw: sa.FourierProfile(**{"dt": 1.0, "cos_coeffs": [0.1], "sin_coeffs": [0.0], **kw}),
    "StopZone": lambda **kw: sa.StopZone(**{"x_mu": 0.1, "w": 0.05, "c_mu": 2.5, **kw}),
    "Scene": lambda **kw: sa.Scene(FIG18, **{"periods": 1, **kw}),
    "FrictionLaw": lambda **kw: FrictionLaw("static_kinetic", **{"mu_s_over_mu_k": 2.0, **kw}),
    "SIScale": lambda **kw: sa.SIScale(**{"mu": 0.3, "g": 9.81, "L": 1e-3, **kw}),
}
WRONG_TYPES = [np.array([1.05]), np.array(1.05), Decimal("1.05"), "1.05", True, None, [1.05]]
PARAMETERS = [("ThreePhaseProfile", "dt"), ("ThreePhaseProfile", "y3"), ("FiniteJerkProfile", "dt"),
              ("PolynomialProfile", "dt"), ("PolynomialProfile", "forward_fraction"), ("FourierProfile", "dt"),
              ("StopZone", "x_mu"), ("StopZone", "w"), ("StopZone", "c_mu"), ("Scene", "x0"), ("Scene", "v0"),
              ("Scene", "phase"), ("FrictionLaw", "mu_s_over_mu_k"), ("SIScale", "L")]


@pytest.mark.parametrize("builder, parameter", PARAMETERS)
@pytest.mark.parametrize("value", WRONG_TYPES, ids=lambda v: type(v).__name__ + str(np.ndim(v)))
def test_wrong_type_is_a_type_error_naming_the_parameter(builder, parameter, value):
    """A parameter given as an array (any shape, 0-d and size-1 included), a Decimal, a string, a
    bool, None or a list is a TypeError naming the parameter and the allowed type, raised before any
    arithmetic (not a numpy or decimal error from inside it)."""
    with pytest.raises(TypeError) as info:
        BUILDERS[builder](**{parameter: value})
    message = one_line(info)
    assert parameter in message and "real number (int, float or numpy scalar)" in message, message


@pytest.mark.parametrize("convert", [np.float64, np.float32, np.int64, Fraction], ids=lambda c: c.__name__)
def test_numpy_scalars_and_fractions_are_real_numbers(convert):
    """numpy scalars (and other numbers.Real) are accepted and converted to float once: the profile
    equals the one built from Python floats."""
    values = {key: convert(value) if convert is not np.int64 else value for key, value in PROFILE_ARGS.items()}
    if convert is np.int64:
        values["dt"] = np.int64(2)
    reference = sa.ThreePhaseProfile(**{key: float(value) for key, value in values.items()})
    profile = sa.ThreePhaseProfile(**values)
    assert type(profile.dt) is float and profile.params() == reference.params()


@pytest.mark.parametrize("key, value", [("periods", "3"), ("periods", np.array(3)), ("max_periods", Decimal(10))])
def test_integer_of_wrong_type_is_a_type_error(key, value):
    kw = {"periods": value} if key == "periods" else {"until": "rest", "max_periods": value}
    with pytest.raises(TypeError, match=f"horizon.{key} must be an integer"):
        sa.Scene(FIG18, **kw)


def test_profile_parameters_beyond_the_friction_scale_are_refused():
    """dt, dy, y2, y3 are in units of the friction scale (Sect. 3.2); beyond 1e+-30 of it the closed
    forms overflow (numpy warnings and inf).  Expected: a ValueError naming the parameter and the range."""
    with pytest.raises(ValueError, match=r"^dy must lie in \[1e-30, 1e\+30\]"):
        sa.ThreePhaseProfile(1.0, 1e-300, 2.0, 2.0)
    with pytest.raises(ValueError, match=r"^y3 must lie in"):
        sa.ThreePhaseProfile(1.0, 1.0, 1e20, 1.7e308)


@pytest.mark.parametrize("mu, g, L", [(1e-300, 1e-150, 1e20), (1.0, 0.05, 5e-324), (1e300, 1e300, 1.0)])
def test_si_scale_without_finite_units_is_refused(mu, g, L):
    """An si scale whose unit of time, velocity, ... is 0 or overflows (mu g = 0, L / (mu g) = inf)
    raised ZeroDivisionError or OverflowError inside a conversion.  Expected: ValueError at once."""
    with pytest.raises(ValueError, match="give no finite unit of"):
        sa.SIScale(mu, g, L)


# ------------------------------------------------------------------------------------------
# Solver options: every integer has an upper bound, every budget is costed before the run
# ------------------------------------------------------------------------------------------

ZONE = sa.StopZone(0.5, 0.05, 2.5)


@pytest.mark.parametrize("method", ["exact", "ivp"])
@pytest.mark.parametrize("value", [2**70, 1e30, 10**10 + 1])
def test_max_events_has_an_upper_bound(method, value):
    """max_events = 2**70 or 1e30 failed to compile the kernel (int64) or overflowed.  Expected: one
    ValueError naming the option, the allowed range [1, 1e10] and the value."""
    with pytest.raises(ValueError) as info:
        sa.simulate(sa.Scene(FIG18, periods=1), method=method, max_events=value)
    assert one_line(info).startswith("option max_events must be an integer in [1, 10,000,000,000], got")


def test_integer_options_are_bounded():
    for options, name in (({"steps_per_period": 2**70}, "steps_per_period"), ({"fp_max_iter": 10**6}, "fp_max_iter")):
        with pytest.raises(ValueError, match=f"option {name} must be an integer in"):
            sa.simulate(sa.Scene(FIG18, periods=1), method="moreau", **options)


@pytest.mark.parametrize("options", [{"h": 1.05}, {"steps_per_period": 1}])
def test_moreau_steps_that_cannot_see_the_table_motion_are_refused(options):
    """Moreau with h = dt (one step: every table impulse y'(t + dt) - y'(t) is 0) reported "at rest for
    good" at the start position.  Expected: ValueError naming h, the share of the table's velocity
    swing its steps see and the least share (1/2), before any step."""
    scene = sa.Scene(FIG18, ZONE, x0=0.0, until="rest")
    with pytest.raises(ValueError) as info:
        sa.simulate(scene, method="moreau", **options)
    message = one_line(info)
    assert message.startswith("option h = dt / ") and "too coarse" in message and "at least 0.5" in message


def test_moreau_at_ten_steps_per_period_still_runs():
    """The accuracy study starts at 10 steps per period: those see 0.89 of FIG18's velocity swing."""
    traj = sa.simulate(sa.Scene(FIG18, ZONE, x0=0.0, until="rest"), method="moreau", steps_per_period=10)
    assert traj.status in (sa.Status.REST, sa.Status.ACCUMULATION)


def test_moreau_work_is_costed_before_the_run():
    """Moreau has no event budget: its horizon is its work.  10,000 periods of 10^7 steps (10^11 steps,
    hours) are refused naming the horizon option, the estimate and the limit 1e10; a scene file
    with the same budget is refused when it is loaded."""
    with pytest.raises(ValueError) as info:
        sa.simulate(sa.Scene(FIG18, until="rest", max_periods=10_000), method="moreau", steps_per_period=10**7)
    message = one_line(info)
    assert "horizon.max_periods = 10,000 periods at 10,000,000 steps per period" in message and "1e+10" in message
    with pytest.raises(sa.SceneError, match="horizon.periods = 2,000 periods"):
        sa.scene_from_dict({"profile": {"kind": "three_phase", "dt": 1.05, "dy": 0.084, "y2": 2.2, "y3": 0.9},
                            "horizon": {"periods": 2000},
                            "solver": {"method": "moreau", "options": {"steps_per_period": 10**7}}})


@pytest.mark.parametrize("method", ["exact", "moreau", "ivp"])
def test_accumulation_tol_is_bounded_by_the_zone_width(method):
    """accumulation_tol = 1e300 took every zone stick above the one before for converged (real rests
    reported as accumulation).  Expected: ValueError naming the option, the zone width and the
    limit 1e-6 w; 1e-6 w itself is accepted."""
    scene = sa.Scene(FIG18, ZONE, x0=0.0, until="rest", max_periods=300)
    with pytest.raises(ValueError) as info:
        sa.simulate(scene, method=method, accumulation_tol=1e300)
    assert one_line(info).startswith("option accumulation_tol = 1e+300 is more than 1e-06 of the zone width w = 0.05")
    assert sa.simulate(scene, method="exact", accumulation_tol=1e-6 * ZONE.w).status is sa.Status.ACCUMULATION


@pytest.mark.parametrize("x_mu", [1e308, -1e12, 0.05 * 2.0**33])
def test_zone_beyond_double_resolution_is_refused(x_mu):
    """StopZone(x_mu=1e308) ran the whole budget ("zone never entered"): doubles near 1e308 are 2e292
    apart.  Expected: ValueError naming x_mu and w when |x_mu| > 2**32 w (the positions x_mu + xi
    resolve w in fewer than 2**20 steps); 1e6 with w = 0.05 is fine (tests/test_torture.py)."""
    with pytest.raises(ValueError) as info:
        sa.StopZone(x_mu, 0.05, 2.5)
    assert one_line(info).startswith(f"stop zone x_mu = {x_mu!r} is more than 2**32 times its width w = 0.05")
    with pytest.raises(ValueError, match="is more than 2\\*\\*32 times its width"):
        sa.simulate_batch(FIG18, 0.0, x_mu=x_mu, w=0.05, c_mu=2.5)


# ------------------------------------------------------------------------------------------
# Batches and positioning
# ------------------------------------------------------------------------------------------

@pytest.mark.parametrize("index, error, match", [
    (0.7, ValueError, "profile_index must hold integers \\(indices into the profiles\\), got 0.7"),
    ([0.0, 1.5], ValueError, "got 1.5"),
    (["a"], TypeError, "profile_index must hold integers, got dtype"),
    (np.nan, ValueError, "got nan"),
])
def test_profile_index_must_be_integers(index, error, match):
    """A float profile_index was truncated to an int (0.7 ran profile 0).  Integral floats are indices."""
    with pytest.raises(error, match=match):
        sa.simulate_batch([FIG18, FIG18], 0.0, profile_index=index, until="periods", periods=1)
    res = sa.simulate_batch([FIG18, sa.ThreePhaseProfile(1.0, 0.084, 1.4, 1.3)], 0.0, profile_index=[1.0, 0.0],
                            until="periods", periods=1)
    assert list(res.records["profile"]) == [1, 0]


@pytest.mark.parametrize("kw, name", [({"x0": "0.1"}, "x0"), ({"v0": [None]}, "v0"), ({"x0": True}, "x0"),
                                      ({"x0": 0.0, "x_mu": "0", "w": 0.05, "c_mu": 2.5}, "x_mu")])
def test_batch_arrays_of_the_wrong_type(kw, name):
    """Per-member inputs that are not numbers were a numpy conversion error naming nothing."""
    with pytest.raises(TypeError, match=f"^{name} must be a real number or an array of them"):
        sa.simulate_batch(FIG18, **{"x0": 0.0, **kw}, until="periods", periods=1)


@pytest.mark.parametrize("kw, name", [({"until": "rest", "max_periods": 2**70}, "max_periods"),
                                      ({"until": "periods", "periods": 1e30}, "periods")])
def test_batch_horizon_is_bounded(kw, name):
    """max_periods = 2**70 was an OverflowError from the kernel call."""
    with pytest.raises(ValueError, match=f"^{name} must be an integer in \\[1, 9.0072e\\+15\\]"):
        sa.simulate_batch(FIG18, 0.0, **kw)


def test_batch_memory_is_costed_before_allocating():
    """10^8 members (a broadcast view costs nothing) would allocate ~40 GiB of records.  Expected:
    ValueError naming the member count, the estimate and the 2 GiB limit, before any allocation."""
    with pytest.raises(ValueError) as info:
        sa.simulate_batch(FIG18, 0.0, profile_index=np.broadcast_to(0, (10**8,)), until="periods", periods=1)
    assert one_line(info).startswith("simulate_batch: 100,000,000 members need about 4")


@pytest.mark.parametrize("kw, start", [
    ({"max_periods": 10**30}, "max_periods must be an integer in [1, 9.0072e+15]"),
    ({"max_periods": 1e21}, "max_periods must be an integer in [1, 9.0072e+15]"),
    ({"n_entries": 10**9}, "n_entries = 1,000,000,000 entries for each of 1 setting(s) need about 615 GiB"),
    ({"n_entries": 64.5}, "n_entries must be an integer"),
    ({"max_periods": 10**9}, "max_periods = 1,000,000,000 for 1 setting(s) x 64 entries is a budget of 6.4e+10 "
                             "entry-periods, more than the 1e+10 allowed"),
    ({"accumulation_tol": 1e300}, "option accumulation_tol = 1e+300 is more than 1e-06 of the zone width"),
])
def test_positioning_sizes_are_bounded(kw, start):
    """positioning(max_periods=10**30) was an OverflowError and n_entries = 10**9 was killed at 24 GB.
    Expected: one ValueError naming the option, its value and the limit (for n_entries the memory
    estimate too), before any work."""
    with pytest.raises(ValueError) as info:
        sa.positioning(FIG18, w=0.05, c_mu=2.5, **kw)
    assert one_line(info).startswith(start)
    grid_kw = {key: value for key, value in kw.items()}
    with pytest.raises(ValueError):
        positioning_grid(1.05, 0.084, np.array([2.2, 2.0]), 0.9, w=0.05, c_mu=2.5, **grid_kw)


def test_scene_file_option_of_the_wrong_type_names_the_file(tmp_path):
    """A solver option of the wrong type in a scene file is a SceneError naming the file and option."""
    path = tmp_path / "s.yaml"
    path.write_text("profile: {kind: three_phase, dt: 1.05, dy: 0.084, y2: 2.2, y3: 0.9}\n"
                    "horizon: {periods: 1}\nsolver: {method: exact, options: {max_events: '5'}}\n")
    with pytest.raises(sa.SceneError, match=f"^{path}: solver: option max_events must be an integer, got '5'"):
        sa.load_scene(path)


# ------------------------------------------------------------------------------------------
# Every exported callable: TypeError for a string where a number (or a profile, a spec) is
# expected, ValueError for a negative or NaN number; a scene document's problems are SceneErrors
# ------------------------------------------------------------------------------------------

NAN = float("nan")
ZONE_SCENE = sa.Scene(FIG18, ZONE, x0=0.0, until="rest", max_periods=50)
SCENE_DOC = {"profile": {"kind": "three_phase", "dt": 1.05, "dy": 0.084, "y2": 2.2, "y3": 0.9},
             "horizon": {"periods": 1}}
PIECES = {"breaks": [0.0, 0.5, 1.0], "accels": [1.0, -1.0], "y_start": 0.0, "yd_start": 0.0}


def design_spec(**changes):
    import dataclasses

    from selfalign.io.design_spec import load_design_spec

    return dataclasses.replace(load_design_spec("workflow/designs/cam_drive.yaml"), **changes)


def scene_doc(**profile):
    return {**SCENE_DOC, "profile": {**SCENE_DOC["profile"], **profile}}


#: (callable, a call with a string where a number or an object is expected, a call with a negative
#: or NaN number).
CALLS = {
    "simulate": (lambda: sa.simulate(sa.Scene(FIG18, periods=1), max_events="5"),
                 lambda: sa.simulate(ZONE_SCENE, accumulation_tol=-1e-12)),
    "simulate/scene": (lambda: sa.simulate("scene.yaml"), lambda: sa.simulate(ZONE_SCENE, accumulation_tol=NAN)),
    "simulate_batch": (lambda: sa.simulate_batch(FIG18, 0.0, surface=ZONE, levels=["0.6"]),
                       lambda: sa.simulate_batch(FIG18, 0.0, surface=ZONE, levels=[NAN])),
    "simulate_batch/max_cycle": (lambda: sa.simulate_batch(FIG18, 0.0, max_cycle="8"),
                                 lambda: sa.simulate_batch(FIG18, 0.0, max_cycle=-8)),
    "simulate_batch/profiles": (lambda: sa.simulate_batch("FIG18", 0.0),
                                lambda: sa.simulate_batch(FIG18, NAN)),
    "positioning": (lambda: sa.positioning(FIG18, w="0.05", c_mu=2.5),
                    lambda: sa.positioning(FIG18, w=-0.05, c_mu=2.5)),
    "positioning/profile": (lambda: sa.positioning("FIG18", w=0.05, c_mu=2.5),
                            lambda: sa.positioning(FIG18, w=0.05, c_mu=NAN)),
    "positioning/friction": (lambda: sa.positioning(FIG18, w=0.05, c_mu=2.5, friction="coulomb"),
                             lambda: sa.positioning(FIG18, w=0.05, c_mu=2.5, ramp=-0.01)),
    "stick_map": (lambda: sa.stick_map("0.51", FIG18, w=0.05, c_mu=2.5, x_mu=0.5),
                  lambda: sa.stick_map(NAN, FIG18, w=0.05, c_mu=2.5, x_mu=0.5)),
    "stick_map/zone": (lambda: sa.stick_map(0.51, FIG18, w="0.05", c_mu=2.5, x_mu=0.5),
                       lambda: sa.stick_map(0.51, FIG18, w=-0.05, c_mu=2.5, x_mu=0.5)),
    "steady_state": (lambda: sa.steady_state((1.05, "0.084", 2.2, 0.9)),
                     lambda: sa.steady_state((1.05, -0.084, 2.2, 0.9))),
    "steady_state/profile": (lambda: sa.steady_state("FIG18"), lambda: sa.steady_state((1.05, NAN, 2.2, 0.9))),
    "classify": (lambda: sa.classify({"dt": 1.05, "dy": 0.084, "y2": "2.2", "y3": 0.9}),
                 lambda: sa.classify({"dt": 1.05, "dy": 0.084, "y2": NAN, "y3": 0.9})),
    "classify/profile": (lambda: sa.classify("FIG18"), lambda: sa.classify((1.05, 0.084, -2.2, 0.9))),
    "floquet": (lambda: sa.floquet(FIG18, "saltation", max_periods="100"),
                lambda: sa.floquet(FIG18, "saltation", max_periods=-100)),
    "floquet/eps": (lambda: sa.floquet(FIG18, "numeric", eps="1e-6"), lambda: sa.floquet(FIG18, "numeric", eps=NAN)),
    "floquet/profile": (lambda: sa.floquet("FIG18"), lambda: sa.floquet(sa.Scene(FIG18, x0=NAN, periods=1))),
    "design": (lambda: sa.design("workflow/designs/cam_drive.yaml"), lambda: sa.design(design_spec(mu=-0.3))),
    "design/spec": (lambda: sa.design(design_spec(mu="0.3")), lambda: sa.design(design_spec(mu=NAN))),
    "lyapunov_trace": (lambda: sa.lyapunov_trace(FIG18, "0.1", 0.2, 3), lambda: sa.lyapunov_trace(FIG18, NAN, 0.2, 3)),
    "lyapunov_trace/periods": (lambda: sa.lyapunov_trace(FIG18, 0.1, 0.2, "3"),
                               lambda: sa.lyapunov_trace(FIG18, 0.1, 0.2, -3)),
    "lyapunov_trace/profile": (lambda: sa.lyapunov_trace("FIG18", 0.1, 0.2, 3),
                               lambda: sa.lyapunov_trace(FIG18, 0.1, 0.2, 3, phase=NAN)),
    "load_scene": (lambda: sa.load_scene(5), lambda: sa.load_scene("no/such/scene.yaml")),
    "ThreePhaseProfile": (lambda: sa.ThreePhaseProfile("1.05", 0.084, 2.2, 0.9),
                          lambda: sa.ThreePhaseProfile(1.05, -0.084, 2.2, 0.9)),
    "FiniteJerkProfile": (lambda: sa.FiniteJerkProfile(1.05, 0.084, 2.2, 0.9, ramp="0.01"),
                          lambda: sa.FiniteJerkProfile(1.05, 0.084, 2.2, 0.9, jerk=NAN)),
    "PolynomialProfile": (lambda: sa.PolynomialProfile(1.0, "0.1"), lambda: sa.PolynomialProfile(-1.0, 0.1)),
    "FourierProfile": (lambda: sa.FourierProfile(1.0, ["0.1"], [0.0]), lambda: sa.FourierProfile(1.0, [NAN], [0.0])),
    "FourierProfile/dt": (lambda: sa.FourierProfile("1.0", [0.1], [0.0]),
                          lambda: sa.FourierProfile(-1.0, [0.1], [0.0])),
    "PiecewiseConstantProfile": (lambda: sa.PiecewiseConstantProfile(**{**PIECES, "breaks": ["0", "0.5", "1"]}),
                                 lambda: sa.PiecewiseConstantProfile(**{**PIECES, "breaks": [0.0, -0.5, 1.0]})),
    "PiecewiseConstantProfile/accels": (lambda: sa.PiecewiseConstantProfile(**{**PIECES, "accels": ["1", -1.0]}),
                                        lambda: sa.PiecewiseConstantProfile(**{**PIECES, "accels": [NAN, -1.0]})),
    "StopZone": (lambda: sa.StopZone("0.5", 0.05, 2.5), lambda: sa.StopZone(0.5, -0.05, 2.5)),
    "StopZone/c_mu": (lambda: sa.StopZone(0.5, 0.05, "2.5"), lambda: sa.StopZone(0.5, 0.05, NAN)),
    "Scene": (lambda: sa.Scene(FIG18, x0="0", periods=1), lambda: sa.Scene(FIG18, x0=NAN, periods=1)),
    "Scene/horizon": (lambda: sa.Scene(FIG18, periods="1"), lambda: sa.Scene(FIG18, periods=-1)),
    "Scene/profile": (lambda: sa.Scene("FIG18", periods=1), lambda: sa.Scene(FIG18, phase=-0.5, periods=1)),
    "Scene/surface": (lambda: sa.Scene(FIG18, "zone", periods=1), lambda: sa.Scene(FIG18, v0=NAN, periods=1)),
    "Scene/record": (lambda: sa.Scene(FIG18, periods=1, record="x"),
                     lambda: sa.Scene(FIG18, periods=1, record=sa.Record(("x",), samples_per_period=-1))),
    "Scene/si": (lambda: sa.Scene(FIG18, periods=1, si="si"),
                 lambda: sa.Scene(FIG18, periods=1, si=sa.SIScale(0.3, 9.81, -1e-3))),
    "FrictionLaw": (lambda: sa.FrictionLaw("static_kinetic", "2"), lambda: sa.FrictionLaw("static_kinetic", NAN)),
}


@pytest.mark.parametrize("name", CALLS)
def test_a_string_for_a_number_is_a_type_error(name):
    """Hypothesis: every exported function and class raises TypeError, naming the argument, for a
    string where it expects a number, an array of numbers, a profile or a design spec, before any
    work; none converts the string or fails later with another error."""
    with pytest.raises(TypeError) as info:
        CALLS[name][0]()
    one_line(info)


@pytest.mark.parametrize("name", CALLS)
def test_a_negative_or_nan_number_is_a_value_error(name):
    """Hypothesis: every exported function and class raises ValueError (or a subclass: SceneError
    for a Scene or scene file) for a negative or NaN number where it needs a positive or finite one,
    and never TypeError: the type was right."""
    with pytest.raises(ValueError) as info:
        CALLS[name][1]()
    assert not isinstance(info.value, TypeError)
    one_line(info)


@pytest.mark.parametrize("loader", ["scene_from_dict", "load_scene"])
@pytest.mark.parametrize("value, problem", [("1.05", "expected number, got str '1.05'"),
                                            (-1.05, "must be > 0, got -1.05"), (NAN, "must be a finite number")])
def test_a_scene_document_names_the_key_for_any_problem(tmp_path, loader, value, problem):
    """Hypothesis: a scene document (a dict or a YAML file) is data, so a string, a negative or a NaN
    where it needs a number is one SceneError (a ValueError) naming the key, like every other
    problem of a document, whatever its kind; the CLI's ``check`` and the workflow catch that one
    class."""
    doc = scene_doc(dt=value)
    if loader == "load_scene":
        import yaml

        path = tmp_path / "bad.yaml"
        path.write_text(yaml.safe_dump(doc))
        doc, source = path, str(path)
    else:
        source = "<scene>"
    with pytest.raises(sa.SceneError) as info:
        getattr(sa, loader)(doc)
    assert one_line(info).startswith(f"{source}: profile.dt: {problem}"), info.value


FIG18_SCENE = sa.Scene(sa.ThreePhaseProfile(1.05, 0.084, 2.2, 0.9), periods=1)
CHOICES = {
    "simulate/method": lambda v: sa.simulate(FIG18_SCENE, v),
    "simulate_batch/method": lambda v: sa.simulate_batch(FIG18_SCENE.profile, [0.0], method=v, periods=1),
    "simulate_batch/until": lambda v: sa.simulate_batch(FIG18_SCENE.profile, [0.0], until=v, periods=1),
    "floquet/method": lambda v: sa.floquet(FIG18_SCENE.profile, v),
    "positioning_grid/progress": lambda v: positioning_grid(1.0, 0.084, 2.0, 1.0, w=0.05, c_mu=2.5, progress=v),
}


@pytest.mark.parametrize("value", [1, 1.5, b"exact", ["exact"]], ids=lambda v: type(v).__name__)
@pytest.mark.parametrize("call", CHOICES)
def test_a_choice_of_the_wrong_type_is_a_type_error(call, value):
    """Hypothesis: a method, ``until`` or ``progress`` that is not a string raises TypeError naming the
    argument and its allowed values, as a number of the wrong type does; an unknown string stays a
    ValueError naming them."""
    name = call.split("/")[1]
    with pytest.raises(TypeError, match=f"^{name} must be a string, one of \\["):
        CHOICES[call](value)
    with pytest.raises(ValueError, match=f"{name} must be one of \\[") as info:
        CHOICES[call]("nonsense")
    assert not isinstance(info.value, TypeError)
