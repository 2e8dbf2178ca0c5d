"""Work-precision figure (error against CPU time, all methods) from the accuracy results."""

from selfalign.io.hdf5 import read_h5
from selfalign.plots.simulation import figure_accuracy_cost
from selfalign.stages.common import logged, save_figure

with logged(snakemake.log[0]) as log:
    fig = figure_accuracy_cost([read_h5(path) for path in snakemake.input])
    save_figure(fig, snakemake.output[0], dpi=snakemake.params.dpi)
    log.info("work-precision figure from %s written to %s", list(snakemake.input), snakemake.output[0])
