"""All benchmarks in one run, printed as the one table of docs/explanation/performance.md.

Run from the repository top:  .venv/bin/python benchmarks/run_all.py [--no-pipeline] [--tiny] [--json FILE]
Exact vs Moreau at equal accuracy, single-trajectory events/s, batched sweep throughput
next to the arithmetic bound, the work-precision of several parts against Siconos (its figure to
results/benchmarks/parts_work_precision.png), the full `snakemake -c2` pipeline from a clean results/
(in a temporary copy of the workflow), and peak memory, with the machine description.
The measurements are `benchmarks/measure.py`; the workflow runs the same via
`snakemake -c2 benchmarks`.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import measure

REPO = Path(__file__).resolve().parent.parent


def main(argv=None) -> dict:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-pipeline", action="store_true", help="skip the full-pipeline timing")
    parser.add_argument("--tiny", action="store_true", help="tiny sizes: checks that everything runs")
    parser.add_argument("--cores", type=int, default=2, help="cores of the pipeline run (default 2)")
    parser.add_argument("--json", type=Path, help="also write the raw numbers to this file")
    args = parser.parse_args(argv)
    report = measure.run(None if args.no_pipeline else REPO, tiny=args.tiny, cores=args.cores,
                         figure=REPO / "results" / "benchmarks" / "parts_work_precision.png")
    print(measure.format_table(report))
    if args.json:
        args.json.write_text(json.dumps(report, indent=2))
    return report


if __name__ == "__main__":
    main()
