"""Rerun recording results/rerun/<scene>.rrd of a simulation result's recorded series."""

from selfalign.io.hdf5 import read_h5
from selfalign.io.recording import write_recording
from selfalign.io.simulation_result import rerun_series, trajectory_from_result
from selfalign.stages.common import logged

with logged(snakemake.log[0]) as log:
    times, series = rerun_series(trajectory_from_result(read_h5(snakemake.input[0])))
    write_recording(snakemake.output[0], times, series)
    log.info("%d samples of %s from %s written to %s", times.size, sorted(series), snakemake.input[0],
             snakemake.output[0])
