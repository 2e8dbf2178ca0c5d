"""figures/planar_drift.<format> and figures/planar_alignment.<format> from results/planar/planar.h5
(rule plot_planar)."""

from selfalign.io.hdf5 import read_h5
from selfalign.plots.planar import alignment_figure, drift_figure
from selfalign.stages.common import logged, save_figure

with logged(snakemake.log[0]) as log:
    result = read_h5(snakemake.input[0])
    figures = {"planar_drift": drift_figure(result), "planar_alignment": alignment_figure(result)}
    for path in snakemake.output:
        save_figure(figures[next(name for name in figures if f"/{name}." in path)], path, dpi=snakemake.params.dpi)
    log.info("planar figures from %s written to %s", list(snakemake.input), list(snakemake.output))
