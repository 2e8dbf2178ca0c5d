"""Fig. 9 (one steady-state time history per case of Table 1) from simulation results."""

from selfalign.analysis.classification import CASE_LABELS, classify
from selfalign.io.hdf5 import read_h5
from selfalign.plots.simulation import figure_09
from selfalign.stages.common import logged, save_figure
from selfalign.stages.simulation import scene_from_result

with logged(snakemake.log[0]) as log:
    results = [read_h5(path) for path in snakemake.input]
    cases = [classify(scene_from_result(r).profile) for r in results]
    fig = figure_09(results, cases, CASE_LABELS, periods=snakemake.params.periods)
    save_figure(fig, snakemake.output[0], dpi=snakemake.params.dpi)
    log.info("figure 9 (cases %s) from %s written to %s", cases, list(snakemake.input), snakemake.output[0])
