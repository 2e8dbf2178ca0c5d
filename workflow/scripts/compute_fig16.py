"""Phase portraits and end positions of Fig. 16 (and Figs. 14/15) into results/accumulation/fig16.h5."""

from selfalign.analysis.positioning import fig16_content
from selfalign.io.hdf5 import write_h5
from selfalign.stages.common import logged

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    datasets, attrs, groups = fig16_content([tuple(pair) for pair in p.fig16_settings], dt=p.dt, dy=p.dy, w=p.w,
                                            c_mu=p.c_mu, n_entries=p.n_entries)
    write_h5(snakemake.output[0], datasets, attrs, groups)
    log.info("fig16: settings %s written to %s", sorted(groups), snakemake.output[0])
