"""Fig. 15 from results/accumulation/fig16.h5 (the setting named in the rule's params)."""

from selfalign.io.hdf5 import read_h5
from selfalign.plots.accumulation import figure_15
from selfalign.stages.common import logged, save_figure

with logged(snakemake.log[0]) as log:
    fig = figure_15(read_h5(snakemake.input[0]), snakemake.params.setting)
    save_figure(fig, snakemake.output[0], dpi=snakemake.params.dpi)
    log.info("figure 15 (%s) written to %s", snakemake.params.setting, snakemake.output[0])
