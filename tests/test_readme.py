"""The README's quick start, CI script and reference sections stay in step with the code."""

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


def section(readme, title):
    match = re.search(rf"^## {re.escape(title)}\n(.*?)(?=^## |\Z)", readme, re.S | re.M)
    assert match, f"README has no section '## {title}'"
    return match.group(1)


def test_readme_opens_with_what_the_project_is(readme):
    first = readme.split("\n## ", 1)[0]
    assert first.startswith("# selfalign\n") and "reference implementation" in first


def test_quick_start_is_two_idempotent_commands(readme):
    """Exactly two commands: build everything with Snakemake, run the tests; both set up the
    venv in a way that is safe to repeat (no --clear, editable install)."""
    build, test = quick_start(readme)
    for command in (build, test):
        assert command.startswith(SETUP), command
    assert re.fullmatch(re.escape(SETUP) + r"\.venv/bin/snakemake -c\d+", build)
    assert test == SETUP + ".venv/bin/python -m pytest -q"


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


@pytest.mark.parametrize("title", ["Quick start", "Install", "The model and its conventions", "The three-phase profile",
                                   "The polynomial profile", "Scenes", "Pipeline", "Results",
                                   "Rerun recordings", "Figure regression", "Solvers",
                                   "Steady state and classification", "Stability", "Stopping and accumulation",
                                   "Numerical robustness", "Benchmarks", "Choices where the paper is silent or wrong"])
def test_section_exists(readme, title):
    assert re.search(rf"^## {re.escape(title)}\b", readme, re.M), title


def test_scene_keys_are_documented(readme):
    """Every top-level key of the scene schema is in the README's key table."""
    text = section(readme, "Scenes")
    for key in scene_schema()["properties"]:
        assert f"| `{key}` |" in text, key


def test_scene_example_is_the_shipped_file(repo, readme):
    """The YAML example in "Scenes" is workflow/scenes/stop_zone.yaml (without its comments)."""
    example = re.search(r"```yaml\n(.*?)```", section(readme, "Scenes"), re.S).group(1)
    assert yaml.safe_load(example) == yaml.safe_load((repo / "workflow/scenes/stop_zone.yaml").read_text())


def test_result_datasets_and_attributes_are_documented(repo, readme):
    text = section(readme, "Results")
    datasets, attrs = profile_samples(load_scene(repo / "workflow/scenes/fig07.yaml"))
    for name in list(datasets) + list(attrs) + ["selfalign_version"]:
        assert f"`{name}`" in text, name
