"""Reference pages generated from the code at every build, so they cannot drift from it.

Written into ``docs/reference/generated/`` (not in git) when the builder starts:

- ``scene-schema.md``, ``design-schema.md``, ``config-schema.md``: every key of the JSON schemas
  (``selfalign/io/schemas``, ``workflow/schemas``), with its type, constraints, default and
  description;
- ``result-quantities.md``: every dataset a result file may hold, from
  :data:`selfalign.io.quantities.QUANTITIES` (the table :func:`selfalign.io.hdf5.write_h5`
  refuses to write without);
- ``statuses.md``: every status and reason of a run's end with its message template, from
  :mod:`selfalign.solvers.outcomes`;
- ``gallery.md`` (one level up, ``docs/gallery.md``): every figure of the workflow with the
  caption the Snakemake report shows, from the index the workflow writes, ``figures/README.md``
  (captions rendered from ``workflow/report/*.rst``).
"""

from __future__ import annotations

import re
from pathlib import Path

import yaml

DOCS = Path(__file__).resolve().parents[1]
ROOT = DOCS.parent
OUT = DOCS / "reference" / "generated"

SCHEMAS = {
    "scene-schema": ("Scene files", ROOT / "selfalign/io/schemas/scene.schema.yaml",
                     "A scene file (`*.yaml`) describes one simulation: see {doc}`/howto/write-scene`."),
    "design-schema": ("Design specs", ROOT / "selfalign/io/schemas/design.schema.yaml",
                      "A design spec describes a station to design: see {doc}`/tutorials/design-station`."),
    "config-schema": ("Workflow configuration", ROOT / "workflow/schemas/config.schema.yaml",
                      "The workflow's `workflow/config/config.yaml`: see {doc}`/tutorials/reproduce-paper`."),
}


def _cell(text) -> str:
    """Text for one cell of a Markdown table."""
    return str(text).replace("|", "\\|").replace("\n", " ").strip()


def _constraints(node: dict) -> str:
    words = []
    for key, symbol in (("minimum", ">="), ("exclusiveMinimum", ">"), ("maximum", "<="),
                        ("exclusiveMaximum", "<"), ("minItems", "items >="), ("maxItems", "items <="),
                        ("minLength", "length >="), ("pattern", "matches")):
        if key in node:
            words.append(f"{symbol} `{node[key]}`")
    if "enum" in node:
        words.append("one of " + ", ".join(f"`{v}`" for v in node["enum"]))
    if "const" in node:
        words.append(f"`{node['const']}`")
    return "; ".join(words)


def _type(node: dict, defs: dict) -> str:
    if "$ref" in node:
        return f"`{node['$ref'].rsplit('/', 1)[-1]}` (below)"
    kinds = node.get("type")
    if kinds is None:
        for key in ("oneOf", "anyOf"):
            if key in node:
                return " or ".join(_type(option, defs) for option in node[key])
        return "enum" if "enum" in node else "any"
    if isinstance(kinds, list):
        return " or ".join(kinds)
    if kinds == "array" and isinstance(node.get("items"), dict):
        return f"array of {_type(node['items'], defs)}"
    return kinds


def _rows(node: dict, prefix: str, required: set, defs: dict):
    for name, child in node.get("properties", {}).items():
        if not isinstance(child, dict):
            continue
        path = f"{prefix}{name}"
        default = f"`{child['default']}`" if "default" in child else ""
        yield (f"`{path}`", _type(child, defs), "yes" if name in required else "", _constraints(child), default,
               child.get("description", ""))
        yield from _rows(child, path + ".", set(child.get("required", ())), defs)
        for option in [*child.get("oneOf", ()), *child.get("anyOf", ())]:
            if isinstance(option, dict) and "properties" in option:
                yield from _rows(option, path + ".", set(option.get("required", ())), defs)


def schema_page(title: str, path: Path, intro: str) -> str:
    schema = yaml.safe_load(path.read_text())
    defs = schema.get("$defs", {})
    head = ["| key | type | required | allowed | default | description |", "| --- | --- | --- | --- | --- | --- |"]
    lines = [f"# {title}", "", intro, "", _cell(schema.get("description", "")), "",
             f"Generated from `{path.relative_to(ROOT)}`; unknown keys are refused.", ""]
    lines += head + ["| " + " | ".join(_cell(c) for c in row) + " |"
                     for row in _rows(schema, "", set(schema.get("required", ())), defs)]
    for name, node in defs.items():
        rows = list(_rows(node, "", set(node.get("required", ())), defs))
        lines += ["", f"## `{name}`", "", _cell(node.get("description", "")) or f"{_type(node, defs)} "
                  f"{_constraints(node)}".strip(), ""]
        if rows:
            lines += head + ["| " + " | ".join(_cell(c) for c in row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def quantities_page() -> str:
    from selfalign.io.quantities import QUANTITIES

    lines = ["# Result datasets", "",
             "Every dataset a result file may hold, with the units and description stored as its "
             "attributes (`units`, `description`, `legend` for a coded value, `si_units` and `si_factor` "
             "when the scene has an SI scale). A dataset is found by `<group>/<name>` (`*` matches any "
             "text) and otherwise by its name; a writer refuses a dataset that is not here. A *measured* "
             "value (CPU or wall-clock time) differs between runs and machines and never identifies a result "
             "({doc}`/reference/results`). Generated from `selfalign.io.quantities.QUANTITIES`.", "",
             "| dataset | units | description | legend |", "| --- | --- | --- | --- |"]
    for key in sorted(QUANTITIES):
        attrs = QUANTITIES[key].attrs()
        legend = ", ".join(f"{code} = {name}" for code, name in attrs.get("legend", {}).items())
        lines.append(f"| `{_cell(key)}` | {_cell(attrs['units'])} | {_cell(attrs['description'])} | {_cell(legend)} |")
    return "\n".join(lines) + "\n"


def statuses_page() -> str:
    from selfalign.solvers import outcomes as O

    lines = ["# Statuses and messages", "",
             "Every run ends with one {class}`~selfalign.Status` and, behind it, one "
             "{class}`~selfalign.Reason` with a message; batch results store the integer codes below. "
             "See {doc}`/explanation/stopping` for what each outcome means. Generated from "
             "`selfalign.solvers.outcomes`.", "",
             "| status | code | reasons |", "| --- | --- | --- |"]
    for status, code in O.STATUS_CODES.items():
        reasons = ", ".join(f"`{r.name}`" for r in O.Reason if O.REASON_STATUS[r] is status)
        lines.append(f"| `{status.value}` | {code} | {reasons} |")
    lines += ["", "| reason | code | status | message template |", "| --- | --- | --- | --- |"]
    for reason in O.Reason:
        lines.append(f"| `{reason.name}` | {int(reason)} | `{reason.status.value}` | "
                     f"`{_cell(O.MESSAGES[reason])}` |")
    return "\n".join(lines) + "\n"


def _index_entries() -> list[tuple[str, str, str]]:
    """(figure, category, caption) of every figure in ``figures/README.md``, the index the
    workflow writes with every caption rendered (rule ``write_figure_index``), in its order."""
    text = (ROOT / "figures/README.md").read_text()
    entries = []
    for block in text.split("\n## ")[1:]:
        name, _, rest = block.partition("\n")
        category_line, image, caption = (part.strip() for part in rest.strip().split("\n\n", 2))
        if not image.startswith(f"![{name}]"):
            raise ValueError(f"figures/README.md: the entry of {name} has no image line")
        entries.append((name.strip(), category_line.split(" · ")[0], caption))
    return entries


def gallery_page() -> str:
    lines = ["# Gallery", "",
             "Every figure the workflow draws (`snakemake -c2` writes them to `figures/`, as PNG and as "
             "PDF at print size), with the caption of the Snakemake report, from the index "
             "`figures/README.md` the workflow writes. Figures named `figNN` are the paper's; the others go "
             "beyond it.", ""]
    for stem, category, caption in _index_entries():
        title = f"Fig. {int(stem[3:])}" if re.fullmatch(r"fig\d\d", stem) else stem.replace("_", " ")
        lines += [f"## {title}", "", f"{category}; vector drawing: `figures/{stem}.pdf`.", "",
                  "```{eval-rst}", f".. figure:: /../figures/{stem}.png",
                  "   :width: 100%", "", *("   " + line for line in caption.splitlines()), "```", ""]
    return "\n".join(lines)


def write_all(app=None) -> list[Path]:
    """Write every generated page; a page is rewritten only when its text changes (so Sphinx
    rebuilds only what moved)."""
    OUT.mkdir(parents=True, exist_ok=True)
    pages = {OUT / f"{name}.md": schema_page(*spec) for name, spec in SCHEMAS.items()}
    pages[OUT / "result-quantities.md"] = quantities_page()
    pages[OUT / "statuses.md"] = statuses_page()
    pages[DOCS / "gallery.md"] = gallery_page()
    for path, text in pages.items():
        if not path.exists() or path.read_text() != text:
            path.write_text(text)
    return list(pages)


def setup(app):
    app.connect("builder-inited", write_all)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
