"""The result tables of the workflow report: small self-contained HTML files built from
existing result files (rules ``tabulate_<name>``, ``workflow/rules/report.smk``).

:data:`TABLES` maps a table's name (the stem of ``results/tables/<name>.html``) to the
function that builds its (columns, rows) from the inputs the workflow gives it;
:func:`html_table` renders them.  Nothing here runs a simulation: every number is read
from a result file, or follows from one by arithmetic (v̄ from the advance per period).
"""

from __future__ import annotations

import html
import math
from pathlib import Path

import numpy as np

from ..analysis.steady_state import OBJECTIVE_SCALE
from ..io.hdf5 import read_h5
from ..io.simulation_result import scene_from_result
from ..model.scene import Scene

#: Printed in a cell that has no value (the method does not apply).
NO_VALUE = "—"

#: Labels of the Floquet methods of a stability result, in the order of the table's columns.
FLOQUET_METHODS = {"analytic": "analytic λ1, λ2", "saltation": "saltation",
                   "numeric_exact": "numeric, exact solver", "numeric_moreau": "numeric, Moreau"}


def setting_text(scene: Scene) -> str:
    """The profile's parameters, and the stop zone if there is one, as plain text."""
    p = scene.profile.params()
    if p["kind"] == "three_phase":
        text = f"Δt = {p['dt']:g}, Δy = {p['dy']:g}, y2'' = {p['y2']:g}, y3'' = {p['y3']:g}"
    elif p["kind"] == "polynomial":
        text = f"polynomial, Δt = {p['dt']:g}, Δy = {p['dy']:g}, forward fraction {p['forward_fraction']:g}"
    else:
        text = f"{p['kind']}, Δt = {p['dt']:g}"
    surface = scene.surface.params()
    if surface["kind"] != "uniform":
        text += f"; stop zone x_mu = {surface['x_mu']:g}, w = {surface['w']:g}, c_mu = {surface['c_mu']:g}"
    return text


def _case(attrs: dict) -> str:
    return str(attrs["case"]) if "case" in attrs else NO_VALUE


def steady_state_rows(results: list[dict]) -> tuple[list[str], list[list[str]]]:
    """Steady states of the stability scenes (``results/stability/<scene>.h5``): the periodic
    motion the Floquet multipliers are taken about, its average velocity v̄ = advance / (k Δt)
    over its k periods and f = 1 / (c v̄²) (eq. 11)."""
    columns = ["scene", "setting", "case", "x(t0), x'(t0)", "periods k", "found by", "v̄", "f (eq. 11)"]
    rows = []
    for result in results:
        a = result["attrs"]
        vbar = a["advance"] / (a["orbit_periods"] * a["dt"])
        f = 1.0 / (OBJECTIVE_SCALE * vbar**2) if vbar else math.inf
        rows.append([a["scene_name"], setting_text(scene_from_result(result)), _case(a),
                     f"{a['x0']:.6g}, {a['v0']:.6g}", str(a["orbit_periods"]), a["orbit_source"],
                     f"{vbar:.6g}", "∞" if math.isinf(f) else f"{f:.4g}"])
    return columns, rows


def _fixed(value: float) -> str:
    """``value`` to 6 decimals, without the sign of a value that rounds to zero."""
    return f"{value:.6f}" if abs(value) >= 5e-7 else f"{0.0:.6f}"


def _multipliers(values) -> str:
    values = np.asarray(values)
    if np.all(values.imag == 0.0):
        return ", ".join(_fixed(v) for v in values.real)
    return ", ".join(f"{_fixed(v.real)}{'+' if v.imag >= 0 else '-'}{_fixed(abs(v.imag))}i" for v in values)


def _error(value: float) -> str:
    return "0" if value == 0.0 else f"{value:.1e}"


def floquet_rows(results: list[dict]) -> tuple[list[str], list[list[str]]]:
    """Floquet multipliers of the stability scenes by every method (Sect. 6.1,
    docs/explanation/stability.md), and the largest entry difference of each monodromy matrix from the
    reference (analytic where it applies, else saltation)."""
    columns = ["scene", "setting", "case", *FLOQUET_METHODS.values(), "reference",
               "max |ΔM|: " + " / ".join(list(FLOQUET_METHODS.values())[1:])]
    rows = []
    for result in results:
        d, a = result["datasets"], result["attrs"]
        methods = [str(m) for m in d["methods"]]
        shown = {m: _multipliers(d["multipliers"][methods.index(m)]) if m in methods else NO_VALUE
                 for m in FLOQUET_METHODS}
        errors = [_error(d["monodromy_error"][methods.index(m)]) if m in methods else NO_VALUE
                  for m in list(FLOQUET_METHODS)[1:]]
        rows.append([a["scene_name"], setting_text(scene_from_result(result)), _case(a), *shown.values(),
                     a["reference"], " / ".join(errors)])
    return columns, rows


def job_time_rows(paths: list[str]) -> tuple[list[str], list[list[str]]]:
    """Wall time, CPU time and peak memory of the jobs that write Snakemake ``benchmark:``
    files (``results/benchmarks/<stage>/<name>.tsv``, one run each)."""
    columns = ["job", "wall time [s]", "CPU time [s]", "max RSS [MB]"]
    rows = []
    for path in paths:
        header, values = Path(path).read_text().splitlines()[:2]
        record = dict(zip(header.split("\t"), values.split("\t")))
        job = Path(path).with_suffix("").as_posix().split("benchmarks/", 1)[-1]  # <stage>/<name>
        rows.append([job, f"{float(record['s']):.2f}", f"{float(record['cpu_time']):.2f}",
                     f"{float(record['max_rss']):.0f}"])
    return columns, rows


#: name -> (title, build(input paths) -> (columns, rows)).
TABLES = {
    "steady_states": ("Steady states of the stability scenes",
                      lambda paths: steady_state_rows([read_h5(p) for p in paths])),
    "floquet": ("Floquet multipliers (Sect. 6.1)", lambda paths: floquet_rows([read_h5(p) for p in paths])),
    "job_times": ("Job times of the last workflow run", job_time_rows),
}


def html_table(title: str, columns: list[str], rows: list[list[str]]) -> str:
    """A self-contained HTML page with ``title`` and the table (all text escaped)."""
    head = "".join(f"<th>{html.escape(c)}</th>" for c in columns)
    body = "\n".join("<tr>" + "".join(f"<td>{html.escape(cell)}</td>" for cell in row) + "</tr>" for row in rows)
    return (f"<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>{html.escape(title)}</title>\n"
            "<style>body{font-family:sans-serif;font-size:14px} table{border-collapse:collapse} "
            "th,td{border:1px solid #bbb;padding:3px 8px;text-align:left} th{background:#eee}</style>\n"
            f"</head><body>\n<h3>{html.escape(title)}</h3>\n<table>\n<tr>{head}</tr>\n{body}\n</table>\n"
            "</body></html>\n")


def build_table(name: str, paths: list[str]) -> str:
    """The HTML page of table ``name`` from its input files."""
    if name not in TABLES:
        raise ValueError(f"unknown table {name!r}; known: {', '.join(TABLES)}")
    title, build = TABLES[name]
    return html_table(title, *build(paths))
