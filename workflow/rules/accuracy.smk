# Stage "accuracy": the work-precision study (Moreau time-stepping and solve_ivp against the
# exact solver, error against CPU time) of each scene into results/accuracy/<scene>.h5.
# Timings are CPU times measured inside the job (docs/explanation/solvers.md).


rule measure_accuracy:
    input:
        scene=lambda wildcards: scene_file(wildcards.scene),
    output:
        results("accuracy", "{scene}"),
    params:
        settings={k: v for k, v in config["stages"]["accuracy"].items() if k != "scenes"},
    log:
        log_file("accuracy", "{scene}"),
    benchmark:
        benchmark_file("accuracy", "{scene}")
    conda:
        ENV
    script:
        "../scripts/measure_accuracy.py"


TARGETS.extend(results("accuracy", name) for name in scenes("accuracy"))
