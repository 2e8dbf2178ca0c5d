# selfalign workflow: scenes (workflow/scenes/*.yaml) -> results/<stage>/*.h5 -> figures/*.png.
# Run from the repository top: `snakemake -c2`, or with the workflow profile
# `snakemake --workflow-profile workflow/profiles/default`.  Layout: README.md, "Pipeline".

from snakemake.utils import min_version, validate

min_version("9.0")


configfile: "workflow/config/config.yaml"


validate(config, "workflow/schemas/config.schema.yaml")


include: "workflow/rules/common.smk"
include: "workflow/rules/trajectory.smk"


rule all:
    default_target: True
    input:
        TARGETS,
