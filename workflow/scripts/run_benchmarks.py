"""Every benchmark of benchmarks/measure.py in one run -> results/benchmarks/table.md and raw JSON."""

import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path.cwd() / "benchmarks"))
import measure  # noqa: E402

from selfalign.stages.common import logged

with logged(snakemake.log[0]) as log:
    # The pipeline timing copies Snakefile + workflow/ from the working directory (the repository top).
    # The work-precision figure against Siconos goes next to the table (not an output of the rule: it is
    # not drawn where Siconos, a benchmark-only dependency, is missing; the table then says why).
    report = measure.run(Path.cwd() if snakemake.params.full_pipeline else None, cores=snakemake.params.cores,
                         figure=Path(snakemake.output.table).with_name("parts_work_precision.png"))
    table = measure.format_table(report)
    Path(snakemake.output.table).write_text(table + "\n")
    Path(snakemake.output.raw).write_text(json.dumps(report, indent=2) + "\n")
    log.info("benchmarks:\n%s", table)
