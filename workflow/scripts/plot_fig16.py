"""Fig. 16 (phase portraits, two entries per setting) from results/accumulation/fig16.h5."""

from selfalign.io.hdf5 import read_h5
from selfalign.plots.accumulation import figure_16
from selfalign.stages.common import logged, save_figure

with logged(snakemake.log[0]) as log:
    save_figure(figure_16(read_h5(snakemake.input[0]), snakemake.params.settings), snakemake.output[0],
                dpi=snakemake.params.dpi)
    log.info("figure 16 written to %s", snakemake.output[0])
