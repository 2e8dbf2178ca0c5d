"""results/tables/<name>.html from existing results (rules tabulate_<name>, workflow/rules/report.smk)."""

from pathlib import Path

from selfalign.io.hdf5 import atomic_write
from selfalign.stages.common import logged
from selfalign.stages.tables import build_table

with logged(snakemake.log[0]) as log:
    page = build_table(snakemake.params.table, list(snakemake.input))
    atomic_write(snakemake.output[0], lambda tmp: Path(tmp).write_text(page, encoding="utf-8"))
    log.info("table %s from %d files written to %s", snakemake.params.table, len(snakemake.input),
             snakemake.output[0])
