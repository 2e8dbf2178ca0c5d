"""Fig. 3 (Moreau time-stepping, polynomial profile: object and table) from a simulation result."""

from selfalign.io.hdf5 import read_h5
from selfalign.plots.simulation import figure_03
from selfalign.stages.common import logged, save_figure

with logged(snakemake.log[0]) as log:
    save_figure(figure_03(read_h5(snakemake.input[0])), snakemake.output[0], dpi=snakemake.params.dpi)
    log.info("figure 3 from %s written to %s", snakemake.input[0], snakemake.output[0])
