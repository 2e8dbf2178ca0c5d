"""Every benchmark of selfalign.benchmarks in one run -> results/benchmarks/table.md and raw JSON."""

import json
from pathlib import Path

from selfalign import benchmarks
from selfalign.pipeline import logged

with logged(snakemake.log[0]) as log:
    # The pipeline timing copies Snakefile + workflow/ from the working directory (the repository top).
    report = benchmarks.run(Path.cwd() if snakemake.params.full_pipeline else None, cores=snakemake.params.cores)
    table = benchmarks.format_table(report)
    Path(snakemake.output.table).write_text(table + "\n")
    Path(snakemake.output.raw).write_text(json.dumps(report, indent=2) + "\n")
    log.info("benchmarks:\n%s", table)
