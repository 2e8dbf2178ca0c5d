"""Simulate a scene into results/simulation/<scene>.h5 (method and options from the scene)."""

from selfalign import load_scene, simulate
from selfalign.io.hdf5 import write_h5
from selfalign.io.simulation_result import trajectory_content
from selfalign.stages.common import logged

with logged(snakemake.log[0]) as log:
    scene = load_scene(snakemake.input.scene)
    traj = simulate(scene)
    write_h5(snakemake.output[0], *trajectory_content(traj, scene))
    log.info("%s: %s, %s (%s); %s written to %s", scene.name, traj.method, traj.status.value, traj.message,
             traj.stats, snakemake.output[0])
