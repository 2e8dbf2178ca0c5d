"""What the fastest table motion costs to find, beside the optimisations a user would otherwise run.

Run from the repository top:  .venv/bin/python benchmarks/optimal_motion.py [--json FILE]

For each setting of limits, side by side in one run:
- the paper's family: the best three-phase profile (Sect. 4.4.3), found by a grid search over
  y2'' and y3'' at the given stroke (``best_three_phase``, closed forms of Sect. 5);
- the paper's method: SQP over a Fourier series of y of order 4, 8 and 12 (Sect. 4.4.2, Fig. 6),
  every steady state from the exact solver (``optimise_fourier``);
- ``selfalign.optimal_profile``: the proven optimum under the acceleration limit, searched under
  the stroke and speed limits (docs/explanation/optimal-motion.md).

For each of them, the table gives v̄ (eq. 10, from the exact solver), its ratio to
``optimal_profile``'s, and the CPU time.  The first row compiles nothing: the solver kernels
are compiled and cached by a warm-up call before the clock starts.
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

import selfalign as sa
from selfalign.analysis.fourier_design import best_three_phase, optimise_fourier
from selfalign.analysis.optimal_motion import steady_mean_velocity

#: (name, period, stroke, peak table speed, largest |y''|): the paper's Fig. 6 constraints, and a
#: slow table at the friction scale (T = 1) with the stroke of Sect. 7.
SETTINGS = (
    ("Fig. 6 (Sect. 4.4.2)", 0.072, 0.021, 3.2, 1275.0),
    ("T = 1, stroke 0.084, a = 3", 1.0, 0.084, 10.0, 3.0),
)
ORDERS = (4, 8, 12)
#: SQP iterations, Fig. 6's budget (workflow config, stages.classification.fourier.max_iter).
MAX_ITER = 130


def _timed(func):
    start = time.process_time()
    value = func()
    return value, time.process_time() - start


def compare(period: float, stroke: float, speed: float, accel: float) -> list[dict]:
    """One row per method: its name, v̄ and CPU seconds; the optimum's row last."""
    rows = []
    three, seconds = _timed(lambda: best_three_phase(period, stroke, accel, speed))
    rows.append({"method": "paper's family (three-phase, grid)", "vbar": float(steady_mean_velocity([three])[0]),
                 "cpu_s": seconds})
    for order in ORDERS:
        opt, seconds = _timed(lambda: optimise_fourier(period, stroke, speed, accel, order=order, max_iter=MAX_ITER,
                                                    progress="quiet"))
        rows.append({"method": f"paper's method (Fourier order {order}, SQP)", "vbar": float(opt.vbar),
                     "cpu_s": seconds})
    best, seconds = _timed(lambda: sa.optimal_profile(period, accel, stroke_max=stroke, velocity_max=speed))
    rows.append({"method": "optimal_profile", "vbar": float(best.vbar), "cpu_s": seconds, "family": best.family,
                 "binding": list(best.binding)})
    for row in rows:
        row["ratio"] = row["vbar"] / best.vbar
    return rows


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", type=Path, help="also write the raw numbers to this file")
    args = parser.parse_args(argv)
    sa.optimal_profile(1.0, 3.0)  # compile and cache the solver kernels before any clock starts
    report = {}
    for name, *limits in SETTINGS:
        report[name] = rows = compare(*limits)
        print(f"\n{name}: period, stroke <= , |y'| <=, |y''| <= {limits}")
        print(f"| {'method':<52} | {'vbar':>10} | {'/ optimum':>9} | {'CPU s':>7} |")
        for row in rows:
            print(f"| {row['method']:<52} | {row['vbar']:10.5g} | {row['ratio']:9.3f} | {row['cpu_s']:7.2f} |")
        print(f"optimal_profile: family {rows[-1]['family']}, binding {rows[-1]['binding']}")
    if args.json:
        args.json.write_text(json.dumps(report, indent=2))
    return report


if __name__ == "__main__":
    main()
