"""Every Python example of the README and the documentation runs as printed and prints what the
page says it does: each ```python block ends its printing lines with the expected output as
``# -> `` comments, and a block without them is a defect (an example a reader cannot check)."""

import contextlib
import io
import re
import shutil

import pytest
from conftest import REPO

EXPECTED = "# -> "
#: Pages written by hand (the generated reference pages hold no examples).
PAGES = [REPO / "README.md", *sorted(p for p in (REPO / "docs").rglob("*.md")
                                     if "_build" not in p.parts and "generated" not in p.parts)]


def blocks() -> list[tuple[str, int, str]]:
    """(page, number, code) of every ```python block of :data:`PAGES`."""
    found = []
    for page in PAGES:
        for number, code in enumerate(re.findall(r"^```python\n(.*?)^```$", page.read_text(), re.S | re.M), 1):
            found.append((str(page.relative_to(REPO)), number, code))
    return found


def test_the_first_simulation_tutorial_covers_the_main_entry_points():
    """One example each for simulate (of a scene file), steady_state/classify, floquet,
    simulate_batch and positioning."""
    text = "".join(code for page, _, code in blocks() if page.endswith("first-simulation.md"))
    for call in ("sa.load_scene(", "sa.steady_state(", "sa.floquet(", "sa.simulate_batch(", "sa.positioning("):
        assert call in text, call


@pytest.mark.parametrize("page, number, code", blocks(), ids=[f"{p}#{n}" for p, n, _ in blocks()])
def test_example_prints_what_its_page_says(page, number, code, tmp_path, monkeypatch):
    """Run from a copy of the repository's scenes and design specs (paths relative to the
    repository top), the example prints exactly its "# -> " lines."""
    expected = [line.split(EXPECTED, 1)[1] for line in code.splitlines() if EXPECTED in line]
    assert expected, f"{page} example {number} shows no output ('# -> ' lines)"
    for folder in ("scenes", "designs"):
        shutil.copytree(REPO / "workflow" / folder, tmp_path / "workflow" / folder)
    monkeypatch.chdir(tmp_path)
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(compile(code, f"{page} example {number}", "exec"), {})
    assert printed.getvalue().splitlines() == expected
