"""Fig. 8: the flow chart of the a-priori case decision, drawn by walking
selfalign.analysis.classification.DECISION_TREE."""

from selfalign.plots.classification import figure_08
from selfalign.stages.common import logged, save_figure

with logged(snakemake.log[0]) as log:
    save_figure(figure_08(), snakemake.output[0], dpi=snakemake.params.dpi)
    log.info("figure 8 from the decision tree written to %s", snakemake.output[0])
