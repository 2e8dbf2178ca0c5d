"""Rerun recording results/rerun/<scene>.rrd of a convergence result: v1, v2 and V."""

from selfalign.io.hdf5 import read_h5
from selfalign.io.recording import write_recording
from selfalign.stages.common import logged
from selfalign.stages.convergence import convergence_recording

with logged(snakemake.log[0]) as log:
    recording = convergence_recording(read_h5(snakemake.input[0]))
    write_recording(snakemake.output[0], recording)
    log.info("%d samples of %s written to %s", recording.times.size, sorted(recording.series), snakemake.output[0])
