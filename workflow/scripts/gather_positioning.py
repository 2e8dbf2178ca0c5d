"""The Fig. 17 positioning sweep results/accumulation/fig17.h5 from its shards."""

from selfalign.io.hdf5 import read_h5, write_h5
from selfalign.stages.accumulation import gather_fig17
from selfalign.stages.common import logged, range_values

with logged(snakemake.log[0]) as log:
    p = snakemake.params.positioning
    y2, y3 = range_values(p["y2"]), range_values(p["y3"])
    datasets, attrs = gather_fig17(y2, y3, [read_h5(path) for path in snakemake.input])
    write_h5(snakemake.output[0], datasets, attrs, config=dict(snakemake.params.items()))
    log.info("fig17: %d x %d settings from %d shards, %d events; written to %s", y2.size, y3.size,
             len(snakemake.input), attrs["events"], snakemake.output[0])
