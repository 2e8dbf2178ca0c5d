# selfalign workflow: scenes (workflow/scenes/*.yaml) -> results/<stage>/*.h5 -> figures/*.png.
# Run from the repository top: `snakemake -c2`, or with the workflow profile
# `snakemake --workflow-profile workflow/profiles/default`.  Layout: docs/tutorials/reproduce-paper.md.

from snakemake.exceptions import WorkflowError
from snakemake.utils import min_version, validate

from selfalign import SceneError
from selfalign.io.scene_files import validate_config

min_version("9.0")


configfile: "workflow/config/config.yaml"


try:
    # One line naming the file and the key, like a bad scene, before Snakemake's own
    # validation (which also fills in the schema's defaults).
    validate_config(config, f"{workflow.basedir}/workflow/schemas/config.schema.yaml",
                    "workflow/config/config.yaml", workflow.config_settings.overwrite_config)
except SceneError as exc:
    raise WorkflowError(f"invalid config: {exc}") from None
validate(config, "workflow/schemas/config.schema.yaml")


include: "workflow/rules/common.smk"
include: "workflow/rules/trajectory.smk"
include: "workflow/rules/simulation.smk"
include: "workflow/rules/accuracy.smk"
include: "workflow/rules/benchmarks.smk"
include: "workflow/rules/stability.smk"
include: "workflow/rules/convergence.smk"
include: "workflow/rules/classification.smk"
include: "workflow/rules/accumulation.smk"
include: "workflow/rules/effects.smk"
include: "workflow/rules/design.smk"
include: "workflow/rules/finite_jerk.smk"
include: "workflow/rules/figures.smk"
include: "workflow/rules/optimal_motion.smk"
include: "workflow/rules/parts.smk"
include: "workflow/rules/planar.smk"
include: "workflow/rules/report.smk"


report: "workflow/report/workflow.rst"


rule all:
    default_target: True
    input:
        TARGETS,
