"""A design spec of workflow/designs/ designed, with its design map, into results/design/<spec>.h5."""

from selfalign.io.design_report import design_report
from selfalign.io.hdf5 import write_h5
from selfalign.stages.common import logged
from selfalign.stages.design import design_results

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    content, result = design_results(snakemake.input[0], map_refine=p.map["refine"], map_entries=p.map["entries"])
    write_h5(snakemake.output[0], *content, config=dict(p.items()))
    log.info("%s\nwritten to %s", design_report(result), snakemake.output[0])
