"""Fig. 5 from results/classification/fig05.h5."""

from selfalign.io.hdf5 import read_h5
from selfalign.plots.classification import figure_05
from selfalign.stages.common import logged, save_figure

with logged(snakemake.log[0]) as log:
    save_figure(figure_05(read_h5(snakemake.input[0])), snakemake.output[0], dpi=snakemake.params.dpi)
    log.info("figure 5 from %s written to %s", snakemake.input[0], snakemake.output[0])
