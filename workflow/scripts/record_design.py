"""Rerun recording results/rerun/design_<spec>.rrd of the chosen design's stop at the nominal mu."""

from selfalign.io.hdf5 import read_h5
from selfalign.io.recording import write_recording
from selfalign.stages.common import logged
from selfalign.stages.design import stop_recording

with logged(snakemake.log[0]) as log:
    recording = stop_recording(read_h5(snakemake.input[0]))
    write_recording(snakemake.output[0], recording)
    log.info("%d samples of the stop written to %s", recording.times.size, snakemake.output[0])
