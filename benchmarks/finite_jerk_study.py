"""What finite jerk does to the paper's results: the numbers and figure of README "Finite jerk".

Run:  python benchmarks/finite_jerk_study.py OUT_DIR

For ramps of y'' of 0, 1, 5 and 10 % of the period: vbar and the case of Table 1 over the
Fig. 11 plane (dt = 1.38, dy = 0.064, y2'', y3'' in [0.1, 3], 24 x 24, exact solver) and the
stopping of 16 steady-state entries into the stop zone (w = 0.05, c_mu = 2.5) over the Fig. 17
plane (dt = 1, dy = 0.084, y2'', y3'' in [0.5, 2.5], 21 x 21, Moreau with dt/10^4).  Writes
OUT_DIR/finite_jerk.npz and OUT_DIR/finite_jerk.png and prints the summary.  Not part of the
Snakemake workflow (a study of the model's robustness, not a figure of the paper).
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure

from selfalign.analysis.finite_jerk import steady_grid, stopping_grid
from selfalign.plots.finite_jerk import finite_jerk_figure

FRACTIONS = (0.0, 0.01, 0.05, 0.10)
C_MU = 2.5


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
    steady = steady_grid(1.38, 0.064, np.linspace(0.1, 3.0, 24), np.linspace(0.1, 3.0, 24), FRACTIONS)
    stopping = stopping_grid(1.0, 0.084, np.linspace(0.5, 2.5, 21), np.linspace(0.5, 2.5, 21), FRACTIONS,
                             w=0.05, c_mu=C_MU)
    np.savez(out / "finite_jerk.npz", ramp_fractions=steady.ramp_fractions, steady_y2=steady.y2,
             steady_y3=steady.y3, vbar=steady.vbar, case=steady.case, stopping_y2=stopping.y2,
             stopping_y3=stopping.y3, frac_accumulate=stopping.frac_accumulate, frac_rest=stopping.frac_rest,
             dx_d=stopping.dx_d)
    fig = finite_jerk_figure(Figure(figsize=(18, 15), layout="constrained"), steady, stopping)
    fig.savefig(out / "finite_jerk.png", dpi=100)
    print("\n".join(summary(steady, stopping, C_MU)))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: python benchmarks/finite_jerk_study.py OUT_DIR")
    main(Path(sys.argv[1]))
