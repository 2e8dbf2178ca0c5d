"""A queue of parts at the stop zone (docs/explanation/queue.md) into results/parts/queue.h5."""

import numpy as np

from selfalign.io.hdf5 import read_h5, write_h5
from selfalign.stages.common import logged
from selfalign.stages.parts import queue_results

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    datasets, attrs, groups = queue_results(dict(p.settings), dict(p.zone), read_h5(snakemake.input[0]))
    write_h5(snakemake.output[0], datasets, attrs, groups, config=dict(p.items()))
    q = groups["queue"]["datasets"]
    log.info("single part at rest at %.12g; front part (N = 1..%d) at the first grid point: %s", q["x_single"],
             q["n"][-1], np.round(q["x_end"][0, 0, 0, :, 0], 9).tolist())
    d = groups["design_queue"]["datasets"]
    log.info("design %s: parts aligned per second %s; front errors [m] %s", groups["design_queue"]["attrs"]["spec"],
             np.round(d["throughput"], 4).tolist(), np.round(d["error"][:, 0], 7).tolist())
    log.info("written to %s", snakemake.output[0])
