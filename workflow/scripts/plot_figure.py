"""figures/<name>.<format> from its result files, one file per output (rules plot_<name>,
workflow/rules/figures.smk)."""

from selfalign.io.hdf5 import read_h5
from selfalign.stages.common import logged, save_figure
from selfalign.stages.figures import draw

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    fig = draw(p.figure, [read_h5(path) for path in snakemake.input], **p.options)
    for path in snakemake.output:
        save_figure(fig, path, dpi=p.dpi)
    log.info("%s from %s written to %s", p.figure, list(snakemake.input), list(snakemake.output))
