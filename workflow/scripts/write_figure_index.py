"""figures/README.md: every figure, its files and its rendered caption (rule write_figure_index,
workflow/rules/report.smk)."""

from pathlib import Path

from selfalign.io.hdf5 import atomic_write
from selfalign.stages.captions import figure_index, render_caption
from selfalign.stages.common import logged

with logged(snakemake.log[0]) as log:
    figures = [{**f, "caption": render_caption(Path(f["caption"]).read_text(), snakemake.config, f["options"])}
               for f in snakemake.params.figures]
    text = figure_index(figures, list(snakemake.params.formats))
    atomic_write(snakemake.output[0], lambda tmp: Path(tmp).write_text(text))
    log.info("index of %d figures written to %s", len(figures), snakemake.output[0])
