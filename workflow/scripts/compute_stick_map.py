"""The accumulation map of Fig. 18 (eq. 59 and the exact solver, Sect. 7.3) into results/accumulation/fig18.h5."""

from selfalign.io.hdf5 import write_h5
from selfalign.model.profiles import ThreePhaseProfile
from selfalign.stages.accumulation import fig18_content
from selfalign.stages.common import logged

with logged(snakemake.log[0]) as log:
    s, zone = snakemake.params.stick_map, snakemake.params.zone
    profile = ThreePhaseProfile(s["dt"], s["dy"], s["y2"], s["y3"])
    datasets, attrs = fig18_content(profile, w=zone["w"], c_mu=zone["c_mu"], points=s["points"])
    write_h5(snakemake.output[0], datasets, attrs, config=dict(snakemake.params.items()))
    log.info("fig18: %r, x_stick_min %r, threshold %r; written to %s", profile, attrs["x_stick_min"],
             attrs["x_threshold"], snakemake.output[0])
