"""Fig. 18 from results/accumulation/fig18.h5."""

from selfalign.io.hdf5 import read_h5
from selfalign.plots.accumulation import figure_18
from selfalign.stages.common import logged, save_figure

with logged(snakemake.log[0]) as log:
    save_figure(figure_18(read_h5(snakemake.input[0])), snakemake.output[0], dpi=snakemake.params.dpi)
    log.info("figure 18 written to %s", snakemake.output[0])
