"""Accumulation and Delta x_d under static friction mu_s = r mu_k into results/effects/static_friction.h5."""

from selfalign.io.hdf5 import write_h5
from selfalign.stages.common import logged, range_values
from selfalign.stages.effects import static_friction_content

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    s, zone = p.study, p.zone
    datasets, attrs, groups = static_friction_content(
        range_values(s["y2"]), range_values(s["y3"]), s["ratios"], s["settings"], range_values(s["excess"]),
        dt=p.setting["dt"], dy=p.setting["dy"], w=zone["w"], c_mu=zone["c_mu"], n_entries=s["n_entries"],
        sweep_entries=s["sweep_entries"], max_periods=s["max_periods"])
    write_h5(snakemake.output[0], datasets, attrs, groups, config=dict(p.items()))
    log.info("static friction: r = %s over %d x %d settings, %d swept settings, %d events; written to %s",
             s["ratios"], datasets["y2"].size, datasets["y3"].size, len(s["settings"]), attrs["events"],
             snakemake.output[0])
