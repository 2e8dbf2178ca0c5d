"""vbar, accumulation and Delta x_d under the Stribeck law against v_s into results/effects/stribeck.h5."""

from selfalign.io.hdf5 import write_h5
from selfalign.stages.common import logged, range_values
from selfalign.stages.effects import stribeck_content

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    s, zone = p.study, p.zone
    datasets, attrs, groups = stribeck_content(
        range_values(s["v_s"]), ratio=s["ratio"], delta=s["delta"], steps_per_period=s["steps_per_period"],
        steady=s["steady"], entries={**s["stopping"], **p.setting, "w": zone["w"], "c_mu": zone["c_mu"]})
    write_h5(snakemake.output[0], datasets, attrs, groups, config=dict(p.items()))
    log.info("Stribeck friction: r = %g, delta = %g, %d values of v_s, %d steady and %d stopping settings; "
             "written to %s", s["ratio"], s["delta"], datasets["v_s_fraction"].size, len(s["steady"]["settings"]),
             len(s["stopping"]["settings"]), snakemake.output[0])
