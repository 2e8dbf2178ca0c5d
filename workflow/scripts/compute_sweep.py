"""Figs. 4, 5: f of the polynomial profile along a dt or dy sweep into results/classification/<sweep>.h5."""

import numpy as np

from selfalign.io.hdf5 import write_h5
from selfalign.stages.classification import polynomial_sweep
from selfalign.stages.common import logged, range_values

with logged(snakemake.log[0]) as log:
    sweep, poly = snakemake.params.sweep, snakemake.params.polynomial
    swept = next(k for k, v in sweep.items() if isinstance(v, dict))
    values = {k: range_values(v) if k == swept else v for k, v in sweep.items()}
    datasets, attrs = polynomial_sweep(values["dt"], values["dy"], forward_fraction=poly["forward_fraction"],
                                       steps_per_period=poly["moreau_steps_per_period"],
                                       iteration=poly["moreau_iteration"])
    attrs["swept"] = swept
    write_h5(snakemake.output[0], datasets, attrs, config=dict(snakemake.params.items()))
    log.info("%s: %d points, max |f_moreau / f_exact - 1| = %.3g; written to %s", snakemake.wildcards.sweep,
             datasets["dt"].size, np.max(np.abs(datasets["f_moreau"] / datasets["f_exact"] - 1)),
             snakemake.output[0])
