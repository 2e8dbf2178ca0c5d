# The result tables of the report: one rule tabulate_<name> per table, each writing
# results/tables/<name>.html from existing results with selfalign.stages.tables.build_table,
# carried with its caption, workflow/report/table_<name>.rst, into `snakemake --report`.

TABLE_CATEGORY = "Tables"

#: Result files behind the job-time table: every job with a `benchmark:` file.
BENCHMARKED_JOBS = (
    [benchmark_file("simulation", n) for n in scenes("simulation")]
    + [benchmark_file("accuracy", n) for n in scenes("accuracy")]
    + [benchmark_file("classification", "fig06")]
    + [benchmark_file("optimal_motion", "fig06_revisited")]
    + [benchmark_file("accumulation", f"shards/fig17_{i}")
       for i in range(config["stages"]["accumulation"]["positioning"]["shards"])]
)

#: name -> input files
TABLES = {
    "steady_states": [results("stability", n) for n in scenes("stability")],
    "floquet": [results("stability", n) for n in scenes("stability")],
    "job_times": BENCHMARKED_JOBS,
}


for name, inputs in TABLES.items():

    rule:
        name:
            f"tabulate_{name}"
        input:
            inputs,
        output:
            report(results("tables", name, "html"), caption=f"../report/table_{name}.rst", category=TABLE_CATEGORY),
        params:
            table=name,
        log:
            log_file("tables", name),
        conda:
            ENV
        script:
            "../scripts/write_table.py"


TARGETS.extend(results("tables", name, "html") for name in TABLES)


# figures/README.md: every figure with its files and its caption, rendered as in the report, so
# that figures/ explains itself; the documentation's gallery is made from it.
rule write_figure_index:
    input:
        [figure(name, fmt) for name in FIGURE_CAPTIONS for fmt in FIGURE_FORMATS],
    output:
        "figures/README.md",
    params:
        figures=[{"name": name, "caption": f"workflow/report/{stem}.rst", "category": category, "options": options}
                 for name, (stem, category, options) in sorted(FIGURE_CAPTIONS.items())],
        formats=FIGURE_FORMATS,
    log:
        log_file("figures", "index"),
    conda:
        ENV
    script:
        "../scripts/write_figure_index.py"


TARGETS.append("figures/README.md")
