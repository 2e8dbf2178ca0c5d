"""One shard (a row block of y2'') of a (y2'', y3'') map of Figs. 10, 11 into
results/classification/shards/<map>_<shard>.h5."""

from selfalign.io.hdf5 import write_h5
from selfalign.stages.classification import map_shard
from selfalign.stages.common import logged, range_values, shard_rows

with logged(snakemake.log[0]) as log:
    m = snakemake.params.map
    y2, y3 = range_values(m["y2"]), range_values(m["y3"])
    index = int(snakemake.wildcards.shard)
    rows = shard_rows(y2.size, m["shards"], index)
    write_h5(snakemake.output[0], map_shard(m["dt"], m["dy"], y2, y3, rows),
             {"row_start": rows.start, "row_stop": rows.stop}, config=dict(snakemake.params.items()))
    log.info("shard %d: rows %d:%d of %d", index, rows.start, rows.stop, y2.size)
