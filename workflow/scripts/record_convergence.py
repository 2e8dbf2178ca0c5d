"""Rerun recording results/rerun/<scene>.rrd of a convergence result: v1, v2 and V."""

from selfalign.io.hdf5 import read_h5
from selfalign.io.recording import write_recording
from selfalign.stages.common import logged
from selfalign.stages.convergence import recording_series

with logged(snakemake.log[0]) as log:
    times, series = recording_series(read_h5(snakemake.input[0]))
    write_recording(snakemake.output[0], times, series)
    log.info("%d samples of %s written to %s", times.size, sorted(series), snakemake.output[0])
