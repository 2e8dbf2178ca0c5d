"""figures/parts_queue.<format> and figures/parts_motion.<format> from results/parts/queue.h5 (rule plot_queue)."""

from selfalign.io.hdf5 import read_h5
from selfalign.plots.parts import motion_figure, queue_figure
from selfalign.stages.common import logged, save_figure

with logged(snakemake.log[0]) as log:
    result = read_h5(snakemake.input[0])
    figures = {"parts_queue": queue_figure(result), "parts_motion": motion_figure(result)}
    for path in snakemake.output:
        save_figure(figures[next(name for name in figures if f"/{name}." in path)], path, dpi=snakemake.params.dpi)
    log.info("queue figures from %s written to %s", list(snakemake.input), list(snakemake.output))
