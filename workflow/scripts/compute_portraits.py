"""Phase portraits and end positions of Figs. 14-16 (Sects. 7.1-7.2) into results/accumulation/fig16.h5."""

from selfalign.io.hdf5 import write_h5
from selfalign.stages.accumulation import fig16_content
from selfalign.stages.common import logged

with logged(snakemake.log[0]) as log:
    p, zone, setting = snakemake.params.portraits, snakemake.params.zone, snakemake.params.setting
    datasets, attrs, groups = fig16_content([tuple(pair) for pair in p["settings"]], dt=setting["dt"],
                                            dy=setting["dy"], w=zone["w"], c_mu=zone["c_mu"],
                                            n_entries=p["n_entries"])
    write_h5(snakemake.output[0], datasets, attrs, groups, config=dict(snakemake.params.items()))
    log.info("fig16: settings %s written to %s", sorted(groups), snakemake.output[0])
