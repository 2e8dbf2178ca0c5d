"""Sphinx configuration of the selfalign documentation (``sphinx-build -W -n docs docs/_build/html``)."""

from __future__ import annotations

import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
sys.path.insert(0, str(DOCS / "_ext"))

project = "selfalign"
author = "the selfalign developers"
copyright = "2026, the selfalign developers"

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "sphinx.ext.napoleon",
    "sphinx.ext.mathjax",
    "sphinx_click",
    "generated_pages",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
exclude_patterns = ["_build", "_ext", "**/.ipynb_checkpoints"]
root_doc = "index"

# Markdown: heading anchors for links such as [Results](../reference/results.md#datasets), $...$ maths,
# definition lists, and ``{eval-rst}`` blocks for figures with captions.
myst_enable_extensions = ["dollarmath", "deflist", "colon_fence"]
myst_heading_anchors = 3

# API reference: numpy-style docstrings, one page per public name (autosummary); the types are in the
# docstrings' Parameters sections, so signatures show no annotations (they name internal classes).
autosummary_generate = True
autosummary_imported_members = False
autodoc_default_options = {"members": True, "show-inheritance": True}
autodoc_member_order = "bysource"
autodoc_typehints = "none"
napoleon_numpy_docstring = True
napoleon_google_docstring = False
napoleon_use_rtype = False
# Attributes sections as :ivar: fields: autodoc documents the members themselves, once.
napoleon_use_ivar = True

# Every cross-reference must resolve (-n).  The documentation is built offline, so the types
# of numpy, scipy, h5py, click and the standard library that annotations name have no target.
nitpicky = True
nitpick_ignore_regex = [
    # Internal classes that signatures and parameter types of the exported functions name: the
    # precomputed profile table simulate_batch also accepts, the design tool's grid, the profile
    # class a finite-jerk profile builds, the entries of a planar alignment study.
    (r"py:class", r"(selfalign(\.\w+)*\.)?(ProfileTable|DesignGrid|PiecewiseLinearProfile|Entries)"),
    (r"py:.*", r"(np|numpy|numpy\.typing|scipy|h5py|click|matplotlib|rerun|numba|collections|typing|"
               r"pathlib|os|enum|dataclasses|numbers|fractions|decimal)(\..*)?"),
    (r"py:class", r"(ndarray|ArrayLike|NDArray|Path|Axes|Figure|Callable|Iterable|Sequence|Mapping|Any|"
                  r"optional|array_like|array|int|float|bool|str|dict|list|tuple|None|callable|"
                  r"Real|StrEnum|IntEnum|Enum|datetime.*)"),
]

templates_path = ["_templates"]
html_theme = "alabaster"
html_title = "selfalign"
html_static_path: list[str] = []
html_theme_options = {"description": "Vibrational self-alignment by friction", "fixed_sidebar": True}
