"""Floquet multipliers by every method into results/stability/<scene>.h5, or over a
(y2'', y3'') grid into results/stability/grid_<name>.h5."""

import numpy as np

from selfalign import load_scene
from selfalign.analysis.floquet import stability_grid, stability_result
from selfalign.io.hdf5 import write_h5
from selfalign.stages.common import logged

with logged(snakemake.log[0]) as log:
    if snakemake.rule == "compute_stability_grid":
        g = snakemake.params.grid
        axes = {k: np.linspace(g[k]["from"], g[k]["to"], g[k]["count"]) for k in ("y2", "y3")}
        datasets, attrs = stability_grid(g["dt"], g["dy"], axes["y2"], axes["y3"], snakemake.params.moreau_steps)
        attrs["grid"] = snakemake.wildcards.grid
    else:
        scene = load_scene(snakemake.input.scene)
        datasets, attrs = stability_result(scene, snakemake.params.moreau_steps, snakemake.params.moreau_eps)
    write_h5(snakemake.output[0], datasets, attrs)
    for k, method in enumerate(datasets["methods"]):
        log.info("%s: max |M - M_%s| = %.3g", method, datasets["methods"][0],
                 np.nanmax(datasets["monodromy_error"][k]))
    log.info("written to %s", snakemake.output[0])
