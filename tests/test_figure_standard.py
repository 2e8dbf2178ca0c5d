"""The figure standard (selfalign.plots.style, docs/explanation/figures.md): colours every reader
tells apart, and the checks that keep each figure at print size.

Colour vision is simulated with the matrices of Machado, Oliveira and Fernandes (2009) and
compared by CIE76 Delta E (selfalign.plots.colour_vision); two colours closer than 15 are hard
to tell apart.
"""

import pytest

from selfalign.plots import colour_vision, style


def test_colour_vision_reproduces_the_known_confusion_of_green_and_red():
    """The simulation is the published one: tab:green and tab:red, the old colours of cases 1
    and 2, come within Delta E 7.3 of each other for a deuteranope (and 4.6 for tab:green
    against tab:orange for a protanope), while a normal reader sees them 120 apart."""
    assert colour_vision.delta_e("tab:green", "tab:red", "deuteranopia") == pytest.approx(7.31, abs=0.01)
    assert colour_vision.delta_e("tab:green", "tab:orange", "protanopia") == pytest.approx(4.64, abs=0.01)
    assert colour_vision.delta_e("tab:green", "tab:red") == pytest.approx(119.77, abs=0.01)
    with pytest.raises(ValueError, match="achromatopsia"):
        colour_vision.delta_e("k", "w", "achromatopsia")


@pytest.mark.parametrize("vision", sorted(colour_vision.DEFICIENCIES))
def test_case_colours_stay_apart_for_every_reader(vision):
    """Every two case colours of Table 1 (and white, left to "no data") stay at least
    MIN_DELTA_E apart under protanopia, deuteranopia, tritanopia and normal vision."""
    colours = {**style.CASE_COLORS, "no data": "white"}
    worst = min((colour_vision.delta_e(colours[a], colours[b], vision), a, b)
                for a in colours for b in colours if a != b)
    assert worst[0] >= colour_vision.MIN_DELTA_E, worst


def test_fraction_classes_and_solid_special_values_stay_apart():
    """The three classes of a fraction (none, some, all) are told apart by every reader, and so
    are the solid special values against each other, against the case-0 grey and against white."""
    classes = dict(zip(style.FRACTION_CLASSES, style.FRACTION_COLORS))
    assert colour_vision.closest_pair(classes)[0] >= colour_vision.MIN_DELTA_E
    solid = {k: e["facecolor"] for k, e in style.SPECIAL.items() if e["facecolor"] != "none"}
    assert colour_vision.closest_pair({**solid, "white": "white"})[0] >= colour_vision.MIN_DELTA_E


def test_the_check_catches_an_old_palette():
    """The check can fail: the old tab: palette of the cases fails it (deuteranopia, 1 vs 2)."""
    old = {0: "0.82", 1: "tab:green", 2: "tab:red", 3: "tab:blue", 4: "tab:orange", 5: "tab:purple"}
    assert colour_vision.closest_pair(old)[0] < colour_vision.MIN_DELTA_E
