"""Figure regression: figures rebuilt from fresh data match the committed references.

The numbers a figure shows are compared with ``tests/figure_refs/<fig>.json``
(``selfalign.figcheck.figure_data``; rtol 1e-9); the pixels are compared with the
committed ``figures/<fig>.png`` only under the pinned matplotlib series, whose
rendering the PNG was made with.  After an intended change, rewrite both with
``python -m pytest tests/test_figures.py --update-figure-refs`` and review the diff.
"""

import re
import shutil
import tomllib

import matplotlib
import pytest
import yaml

from selfalign import load_scene
from selfalign.figcheck import compare_figure_data, compare_pixels, figure_data, load_reference, save_reference
from selfalign.pipeline import figure_07, profile_samples, save_figure
from selfalign.profiles import ThreePhaseProfile
from selfalign.results import read_h5, write_h5

#: Relative tolerance on figure data: the numbers come from closed forms, so only rounding differs.
RTOL = 1e-9
#: Absolute tolerance, for values that are zero up to rounding (min y = 0).
ATOL = 1e-12
#: RMS pixel difference (0..255) tolerated under the pinned matplotlib series.
PIXEL_TOL = 1.0


def pinned_matplotlib_series(repo):
    """"3.11" from the dependency "matplotlib==3.11.*" in pyproject.toml."""
    deps = tomllib.loads((repo / "pyproject.toml").read_text())["project"]["dependencies"]
    pins = [m.group(1) for d in deps if (m := re.fullmatch(r"matplotlib\s*==\s*(\d+\.\d+)\.\*", d))]
    assert len(pins) == 1, f"pyproject.toml must pin matplotlib as ==X.Y.*, got {deps}"
    return pins[0]


def build_fig07(scene, tmp_path):
    """The pipeline's steps without Snakemake: scene -> HDF5 -> figure."""
    h5 = tmp_path / f"{scene.name}.h5"
    write_h5(h5, *profile_samples(scene))
    return figure_07(read_h5(h5))


@pytest.fixture
def fig07_scene(repo):
    return load_scene(repo / "workflow/scenes/fig07.yaml")


@pytest.fixture
def dpi(repo):
    return yaml.safe_load((repo / "workflow/config/config.yaml").read_text())["figures"]["dpi"]


def test_fig07_data_matches_reference(repo, fig07_scene, tmp_path, update_figure_refs, dpi):
    """Fig. 7 (Sect. 4.4.3) shows the same numbers as the committed reference, rtol 1e-9."""
    ref_path = repo / "tests/figure_refs/fig07.json"
    fig = build_fig07(fig07_scene, tmp_path)
    data = figure_data(fig)
    if update_figure_refs:
        save_reference(data, ref_path)
        save_figure(fig, repo / "figures/fig07.png", dpi=dpi)
        pytest.skip("figure references rewritten")
    diffs = compare_figure_data(data, load_reference(ref_path), rtol=RTOL, atol=ATOL)
    assert not diffs, "\n".join(diffs[:20])


def test_fig07_pixels_match_committed_png(repo, fig07_scene, tmp_path, dpi):
    """The committed figures/fig07.png is what the current code draws (RMS <= 1 of 255)."""
    series = pinned_matplotlib_series(repo)
    if not matplotlib.__version__.startswith(series + "."):
        pytest.skip(f"pixels are compared under matplotlib {series}.* only; this is {matplotlib.__version__}")
    fresh = save_figure(build_fig07(fig07_scene, tmp_path), tmp_path / "fig07.png", dpi=dpi)
    committed = tmp_path / "fig07-committed.png"
    shutil.copyfile(repo / "figures/fig07.png", committed)
    rms = compare_pixels(fresh, committed, tol=PIXEL_TOL)
    assert rms is None, f"figures/fig07.png differs from the current drawing: RMS {rms}"


def test_fig07_comparison_catches_stroke_change(repo, fig07_scene, tmp_path):
    """The check can fail: a stroke 1 % larger (dy 0.084 -> 0.08484) is reported, on the y data."""
    p = fig07_scene.profile
    changed = fig07_scene.replace(profile=ThreePhaseProfile(p.dt, p.dy * 1.01, p.y2, p.y3))
    diffs = compare_figure_data(figure_data(build_fig07(changed, tmp_path)),
                                load_reference(repo / "tests/figure_refs/fig07.json"), rtol=RTOL, atol=ATOL)
    assert any(d.startswith("figure.axes[0].lines[0].y") for d in diffs), diffs
