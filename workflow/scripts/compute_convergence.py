"""Two velocity transients and V = (v1 - v2)^2 / 2 into results/convergence/<scene>.h5
(rule compute_convergence), or their rerun recording results/rerun/<scene>.rrd
(rule record_convergence)."""

from selfalign import load_scene
from selfalign.analysis.lyapunov import convergence_result, recording_series
from selfalign.io.hdf5 import read_h5, write_h5
from selfalign.io.recording import write_recording
from selfalign.stages.common import logged

with logged(snakemake.log[0]) as log:
    if snakemake.rule == "record_convergence":
        times, series = recording_series(read_h5(snakemake.input[0]))
        write_recording(snakemake.output[0], times, series)
        log.info("%d samples of %s written to %s", times.size, sorted(series), snakemake.output[0])
    else:
        scene = load_scene(snakemake.input.scene)
        datasets, attrs = convergence_result(scene, float(snakemake.params.v20))
        write_h5(snakemake.output[0], datasets, attrs)
        log.info("%s: v10 = %r, v20 = %r, V = 0 from t = %r on; %d intervals; written to %s", scene.name,
                 attrs["v10"], attrs["v20"], attrs["converged_time"], datasets["interval_start"].size,
                 snakemake.output[0])
