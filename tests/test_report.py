"""`snakemake --report`: one self-contained HTML file with every figure, every result table and
their captions.

The report is built in a temporary copy of the workflow from the results and figures of
the small pipeline run (conftest ``small_pipeline``: every stage on a shrunk config): only
the table jobs run, nothing is recomputed, so a clean checkout tests it too.
"""

import html
import io
import json
import re
import shutil

import pytest
from conftest import REPO, copy_workflow, run_snakemake

from selfalign.stages.figures import FIGURES
from selfalign.stages.tables import TABLES


def report_entries(page: str) -> dict[str, dict]:
    """The results embedded in a report page: path -> its entry (caption, mime type, data URI)."""
    decoder = json.JSONDecoder()
    entries = {}
    for match in re.finditer(r'"((?:figures|results)/[^"]+)": (\{"name": )', page):
        entries[match.group(1)], _ = decoder.raw_decode(page, match.start(2))
    return entries


def caption_start(rst: str) -> str:
    """The first words of a caption file, without inline markup."""
    return " ".join(rst.replace("**", "").split()[:6])


def caption_text(caption: str) -> str:
    """The text of a rendered caption: tags removed, entities decoded, white space single."""
    return " ".join(html.unescape(re.sub(r"<[^>]+>", "", caption)).split())


@pytest.fixture(scope="module")
def report(repo, small_pipeline, tmp_path_factory):
    """(report page, workflow copy) built from the small pipeline's results and figures."""
    ran, _, rc, out = small_pipeline
    assert rc == 0, out
    work = copy_workflow(repo, tmp_path_factory.mktemp("report"))
    shutil.copy(ran / "workflow/config/config.yaml", work / "workflow/config/config.yaml")
    shutil.copytree(ran / "results", work / "results", ignore=shutil.ignore_patterns("tables"))
    shutil.copytree(ran / "figures", work / "figures")
    tables = [f"results/tables/{name}.html" for name in TABLES]
    rc, out = run_snakemake(work, "-c1", *tables)
    assert rc == 0, out
    rc, out = run_snakemake(work, "--report", "report.html")
    assert rc == 0, out
    assert "ERROR" not in out, out  # docutils reports caption markup errors and carries on
    return (work / "report.html").read_text(encoding="utf-8"), work


@pytest.mark.slow
def test_report_holds_every_figure_with_its_caption(report, repo):
    page, _ = report
    entries = report_entries(page)
    for name in FIGURES:
        entry = entries.get(f"figures/{name}.png")
        assert entry is not None, f"figures/{name}.png is not in the report"
        assert entry["data_uri"].startswith("data:image/png;"), name  # embedded: self-contained
        caption = entry["caption"]
        assert caption_start((repo / f"workflow/report/{name}.rst").read_text()) in caption_text(caption), name
        assert "problematic" not in caption and "{{" not in caption, (name, caption)


def test_report_holds_every_table_with_its_caption(report, repo):
    page, work = report
    entries = report_entries(page)
    for name in TABLES:
        entry = entries.get(f"results/tables/{name}.html")
        assert entry is not None, f"table {name} is not in the report"
        assert entry["data_uri"].startswith("data:text/html;"), name
        rst = (repo / f"workflow/report/table_{name}.rst").read_text()
        assert caption_start(rst) in caption_text(entry["caption"]), name
        table = (work / f"results/tables/{name}.html").read_text(encoding="utf-8")
        assert table.count("<tr>") > 1, table  # a header and rows


def test_tables_hold_every_stability_scene(report):
    """The steady-state and Floquet tables have one row per scene of the stability stage."""
    import yaml

    _, work = report
    config = yaml.safe_load((work / "workflow/config/config.yaml").read_text())
    for name in ("steady_states", "floquet"):
        table = (work / f"results/tables/{name}.html").read_text(encoding="utf-8")
        for scene in config["stages"]["stability"]["scenes"]:
            assert f"<tr><td>{scene}</td>" in table, (name, scene)


@pytest.mark.parametrize("caption", sorted(p.name for p in (REPO / "workflow" / "report").glob("*.rst")))
def test_captions_are_valid_restructuredtext(caption):
    """Every caption is reStructuredText that docutils renders without a warning, as the report
    renders it: a bare |...| in a formula, for instance, is a substitution reference that the report
    shows as an error."""
    from docutils.core import publish_parts

    text = (REPO / "workflow" / "report" / caption).read_text()
    text = re.sub(r"\{\{.*?\}\}", "1", text)  # the report fills these in from the config (Jinja2)
    warnings = io.StringIO()
    publish_parts(text, writer="html", settings_overrides={"warning_stream": warnings, "report_level": 2})
    assert warnings.getvalue() == "", warnings.getvalue()


def test_figure_index_renders_every_caption_of_the_pipeline(small_pipeline):
    """The small pipeline writes figures/README.md with an entry for every figure it drew, each
    with its caption rendered (no template expression left) and with its PNG and PDF files;
    every PDF is one or two columns wide (the figure standard, selfalign.plots.style)."""
    from figcheck import pdf_page_size

    ran, _, rc, out = small_pipeline
    assert rc == 0, out
    drawn = sorted(p.stem for p in (ran / "figures").glob("*.png"))
    index = (ran / "figures/README.md").read_text()
    entries = re.findall(r"^## (\S+)$", index, flags=re.M)
    assert entries == sorted(entries) and entries == drawn
    assert "{{" not in index and "{%" not in index
    for name in drawn:
        assert f"[pdf]({name}.pdf)" in index
        width, _ = pdf_page_size(ran / f"figures/{name}.pdf")
        assert min(abs(width - 84.0), abs(width - 174.0)) < 0.05, (name, width)
