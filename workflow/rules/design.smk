# Stage "design": each spec of workflow/designs/ (docs/tutorials/design-station.md)
# designed with its design map at the chosen period and stroke, and the chosen design's stop
# recorded for rerun.  The figure of each design is a rule of figures.smk (plot_design_<spec>).

DESIGN = config["stages"]["design"]
DESIGNS = DESIGN["designs"]

wildcard_constraints:
    design="|".join(re.escape(n) for n in sorted(DESIGNS)),


rule compute_design:
    input:
        f"{DESIGN['designs_dir']}/{{design}}.yaml",
    output:
        results("design", "{design}"),
    params:
        map=DESIGN["map"],
    log:
        log_file("design", "{design}"),
    benchmark:
        benchmark_file("design", "{design}")
    conda:
        ENV
    script:
        "../scripts/compute_design.py"


rule record_design:
    input:
        results("design", "{design}"),
    output:
        results("rerun", "design_{design}", "rrd"),
    log:
        log_file("design", "record_{design}"),
    conda:
        ENV
    script:
        "../scripts/record_design.py"


TARGETS.extend(results("rerun", f"design_{name}", "rrd") for name in DESIGNS)
