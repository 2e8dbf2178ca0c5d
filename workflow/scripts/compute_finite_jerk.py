"""The finite-jerk study (docs/explanation/model.md) into results/finite_jerk/finite_jerk.h5."""

import numpy as np

from selfalign.io.hdf5 import write_h5
from selfalign.stages.common import logged
from selfalign.stages.finite_jerk import finite_jerk_results

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    datasets, attrs, groups = finite_jerk_results(p.ramp_fractions, p.steady, p.stopping, p.zone)
    write_h5(snakemake.output[0], datasets, attrs, groups, config=dict(p.items()))
    for name, group in groups.items():
        shown = group["datasets"]["vbar" if "vbar" in group["datasets"] else "dx_d"]
        log.info("%s: cells with a result per ramp fraction %s", name, np.isfinite(shown).sum(axis=(1, 2)).tolist())
    log.info("written to %s", snakemake.output[0])
