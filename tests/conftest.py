"""Shared test options.

``--update-figure-refs`` rewrites the figure references (tests/figure_refs/*.json
and the committed figures/*.png) from the current code instead of comparing
against them; use it only after an intended change of a figure and review the diff.
"""

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]


def pytest_addoption(parser):
    parser.addoption("--update-figure-refs", action="store_true", default=False,
                     help="rewrite tests/figure_refs/*.json and figures/*.png instead of comparing")


@pytest.fixture
def update_figure_refs(request) -> bool:
    return request.config.getoption("--update-figure-refs")


@pytest.fixture
def repo() -> Path:
    return REPO
