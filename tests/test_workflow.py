"""The Snakemake workflow and its trajectory stage.

Snakemake runs in a temporary copy of ``Snakefile`` + ``workflow/`` (results
and figures are written relative to the working directory, so the repository
is never touched).  The stage's library step, ``profile_samples``, is tested
directly as well.
"""

import numpy as np
import pytest
import yaml
from conftest import run_snakemake as snakemake

import selfalign
from selfalign import load_scene, scene_from_dict
from selfalign.io.hdf5 import read_h5
from selfalign.stages.trajectory import profile_samples

NOTHING_TO_DO = "Nothing to be done"


def test_dry_run_plans_every_stage_job(workdir):
    """`snakemake -n` parses the workflow, validates config and scenes, and plans all jobs."""
    rc, out = snakemake(workdir, "-n", "-c1")
    assert rc == 0, out
    config = yaml.safe_load((workdir / "workflow/config/config.yaml").read_text())
    for name in config["stages"]["trajectory"]["scenes"]:
        assert f"results/trajectory/{name}.h5" in out
    assert "plot_fig07" in out and "figures/fig07.png" in out


@pytest.mark.parametrize("old, new, key", [
    ("dt: 0.05", "dt: -0.05", "profile.dt"),
    ("horizon: {periods: 3}", "horizon: {periods: 3, perods: 4}", "horizon: unknown key 'perods'"),
])
def test_malformed_scene_stops_before_any_job(workdir, old, new, key):
    """A bad scene file stops the run at parse time with one message naming file and key."""
    scene = workdir / "workflow/scenes/polynomial.yaml"
    scene.write_text(scene.read_text().replace(old, new))
    rc, out = snakemake(workdir, "-c1")
    assert rc != 0
    assert f"invalid scene: workflow/scenes/polynomial.yaml: {key}" in out, out
    assert not (workdir / "results").exists() and not (workdir / "figures").exists()


def trajectory_targets(workdir):
    """The trajectory stage's outputs only, so this test does not run the later stages."""
    config = yaml.safe_load((workdir / "workflow/config/config.yaml").read_text())
    return [f"results/trajectory/{name}.h5" for name in config["stages"]["trajectory"]["scenes"]] + [
        "figures/fig07.png"]


@pytest.mark.slow
def test_trajectory_stage_end_to_end(workdir):
    """The workflow profile builds every trajectory result and Fig. 7; afterwards nothing is
    left to do, and restyling the figure (dpi) reruns the plot only, not the data."""
    targets = trajectory_targets(workdir)
    rc, out = snakemake(workdir, "--workflow-profile", "workflow/profiles/default", *targets)
    assert rc == 0, out
    result = read_h5(workdir / "results/trajectory/fig07.h5")
    d, a = result["datasets"], result["attrs"]
    assert set(d) == {"t", "y", "yd", "ydd", "switch_times"}
    np.testing.assert_allclose(d["switch_times"], [a["t1"], a["t2"]], rtol=0, atol=0)
    assert (a["kind"], a["dt"], a["dy"], a["y2"], a["y3"]) == ("three_phase", 1.05, 0.084, 2.2, 0.9)
    assert a["selfalign_version"] == selfalign.__version__
    scene = load_scene(workdir / "workflow/scenes/fig07.yaml")
    assert scene_from_dict(yaml.safe_load(a["scene"])).to_dict() == scene.to_dict()
    assert (workdir / "figures/fig07.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"

    rc, out = snakemake(workdir, "-n", "-c1", *targets)
    assert rc == 0 and NOTHING_TO_DO in out, out

    config = workdir / "workflow/config/config.yaml"
    assert "dpi: 300" in config.read_text()
    config.write_text(config.read_text().replace("dpi: 300", "dpi: 80"))
    rc, out = snakemake(workdir, "-n", "-c1", *targets)
    assert rc == 0 and "plot_fig07" in out and "sample_trajectory" not in out, out


def test_samples_include_switch_times_and_span_the_horizon(repo):
    """Samples cover [phase dt, (phase + N) dt] with samples_per_period per period plus every
    switch time; at a switch y'' is the new piece's value (right-continuous), so y' is exactly
    linear between samples (midpoint value = mean of the ends, to 1e-12)."""
    base = load_scene(repo / "workflow/scenes/fig07.yaml")
    scene = base.replace(phase=0.3, periods=3)
    d, a = profile_samples(scene)
    p = scene.profile
    t = d["t"]
    assert t[0] == pytest.approx(0.3 * p.dt, abs=1e-15) and t[-1] == pytest.approx(3.3 * p.dt, rel=1e-15)
    assert np.all(np.diff(t) > 0)
    switches = np.concatenate([k * p.dt + p.switch_times for k in range(4)])
    switches = switches[(switches >= t[0]) & (switches <= t[-1])]
    hits = np.searchsorted(t, switches)
    np.testing.assert_allclose(t[hits], switches, rtol=1e-15)
    assert t.size == 3 * scene.record.samples_per_period + 1 + switches.size
    # right after t1 the table decelerates with -y2, right after t2 it accelerates with +y3
    assert set(np.round(d["ydd"][hits], 12)) == {-p.y2, p.y3}
    mid = 0.5 * (t[:-1] + t[1:])
    np.testing.assert_allclose(p.velocity(mid), 0.5 * (d["yd"][:-1] + d["yd"][1:]), rtol=0, atol=1e-12)
    assert (a["periods"], a["samples_per_period"]) == (3, scene.record.samples_per_period)


def test_rest_scene_samples_one_period(repo):
    """A scene that runs until rest has no fixed horizon: the stage samples one period."""
    scene = load_scene(repo / "workflow/scenes/stop_zone.yaml")
    d, a = profile_samples(scene)
    assert a["periods"] == 1 and d["t"][-1] == pytest.approx(scene.profile.dt, rel=1e-15)


def set_figure_formats(workdir, formats: str):
    config = workdir / "workflow/config/config.yaml"
    text = config.read_text()
    assert "formats: [png, pdf]" in text
    config.write_text(text.replace("formats: [png, pdf]", f"formats: {formats}"))


def test_figure_formats_plan_one_file_per_format(workdir):
    """`figures.formats` adds PDF and SVG files of every figure; all come from one plot job."""
    set_figure_formats(workdir, "[png, pdf, svg]")
    rc, out = snakemake(workdir, "-n", "-c1", "figures/fig07.svg")
    assert rc == 0, out
    for fmt in ("png", "pdf", "svg"):
        assert f"figures/fig07.{fmt}" in out, out
    assert out.count("rule plot_fig07:") == 1, out


def test_unknown_figure_format_is_rejected(workdir):
    set_figure_formats(workdir, "[png, jpg]")
    rc, out = snakemake(workdir, "-n", "-c1")
    assert rc != 0
    assert "invalid config" in out and "formats" in out, out


@pytest.mark.parametrize("fmt, magic", [("png", b"\x89PNG"), ("pdf", b"%PDF"), ("svg", b"<?xml")])
def test_figure_files_are_reproducible_in_every_format(tmp_path, fmt, magic):
    """save_figure writes the format of the suffix, and the same drawing twice gives the same bytes
    (no dates or versions in the metadata, constant SVG ids)."""
    from selfalign.plots.style import new_figure
    from selfalign.stages.common import save_figure

    def drawing():
        fig = new_figure("single", 40)
        fig.subplots().plot([0, 1], [1, 0], label="line")
        return fig

    first, second = (save_figure(drawing(), tmp_path / f"{i}.{fmt}", dpi=50).read_bytes() for i in range(2))
    assert first.startswith(magic) and first == second


def test_save_figure_rejects_an_unknown_format(tmp_path):
    from selfalign.plots.style import new_figure
    from selfalign.stages.common import save_figure

    with pytest.raises(ValueError, match="jpg"):
        save_figure(new_figure("single", 40), tmp_path / "f.jpg")


def test_save_figure_refuses_a_figure_off_the_print_standard(tmp_path):
    """A figure wider than two columns, with 6-pt text or a title, is refused before a file is
    written, with every problem named (the figure standard, selfalign.plots.style)."""
    from matplotlib.figure import Figure

    from selfalign.stages.common import save_figure

    fig = Figure(figsize=(8, 4))
    ax = fig.subplots()
    ax.set_title("a title")
    ax.set_xlabel("x", fontsize=6)
    with pytest.raises(ValueError, match=r"width 203.2 mm.*title 'a title'.*'x' is 6 pt"):
        save_figure(fig, tmp_path / "f.png")
    assert not (tmp_path / "f.png").exists()
