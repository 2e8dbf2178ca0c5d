"""Two velocity transients and V = (v1 - v2)^2 / 2 (Sect. 6.2) into results/convergence/<scene>.h5."""

from selfalign import load_scene
from selfalign.io.hdf5 import write_h5
from selfalign.stages.common import logged
from selfalign.stages.convergence import convergence_result

with logged(snakemake.log[0]) as log:
    scene = load_scene(snakemake.input.scene)
    datasets, attrs = convergence_result(scene, float(snakemake.params.v20))
    write_h5(snakemake.output[0], datasets, attrs)
    log.info("%s: v10 = %r, v20 = %r, V = 0 from t = %r on; %d intervals; written to %s", scene.name,
             attrs["v10"], attrs["v20"], attrs["converged_time"], datasets["interval_start"].size,
             snakemake.output[0])
