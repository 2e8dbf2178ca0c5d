"""Fig. 11 from results/classification/fig11.h5."""

from selfalign.io.hdf5 import read_h5
from selfalign.plots.classification import figure_map
from selfalign.stages.common import logged, save_figure

with logged(snakemake.log[0]) as log:
    fig = figure_map(read_h5(snakemake.input[0]), snakemake.params.f_max)
    save_figure(fig, snakemake.output[0], dpi=snakemake.params.dpi)
    log.info("figure 11 from %s written to %s", snakemake.input[0], snakemake.output[0])
