# Benchmarks (docs/explanation/performance.md): not part of rule `all`, so `snakemake -c2` stays fast.
# Run them with `snakemake -c2 benchmarks`; the table lands in results/benchmarks/table.md.

BENCHMARKS = config.get("benchmarks", {})


rule run_benchmarks:
    output:
        table="results/benchmarks/table.md",
        raw="results/benchmarks/benchmarks.json",
    params:
        full_pipeline=BENCHMARKS.get("full_pipeline", True),
        cores=BENCHMARKS.get("cores", 2),
    log:
        log_file("benchmarks", "run_benchmarks"),
    # The timed pipeline run uses `cores` cores; reserve them so no other job skews the timings.
    threads: BENCHMARKS.get("cores", 2)
    conda:
        ENV
    script:
        "../scripts/run_benchmarks.py"


rule benchmarks:
    input:
        rules.run_benchmarks.output.table,
