"""Rerun recording results/rerun/parts_queue.rrd of the recorded queue of results/parts/queue.h5: boxes over time."""

from selfalign.io.hdf5 import read_h5
from selfalign.io.recording import write_recording
from selfalign.stages.common import logged
from selfalign.stages.parts import queue_recording

with logged(snakemake.log[0]) as log:
    recording = queue_recording(read_h5(snakemake.input[0]))
    write_recording(snakemake.output[0], recording)
    log.info("%d period ends of %d boxes written to %s", recording.times.size,
             recording.boxes["queue/parts"].centres.shape[1], snakemake.output[0])
