"""The (y2'', y3'') map results/classification/<map>.h5 of Fig. 10 or 11 from its shards."""

import numpy as np

from selfalign.io.hdf5 import read_h5, write_h5
from selfalign.stages.classification import gather_map
from selfalign.stages.common import logged, range_values

with logged(snakemake.log[0]) as log:
    m = snakemake.params.map
    y2, y3 = range_values(m["y2"]), range_values(m["y3"])
    datasets, attrs = gather_map(m["dt"], m["dy"], y2, y3, [read_h5(path)["datasets"] for path in snakemake.input])
    write_h5(snakemake.output[0], datasets, attrs, config=dict(snakemake.params.items()))
    log.info("%s: %d x %d map from %d shards, cases %s", snakemake.wildcards.map, y2.size, y3.size,
             len(snakemake.input), sorted(set(np.unique(datasets["case"]).tolist())))
