"""Bad input is refused before any work, in one line naming the parameter, its value and what is
allowed (README "Numerical robustness", "Limits"): TypeError for a wrong type, ValueError for a
wrong value.  Sizes and budgets that scale the work are bounded by documented limits.
"""

from decimal import Decimal
from fractions import Fraction

import numpy as np
import pytest

import selfalign as sa
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
