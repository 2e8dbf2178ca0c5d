"""The README's "Use from Python" examples run as printed and print what the README says they do."""

import contextlib
import io
import re
import shutil

import pytest
from conftest import REPO

EXPECTED = "# -> "


def examples() -> list[str]:
    """The ```python blocks of the README section "Use from Python"."""
    readme = (REPO / "README.md").read_text()
    match = re.search(r"^## Use from Python\n(.*?)(?=^## |\Z)", readme, re.S | re.M)
    assert match, "README has no section '## Use from Python'"
    return re.findall(r"^```python\n(.*?)^```$", match.group(1), re.S | re.M)


def test_every_main_api_has_an_example():
    """One example each for simulate (of a scene file), steady_state/classify, floquet,
    simulate_batch and positioning, and each says what it prints."""
    blocks = examples()
    for call in ("sa.load_scene(", "sa.steady_state(", "sa.floquet(", "sa.simulate_batch(", "sa.positioning("):
        assert any(call in block for block in blocks), call
    assert all(EXPECTED in block for block in blocks)


@pytest.mark.parametrize("index", range(len(examples())))
def test_example_prints_what_the_readme_says(index, tmp_path, monkeypatch):
    """Run from a copy of the repository's scenes (paths relative to the repository top), the
    example prints exactly its "# -> " lines."""
    shutil.copytree(REPO / "workflow" / "scenes", tmp_path / "workflow" / "scenes")
    monkeypatch.chdir(tmp_path)
    block = examples()[index]
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(compile(block, f"README 'Use from Python' example {index + 1}", "exec"), {})
    expected = [line[len(EXPECTED):] for line in block.splitlines() if line.startswith(EXPECTED)]
    assert printed.getvalue().splitlines() == expected
