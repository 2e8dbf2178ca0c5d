"""Every benchmark of benchmarks/measure.py in one run -> results/benchmarks/table.md and raw JSON."""

import json
import sys
from pathlib import Path

sys.path.insert(0, str(Path.cwd() / "benchmarks"))
import measure  # noqa: E402

from selfalign.stages.common import logged

with logged(snakemake.log[0]) as log:
    # The pipeline timing copies Snakefile + workflow/ from the working directory (the repository top).
    report = measure.run(Path.cwd() if snakemake.params.full_pipeline else None, cores=snakemake.params.cores)
    table = measure.format_table(report)
    Path(snakemake.output.table).write_text(table + "\n")
    Path(snakemake.output.raw).write_text(json.dumps(report, indent=2) + "\n")
    log.info("benchmarks:\n%s", table)
