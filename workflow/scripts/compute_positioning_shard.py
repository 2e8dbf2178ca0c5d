"""One shard of the Fig. 17 positioning sweep (Sect. 7.2) with the batched exact solver into
results/accumulation/shards/fig17_<shard>.h5: every n-th row of y2'' (interleaved, because
the cost lies at large y2'')."""

from selfalign.io.hdf5 import write_h5
from selfalign.stages.accumulation import fig17_shard
from selfalign.stages.common import logged, range_values, shard_rows

with logged(snakemake.log[0]) as log:
    p, zone = snakemake.params.positioning, snakemake.params.zone
    y2, y3 = range_values(p["y2"]), range_values(p["y3"])
    index = int(snakemake.wildcards.shard)
    rows = shard_rows(y2.size, p["shards"], index, interleaved=True)
    datasets, attrs = fig17_shard(y2, y3, rows, dt=p["dt"], dy=p["dy"], w=zone["w"], c_mu=zone["c_mu"],
                                  n_entries=p["n_entries"], max_periods=p["max_periods"], levels=p["levels"])
    write_h5(snakemake.output[0], datasets, attrs, config=dict(snakemake.params.items()))
    log.info("fig17 shard %d: rows %d::%d of %d, %d entries each, %d events", index, rows.start, rows.step,
             y2.size, p["n_entries"], attrs["events"])
