"""The README's quick start and CI script stay in step, and the reference pages it hands over to
in docs/ stay in step with the code."""

import re
import tomllib

import pytest
import yaml
from test_light_install import requirement_names

from selfalign.io.scene_files import load_scene, scene_schema
from selfalign.stages.trajectory import profile_samples

BEGIN, END = "<!-- quick-start:begin -->", "<!-- quick-start:end -->"
SETUP = "python3 -m venv .venv && .venv/bin/pip install -e '.[test]' && "


@pytest.fixture
def readme(repo):
    return (repo / "README.md").read_text()


def quick_start(readme):
    """The commands between the quick-start markers (fence lines and blanks dropped)."""
    assert readme.count(BEGIN) == 1 and readme.count(END) == 1
    block = readme[readme.index(BEGIN) + len(BEGIN):readme.index(END)]
    return [line for line in block.strip().splitlines() if line.strip() and not line.startswith("```")]


def test_readme_opens_with_what_the_project_is(readme):
    first = readme.split("\n## ", 1)[0]
    assert first.startswith("# selfalign\n") and "reference implementation" in first


def test_quick_start_is_two_idempotent_commands(readme):
    """Exactly two commands: build everything with Snakemake, run the tests (on two processes, a test
    file per process at a time, so that a file's fixtures are built once); both set up the venv in a
    way that is safe to repeat (no --clear, editable install)."""
    build, test = quick_start(readme)
    for command in (build, test):
        assert command.startswith(SETUP), command
    assert re.fullmatch(re.escape(SETUP) + r"\.venv/bin/snakemake -c\d+", build)
    assert test == SETUP + ".venv/bin/python -m pytest -q -n 2 --dist loadfile"


def test_ci_runs_the_readme_test_command_verbatim(repo, readme):
    test = quick_start(readme)[1]
    lines = (repo / ".ci/run").read_text().splitlines()
    assert lines[0] == "#!/usr/bin/env bash"
    assert "set -euo pipefail" in lines
    assert test in lines


def test_quick_start_extra_and_tools_are_declared(repo):
    """'.[test]' names an extra that exists; snakemake (through the `workflow` extra it names) and
    pytest come with the install."""
    project = tomllib.loads((repo / "pyproject.toml").read_text())["project"]
    assert "test" in project["optional-dependencies"]
    names = requirement_names(project, "test")
    assert "snakemake" in names and "pytest" in names


def test_readme_is_short_and_points_into_the_docs(repo, readme):
    """The README is the front page (at most 200 lines); the reference and the derivations live in
    docs/, and every docs page it names exists."""
    assert len(readme.splitlines()) <= 200
    for page in re.findall(r"`(docs/[\w/.-]+\.md)`", readme):
        assert (repo / page).is_file(), page


def test_scene_keys_are_documented(repo):
    """Every top-level key of the scene schema is in the key table of the how-to on scenes."""
    text = (repo / "docs/howto/write-scene.md").read_text()
    for key in scene_schema()["properties"]:
        assert f"| `{key}` |" in text, key


def test_scene_example_is_the_shipped_file(repo):
    """The YAML example of the how-to on scenes is workflow/scenes/stop_zone.yaml (without its comments)."""
    example = re.search(r"```yaml\n(.*?)```", (repo / "docs/howto/write-scene.md").read_text(), re.S).group(1)
    assert yaml.safe_load(example) == yaml.safe_load((repo / "workflow/scenes/stop_zone.yaml").read_text())


def test_result_datasets_and_attributes_are_documented(repo):
    """Every dataset and attribute of a trajectory-stage result is on the result-file page."""
    text = (repo / "docs/reference/results.md").read_text()
    datasets, attrs = profile_samples(load_scene(repo / "workflow/scenes/fig07.yaml"))
    for name in list(datasets) + list(attrs) + ["selfalign_version"]:
        assert f"`{name}`" in text, name
