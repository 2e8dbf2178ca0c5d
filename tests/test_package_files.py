"""The files a scientific package has: licence, citation, changelog and the typing marker and stub, each
consistent with pyproject.toml."""

import re
import tomllib
from importlib import resources

import yaml

PAPER_DOI = "10.1007/s11071-010-9878-0"


def project(repo):
    return tomllib.loads((repo / "pyproject.toml").read_text())["project"]


def test_licence_file_is_the_declared_licence(repo):
    """pyproject declares an OSI licence (SPDX id) whose text is the LICENSE file."""
    meta = project(repo)
    assert meta["license"] == "BSD-3-Clause"
    assert meta["license-files"] == ["LICENSE"]
    assert (repo / "LICENSE").read_text().startswith("BSD 3-Clause License")


def test_citation_cites_the_paper_and_the_software(repo):
    """CITATION.cff is valid YAML in CFF 1.2 form, cites the paper by its DOI and the
    software at the package's version and licence."""
    cff = yaml.safe_load((repo / "CITATION.cff").read_text())
    meta = project(repo)
    assert cff["cff-version"] == "1.2.0"
    assert cff["type"] == "software" and cff["version"] == meta["version"]
    assert cff["license"] == meta["license"]
    paper = cff["preferred-citation"]
    assert paper["doi"] == PAPER_DOI
    assert [a["family-names"] for a in paper["authors"]] == ["Hunnekens", "Fey", "Shukla", "Nijmeijer"]
    assert (paper["journal"], paper["volume"], paper["start"], paper["end"], paper["year"]) == \
        ("Nonlinear Dynamics", 65, 109, 129, 2011)


def test_changelog_has_the_current_version(repo):
    """CHANGELOG.md has an Unreleased section and one for the version in pyproject."""
    text = (repo / "CHANGELOG.md").read_text()
    versions = re.findall(r"^## \[([^\]]+)\]", text, re.M)
    assert versions[0] == "Unreleased"
    assert project(repo)["version"] in versions


def test_package_is_marked_typed(repo):
    """py.typed and the stub of the top-level names, __init__.pyi, ship with the package (PEP 561):
    both are package data and present."""
    config = tomllib.loads((repo / "pyproject.toml").read_text())
    for name in ("py.typed", "__init__.pyi"):
        assert name in config["tool"]["setuptools"]["package-data"]["selfalign"], name
        assert resources.files("selfalign").joinpath(name).is_file(), name
