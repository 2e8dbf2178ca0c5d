"""What finite jerk does to the paper's results: the numbers and figure of docs/explanation/model.md.

Run:  python benchmarks/finite_jerk_study.py OUT_DIR

The workflow's stage (selfalign.stages.finite_jerk, rule compute_finite_jerk) on finer grids:
for ramps of y'' of 0, 1, 5 and 10 % of the period, vbar and the case of Table 1 over the
Fig. 10 plane (dt = 0.072, dy = 0.021, y2'' in [20, 1500], y3'' in [20, 300]) and the Fig. 11
plane (dt = 1.38, dy = 0.064, y2'', y3'' in [0.1, 3]), 24 x 24 each, exact solver, and the
stopping of 16 steady-state entries into the stop zone (w = 0.05, c_mu = 2.5) over the Fig. 17
plane (dt = 1, dy = 0.084, y2'', y3'' in [0.5, 2.5], 21 x 21, exact solver).  Writes
OUT_DIR/finite_jerk.h5, OUT_DIR/finite_jerk.png (the steady planes) and OUT_DIR/finite_jerk_stopping.png
(the stop zone) and prints the summary of the Fig. 11 and
Fig. 17 planes.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

from selfalign.io.hdf5 import write_h5
from selfalign.stages.common import save_figure
from selfalign.stages.figures import draw
from selfalign.stages.finite_jerk import finite_jerk_results, grids_from_result

FRACTIONS = (0.0, 0.01, 0.05, 0.10)
ZONE = {"w": 0.05, "c_mu": 2.5}


def axis(lo: float, hi: float, count: int) -> dict:
    return {"from": lo, "to": hi, "count": count, "scale": "linear"}


STEADY = {"fig10": {"dt": 0.072, "dy": 0.021, "y2": axis(20.0, 1500.0, 24), "y3": axis(20.0, 300.0, 24)},
          "fig11": {"dt": 1.38, "dy": 0.064, "y2": axis(0.1, 3.0, 24), "y3": axis(0.1, 3.0, 24)}}
STOPPING = {"dt": 1.0, "dy": 0.084, "y2": axis(0.5, 2.5, 21), "y3": axis(0.5, 2.5, 21), "n_entries": 16,
            "max_periods": 1000}


def summary(steady, stopping, c_mu: float) -> list[str]:
    """One line per ramp: vbar against the paper's (cells moving in both), the largest vbar, the
    cases, the accumulation region and Delta x_d.  The column y2'' = c_mu (a tie: x_stick_min is
    the zone's end) is left out of the accumulation counts."""
    lines = []
    base_v, base_case = steady.vbar[0], steady.case[0]
    y2, y3 = stopping.y2[:, None], stopping.y3[None, :]
    regular = np.broadcast_to(y2 < c_mu, stopping.dx_d[0].shape)
    base_acc = stopping.frac_accumulate[0] > 0
    for k, fraction in enumerate(steady.ramp_fractions.tolist()):
        moving = (base_v > 0) & (steady.vbar[k] > 0)
        rel = steady.vbar[k][moving] / base_v[moving] - 1.0
        both = (base_case > 0) & (steady.case[k] > 0)
        i, j = np.unravel_index(np.nanargmax(steady.vbar[k]), base_v.shape)
        known = regular & np.isfinite(stopping.frac_accumulate[k])
        acc = known & (stopping.frac_accumulate[k] > 0)
        changed = known & np.isfinite(stopping.frac_accumulate[0]) & (acc != base_acc)
        with np.errstate(divide="ignore", invalid="ignore"):
            dx = stopping.dx_d[k] / stopping.dx_d[0] - 1.0
        dx = dx[regular & (stopping.dx_d[0] > 0) & np.isfinite(dx)]
        smallest = float(np.min(np.broadcast_to(y2, acc.shape)[acc]))
        lines.append(
            f"ramp {100 * fraction:g} %: vbar change median {np.median(rel):+.1%} (10-90 %: "
            f"{np.percentile(rel, 10):+.1%} .. {np.percentile(rel, 90):+.1%}) over {rel.size} cells; "
            f"max vbar {steady.vbar[k][i, j]:.4g} at y2 = {steady.y2[i]:.3g}, y3 = {steady.y3[j]:.3g}; "
            f"case changed in {int(np.sum(both & (steady.case[k] != base_case)))} of {int(np.sum(both))} cells, "
            f"ramps do not fit in {int(np.sum(steady.case[k] < 0))}; accumulation in {int(np.sum(acc))} of "
            f"{int(np.sum(known))} cells ({int(np.sum(changed))} changed), {int(np.sum(acc & (y2 < y3)))} with "
            f"y2 < y3, {int(np.sum(acc & (y2 == y3)))} with y2 = y3, smallest y2 {smallest:.3g}; "
            f"max dx_d {np.nanmax(np.where(regular, stopping.dx_d[k], np.nan)):.3g}, change median "
            f"{np.median(dx) if dx.size else np.nan:+.1%} over {dx.size} cells")
    return lines


def main(out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    content = finite_jerk_results(FRACTIONS, STEADY, STOPPING, ZONE)
    path = write_h5(out / "finite_jerk.h5", *content,
                    config={"ramp_fractions": list(FRACTIONS), "steady": STEADY, "stopping": STOPPING, "zone": ZONE})
    datasets, _, groups = content
    result = {"datasets": datasets, "groups": groups}
    steady, stopping = grids_from_result(result)
    for name in ("finite_jerk", "finite_jerk_stopping"):
        save_figure(draw(name, [result]), out / f"{name}.png", dpi=100)
    print(f"written to {path}")
    print("\n".join(summary(steady["fig11"], stopping, ZONE["c_mu"])))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: python benchmarks/finite_jerk_study.py OUT_DIR")
    main(Path(sys.argv[1]))
