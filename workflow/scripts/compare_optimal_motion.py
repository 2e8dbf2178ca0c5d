"""Fig. 6 revisited (docs/explanation/fig6-revisited.md) into results/optimal_motion/fig06_revisited.h5."""

from selfalign.io.hdf5 import write_h5
from selfalign.stages.common import logged
from selfalign.stages.optimal_motion import fig06_revisited_results

with logged(snakemake.log[0]) as log:
    settings = dict(snakemake.params.settings)
    datasets, attrs, groups = fig06_revisited_results(settings)
    write_h5(snakemake.output[0], datasets, attrs, groups, config=dict(snakemake.params.items()))
    c = groups["comparison"]["datasets"]
    for entry, vbar, share in zip(c["entry"].tolist(), c["vbar"].tolist(), c["share_of_optimum"].tolist()):
        log.info("%s: vbar = %.6g (%.3g of the optimum)", entry, vbar, share)
    log.info("written to %s", snakemake.output[0])
