"""The figure standard (selfalign.plots.style, docs/explanation/figures.md): colours every reader
tells apart, and every committed figure at print size, as PNG and PDF, in the figure index.

Colour vision is simulated with the matrices of Machado, Oliveira and Fernandes (2009) and
compared by CIE76 Delta E (selfalign.plots.colour_vision); two colours closer than 15 are hard
to tell apart.
"""

import re
from pathlib import Path

import pytest
from figcheck import pdf_font_sizes, pdf_page_size

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
    worst = min(((colour_vision.delta_e(colours[a], colours[b], vision), str(a), str(b))
                 for a in colours for b in colours if a != b), key=lambda pair: pair[0])
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


REPO = Path(__file__).resolve().parents[1]
COMMITTED = sorted(p.stem for p in (REPO / "figures").glob("*.png"))
#: mathtext draws a sub- or superscript at 0.7 of its text per level (matplotlib's SHRINK_FACTOR).
SCRIPT_SCALES = (0.7, 0.49)


def pdf_problems(path) -> list[str]:
    """What keeps the PDF file ``path`` from the print standard: its page is not 84 or 174 mm
    wide or is higher than 234 mm, or it sets a font below 7 pt that is not a mathtext script
    (0.7 or 0.49 of a size of 7 pt or more that the file also sets)."""
    width, height = pdf_page_size(path)
    problems = [f"width {width:.1f} mm"] if min(abs(width - 84.0), abs(width - 174.0)) > 0.05 else []
    if height > 234.05:
        problems.append(f"height {height:.1f} mm")
    sizes = pdf_font_sizes(path)
    text = [s for s in sizes if s >= style.SMALL_FONT_SIZE - 1e-6]
    small = sorted(s for s in sizes if s < style.SMALL_FONT_SIZE - 1e-6
                   and not any(abs(s - k * t) < 1e-3 for t in text for k in SCRIPT_SCALES))
    return problems + ([f"fonts of {small} pt"] if small else [])


def test_every_figure_is_committed_as_png_and_pdf_and_indexed():
    """figures/ holds each figure as PNG and as PDF, and figures/README.md (written by the
    workflow's rule write_figure_index) has an entry for each, with a caption."""
    assert len(COMMITTED) >= 30
    assert sorted(p.stem for p in (REPO / "figures").glob("*.pdf")) == COMMITTED
    index = (REPO / "figures/README.md").read_text()
    entries = re.findall(r"^## (\S+)$", index, flags=re.M)
    assert sorted(entries) == COMMITTED
    assert "{{" not in index


@pytest.mark.parametrize("name", COMMITTED)
def test_committed_figure_prints_at_a_column_width_with_legible_text(name):
    """figures/<name>.pdf is one or two journal columns wide (84 or 174 mm), at most 234 mm high,
    and sets no font below 7 pt but mathtext scripts; figures/<name>.png is the same size at
    300 dpi."""
    from PIL import Image

    pdf = REPO / f"figures/{name}.pdf"
    assert pdf_problems(pdf) == []
    width, height = pdf_page_size(pdf)
    with Image.open(REPO / f"figures/{name}.png") as png:
        assert png.size == pytest.approx((width / 25.4 * style.DPI, height / 25.4 * style.DPI), abs=1.5)


def test_the_pdf_check_catches_a_poster(tmp_path):
    """The check can fail: a 200 mm wide drawing with 6-pt text (not a script of the 10-pt ticks:
    0.7 x 10 = 7) is refused on both counts."""
    from matplotlib.figure import Figure

    from selfalign.plots.encode import figure_bytes

    fig = Figure(figsize=(200 / 25.4, 60 / 25.4))
    fig.subplots().set_xlabel("x", fontsize=6)
    path = tmp_path / "poster.pdf"
    path.write_bytes(figure_bytes(fig, "pdf", 100))
    assert pdf_problems(path) == ["width 200.0 mm", "fonts of [6.0] pt"]


def test_every_caption_states_its_units():
    """Every figure's caption says that its quantities are dimensionless (Sect. 3.2 of the paper)
    or that they are in SI units, so a reader of figures/README.md knows what the axes measure."""
    captions = [p for p in sorted((REPO / "workflow/report").glob("*.rst"))
                if not p.stem.startswith("table_") and p.stem != "workflow"]
    assert len(captions) >= 30
    silent = [p.stem for p in captions if not re.search(r"dimensionless|\bSI\b", p.read_text())]
    assert silent == []
