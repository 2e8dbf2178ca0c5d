"""Fig. 7 (three-phase profile sketch) from a trajectory result."""

from selfalign.io.hdf5 import read_h5
from selfalign.stages.common import figure_07, logged, save_figure

with logged(snakemake.log[0]) as log:
    save_figure(figure_07(read_h5(snakemake.input[0])), snakemake.output[0], dpi=snakemake.params.dpi)
    log.info("figure 7 from %s written to %s", snakemake.input[0], snakemake.output[0])
