"""Floquet multipliers by every method over a (y2'', y3'') grid into results/stability/grid_<name>.h5."""

import numpy as np

from selfalign.io.hdf5 import write_h5
from selfalign.stages.common import logged, range_values
from selfalign.stages.stability import stability_grid

with logged(snakemake.log[0]) as log:
    g = snakemake.params.grid
    datasets, attrs = stability_grid(g["dt"], g["dy"], range_values(g["y2"]), range_values(g["y3"]),
                                     g["moreau_steps"])
    attrs["grid"] = snakemake.wildcards.grid
    write_h5(snakemake.output[0], datasets, attrs, config=dict(snakemake.params.items()))
    for k, method in enumerate(datasets["methods"]):
        log.info("%s: max |M - M_analytic| = %.3g", method, np.nanmax(datasets["monodromy_error"][k]))
    log.info("written to %s", snakemake.output[0])
