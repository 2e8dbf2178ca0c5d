"""Fig. 17 from results/accumulation/fig17.h5."""

from selfalign.io.hdf5 import read_h5
from selfalign.plots.accumulation import figure_17
from selfalign.stages.common import logged, save_figure

with logged(snakemake.log[0]) as log:
    save_figure(figure_17(read_h5(snakemake.input[0])), snakemake.output[0], dpi=snakemake.params.dpi)
    log.info("figure 17 written to %s", snakemake.output[0])
