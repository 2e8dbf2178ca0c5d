"""Fig. 17 sweep (Sect. 7.2) into results/accumulation/fig17.h5 with the batched exact solver."""

import numpy as np

from selfalign.pipeline import logged
from selfalign.results import write_h5
from selfalign.stopping import fig17_content

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    axis = np.linspace(*p.fig17_axis[:2], int(p.fig17_axis[2]))
    datasets, attrs = fig17_content(axis, axis, dt=p.dt, dy=p.dy, w=p.w, c_mu=p.c_mu, n_entries=p.n_entries,
                                    max_periods=p.max_periods, levels=p.levels, processes=snakemake.threads)
    write_h5(snakemake.output[0], datasets, attrs)
    log.info("fig17: %d x %d settings, %d entries each, %d events; written to %s", axis.size, axis.size,
             p.n_entries, attrs["events"], snakemake.output[0])
