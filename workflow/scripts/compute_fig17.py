"""Fig. 17 sweep (Sect. 7.2) with the batched exact solver: one shard (every n-th row of y2'',
interleaved because the cost lies at large y2'') into results/accumulation/shards/fig17_<i>.h5,
or the gathered results/accumulation/fig17.h5."""

import numpy as np

from selfalign.analysis.positioning import fig17_shard, gather_fig17
from selfalign.io.hdf5 import read_h5, write_h5
from selfalign.stages.common import logged, shard_rows

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    axis = np.linspace(*p.fig17_axis[:2], int(p.fig17_axis[2]))
    if snakemake.rule == "compute_fig17_shard":
        index = int(snakemake.wildcards.shard)
        rows = shard_rows(axis.size, p.shards, index, interleaved=True)
        datasets, attrs = fig17_shard(axis, axis, rows, dt=p.dt, dy=p.dy, w=p.w, c_mu=p.c_mu,
                                      n_entries=p.n_entries, max_periods=p.max_periods, levels=p.levels)
        write_h5(snakemake.output[0], datasets, attrs)
        log.info("fig17 shard %d: rows %d::%d of %d, %d entries each, %d events", index, rows.start, rows.step,
                 axis.size, p.n_entries, attrs["events"])
    else:
        datasets, attrs = gather_fig17(axis, axis, [read_h5(path) for path in snakemake.input])
        write_h5(snakemake.output[0], datasets, attrs)
        log.info("fig17: %d x %d settings from %d shards, %d events; written to %s", axis.size, axis.size,
                 len(snakemake.input), attrs["events"], snakemake.output[0])
