# Stage "accuracy": the work-precision study (Moreau time-stepping and solve_ivp against the
# exact solver, error against CPU time) of each scene into results/accuracy/<scene>.h5, and
# figures/accuracy_cost.png.  Timings are CPU times measured inside the job (README "Solvers").


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
        "results/benchmarks/accuracy/{scene}.tsv"
    script:
        "../scripts/measure_accuracy.py"


rule plot_accuracy_cost:
    input:
        [results("accuracy", name) for name in scenes("accuracy")],
    output:
        figure("accuracy_cost"),
    params:
        dpi=config["figures"]["dpi"],
    log:
        log_file("figures", "accuracy_cost"),
    script:
        "../scripts/plot_accuracy_cost.py"


TARGETS.extend(results("accuracy", name) for name in scenes("accuracy"))
TARGETS.append(figure("accuracy_cost"))
