"""Sample a scene's table motion into results/trajectory/<scene>.h5."""

from selfalign import load_scene
from selfalign.io.hdf5 import write_h5
from selfalign.stages.common import logged
from selfalign.stages.trajectory import profile_samples

with logged(snakemake.log[0]) as log:
    scene = load_scene(snakemake.input.scene)
    datasets, attrs = profile_samples(scene)
    write_h5(snakemake.output[0], datasets, attrs)
    log.info("%s: %d samples of %r written to %s", scene.name, datasets["t"].size, scene.profile,
             snakemake.output[0])
