"""Rerun recording results/rerun/planar_motion.rrd of the two example entries of results/planar/planar.h5: the part
moving in the plane over the strips' edges."""

from selfalign.io.hdf5 import read_h5
from selfalign.io.recording import write_recording
from selfalign.stages.common import logged
from selfalign.stages.planar import planar_recording

with logged(snakemake.log[0]) as log:
    recording = planar_recording(read_h5(snakemake.input[0]))
    write_recording(snakemake.output[0], recording)
    log.info("%d samples of two entries written to %s", recording.times.size, snakemake.output[0])
