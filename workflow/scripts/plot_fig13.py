"""Fig. 13 (convergence of two velocity transients, Sect. 6.2) from a convergence result."""

from selfalign.io.hdf5 import read_h5
from selfalign.plots.stability import figure_13
from selfalign.stages.common import logged, save_figure

with logged(snakemake.log[0]) as log:
    save_figure(figure_13(read_h5(snakemake.input[0])), snakemake.output[0], dpi=snakemake.params.dpi)
    log.info("figure 13 from %s written to %s", snakemake.input[0], snakemake.output[0])
