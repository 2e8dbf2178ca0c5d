"""Floquet multipliers of a scene's steady state by every method into results/stability/<scene>.h5."""

from selfalign import load_scene
from selfalign.io.hdf5 import write_h5
from selfalign.stages.common import logged
from selfalign.stages.stability import stability_result

with logged(snakemake.log[0]) as log:
    scene = load_scene(snakemake.input.scene)
    datasets, attrs = stability_result(scene, snakemake.params.moreau_steps, snakemake.params.moreau_eps)
    write_h5(snakemake.output[0], datasets, attrs)
    for k, method in enumerate(datasets["methods"]):
        log.info("%s: max |M - M_%s| = %.3g", method, datasets["methods"][0], datasets["monodromy_error"][k])
    log.info("written to %s", snakemake.output[0])
