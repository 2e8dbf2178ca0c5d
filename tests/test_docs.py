"""The documentation stays in step with the code (docs/howto/build-docs.md): its generated reference
pages cover every schema key, result dataset, status and figure, and every test a page cites as
evidence exists.  The build itself (`sphinx-build -W -n`) runs in CI (.ci/run)."""

import re
import sys

import pytest
import yaml
from conftest import REPO

sys.path.insert(0, str(REPO / "docs" / "_ext"))
import generated_pages as G  # noqa: E402

PAGES = sorted(p for p in (REPO / "docs").rglob("*.md") if "_build" not in p.parts and "generated" not in p.parts
               and p.name != "gallery.md")


def _keys(node, prefix=""):
    for name, child in node.get("properties", {}).items():
        if isinstance(child, dict):
            yield prefix + name
            yield from _keys(child, f"{prefix}{name}.")


@pytest.mark.parametrize("name", sorted(G.SCHEMAS))
def test_schema_page_lists_every_key(name):
    """Every property of the schema, nested ones included, has a row (`key.sub` paths)."""
    title, path, intro = G.SCHEMAS[name]
    page = G.schema_page(title, path, intro)
    for key in _keys(yaml.safe_load(path.read_text())):
        assert f"| `{key}` |" in page, (name, key)


def test_quantities_page_lists_every_dataset():
    from selfalign.io.quantities import QUANTITIES

    page = G.quantities_page()
    for key in QUANTITIES:
        assert f"| `{key.replace('|', chr(92) + '|')}` |" in page, key


def test_statuses_page_lists_every_status_and_reason():
    from selfalign.solvers.outcomes import Reason, Status

    page = G.statuses_page()
    for status in Status:
        assert f"| `{status.value}` |" in page, status
    for reason in Reason:
        assert f"| `{reason.name}` | {int(reason)} |" in page, reason


def test_gallery_shows_every_figure_with_its_caption():
    """Every figure of figures/ is on the gallery page with its caption as the figure index
    figures/README.md renders it, and no caption keeps an unrendered template expression."""
    page = G.gallery_page()
    figures = sorted(p.stem for p in (REPO / "figures").glob("*.png"))
    assert len(figures) >= 20
    entries = G._index_entries()
    assert sorted(name for name, _, _ in entries) == figures
    for stem in figures:
        assert f"/../figures/{stem}.png" in page, stem
    for stem, _, caption in entries:
        assert "   " + caption.splitlines()[0] in page, stem
        assert "{{" not in caption and "{%" not in caption, stem


def test_cited_tests_exist():
    """A page that cites `tests/test_x.py::test_name` (or `::name` after it) as evidence names a
    test that exists, so the evidence cannot silently disappear."""
    cited = 0
    for page in PAGES:
        text = page.read_text()
        for match in re.finditer(r"`(tests/test_\w+\.py)((?:::\w+)?)`((?:,?\s*(?:and\s+)?`::\w+`)*)", text):
            source = (REPO / match.group(1)).read_text()
            names = [match.group(2)] + re.findall(r"`(::\w+)`", match.group(3))
            for name in filter(None, names):
                cited += 1
                assert re.search(rf"^def {name[2:]}\(", source, re.M), f"{page.name}: {match.group(1)}{name}"
    assert cited >= 15


def test_every_page_is_in_a_toctree():
    """Sphinx warns about a page outside every toctree; the index names each hand-written page."""
    index = (REPO / "docs/index.md").read_text()
    for page in PAGES:
        name = page.relative_to(REPO / "docs").with_suffix("").as_posix()
        if name != "index":
            assert re.search(rf"^{re.escape(name)}$", index, re.M), name


def test_every_exported_name_has_an_api_page():
    """The API reference (docs/reference/api.md, autosummary) lists every name `selfalign` exports."""
    import selfalign

    listed = set(re.findall(r"^   selfalign\.(\w+)$", (REPO / "docs/reference/api.md").read_text(), re.M))
    assert listed == set(selfalign.__all__) - {"__version__"}
