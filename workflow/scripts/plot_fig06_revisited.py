"""figures/fig06_revisited.<format> from results/optimal_motion/fig06_revisited.h5 (rule plot_fig06_revisited)."""

from selfalign.io.hdf5 import read_h5
from selfalign.plots.optimal_motion import figure_fig06_revisited
from selfalign.stages.common import logged, save_figure

with logged(snakemake.log[0]) as log:
    fig = figure_fig06_revisited(read_h5(snakemake.input[0]))
    for path in snakemake.output:
        save_figure(fig, path, dpi=snakemake.params.dpi)
    log.info("fig06_revisited from %s written to %s", list(snakemake.input), list(snakemake.output))
