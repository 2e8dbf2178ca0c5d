"""Fig. 3 (Moreau time-stepping, polynomial profile: object and table) from a simulation result."""

from selfalign.pipeline import logged, save_figure
from selfalign.plots_simulation import figure_03
from selfalign.results import read_h5

with logged(snakemake.log[0]) as log:
    save_figure(figure_03(read_h5(snakemake.input[0])), snakemake.output[0], dpi=snakemake.params.dpi)
    log.info("figure 3 from %s written to %s", snakemake.input[0], snakemake.output[0])
