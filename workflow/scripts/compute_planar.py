"""Drift and self-alignment in the plane (docs/explanation/planar-alignment.md) into results/planar/planar.h5."""

import numpy as np

from selfalign.io.hdf5 import write_h5
from selfalign.stages.common import logged
from selfalign.stages.planar import planar_results

with logged(snakemake.log[0]) as log:
    p = snakemake.params
    datasets, attrs, groups = planar_results(dict(p.settings))
    write_h5(snakemake.output[0], datasets, attrs, groups, config=dict(p.items()))
    for name in ("limit_three_phase", "limit_harmonic"):
        d = groups[name]["datasets"]
        log.info("%s: error of the high-acceleration limit %s, fitted slope %.4f", name,
                 np.round(d["error"], 6).tolist(), d["slope"])
    for name in ("line_along", "line_planar"):
        d = groups[name]["datasets"]
        log.info("%s: Delta x_d along n %s, along the strip %s, accumulated %s", name,
                 np.round(d["dx_d_normal"], 9).tolist(), np.round(d["dx_d_slide"], 9).tolist(),
                 np.round(d["at_limit"], 3).tolist())
    log.info("corner: largest distance from the corner point %.6g", groups["corner"]["datasets"]["spread_radius"])
    log.info("written to %s", snakemake.output[0])
