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


def summary(steady, stopping) -> list[str]:
    lines = []
    base_v, base_case = steady.vbar[0], steady.case[0]
    base_acc, base_dx = stopping.frac_accumulate[0] > 0, stopping.dx_d[0]
    i, j = np.unravel_index(np.nanargmax(base_v), base_v.shape)
    lines.append(f"tau 0: max vbar {base_v[i, j]:.5g} at y2 = {steady.y2[i]:.3g}, y3 = {steady.y3[j]:.3g}; "
                 f"{int(np.sum(base_acc))} accumulation cells, "
                 f"{int(np.sum(base_acc & (stopping.y2[:, None] > stopping.y3)))} of them with y2 > y3")
    for k, fraction in enumerate(steady.ramp_fractions[1:].tolist(), start=1):
        moving = (base_v > 0) & (steady.vbar[k] > 0)
        rel = steady.vbar[k][moving] / base_v[moving] - 1.0
        both = (base_case > 0) & (steady.case[k] > 0)
        i, j = np.unravel_index(np.nanargmax(steady.vbar[k]), base_v.shape)
        acc = stopping.frac_accumulate[k] > 0
        known = np.isfinite(stopping.frac_accumulate[k]) & np.isfinite(stopping.frac_accumulate[0])
        above = acc & (stopping.y2[:, None] <= stopping.y3)
        dx = stopping.dx_d[k] / base_dx - 1.0
        lines.append(
            f"tau {100 * fraction:g} %: vbar change median {np.median(rel):+.3%}, "
            f"range [{rel.min():+.2%}, {rel.max():+.2%}] over {rel.size} moving cells; "
            f"max vbar {steady.vbar[k][i, j]:.5g} at y2 = {steady.y2[i]:.3g}, "
            f"y3 = {steady.y3[j]:.3g}; case changed in {int(np.sum(both & (steady.case[k] != base_case)))} of "
            f"{int(np.sum(both))} cells, ramps too long in {int(np.sum(steady.case[k] < 0))}; accumulation cells "
            f"{int(np.sum(acc))} (changed {int(np.sum(known & (acc != base_acc)))} of {int(np.sum(known))}, "
            f"{int(np.sum(above))} with y2 <= y3); dx_d change median {np.nanmedian(dx):+.2%}, "
            f"range [{np.nanmin(dx):+.2%}, {np.nanmax(dx):+.2%}]")
    return lines


def main(out: Path) -> None:
    out.mkdir(parents=True, exist_ok=True)
    steady = steady_grid(1.38, 0.064, np.linspace(0.1, 3.0, 24), np.linspace(0.1, 3.0, 24), FRACTIONS)
    stopping = stopping_grid(1.0, 0.084, np.linspace(0.5, 2.5, 21), np.linspace(0.5, 2.5, 21), FRACTIONS,
                             w=0.05, c_mu=2.5)
    np.savez(out / "finite_jerk.npz", ramp_fractions=steady.ramp_fractions, steady_y2=steady.y2,
             steady_y3=steady.y3, vbar=steady.vbar, case=steady.case, stopping_y2=stopping.y2,
             stopping_y3=stopping.y3, frac_accumulate=stopping.frac_accumulate, frac_rest=stopping.frac_rest,
             dx_d=stopping.dx_d)
    fig = finite_jerk_figure(Figure(figsize=(18, 15), layout="constrained"), steady, stopping)
    fig.savefig(out / "finite_jerk.png", dpi=100)
    print("\n".join(summary(steady, stopping)))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: python benchmarks/finite_jerk_study.py OUT_DIR")
    main(Path(sys.argv[1]))
