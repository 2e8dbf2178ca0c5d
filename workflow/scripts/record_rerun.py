"""Rerun recording results/rerun/<scene>.rrd of a simulation result: series, events, scene."""

from selfalign.io.hdf5 import read_h5
from selfalign.io.recording import write_recording
from selfalign.io.simulation_result import simulation_recording
from selfalign.stages.common import logged

with logged(snakemake.log[0]) as log:
    recording = simulation_recording(read_h5(snakemake.input[0]))
    write_recording(snakemake.output[0], recording)
    log.info("%d samples of %s and %d log lines from %s written to %s", recording.times.size, sorted(recording.series),
             sum(len(entries.texts) for entries in recording.logs.values()), snakemake.input[0], snakemake.output[0])
