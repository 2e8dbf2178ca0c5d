# Stage "finite_jerk" (docs/explanation/model.md): the paper's maps against the ramp time of y''
# (steady vbar and case over each steady plane, stopping in accumulation's zone) into one
# result file; its figure is the rule plot_finite_jerk of figures.smk.

FINITE_JERK = config["stages"]["finite_jerk"]


rule compute_finite_jerk:
    output:
        results("finite_jerk", "finite_jerk"),
    params:
        ramp_fractions=FINITE_JERK["ramp_fractions"],
        steady=FINITE_JERK["steady"],
        stopping=FINITE_JERK["stopping"],
        zone=ACCUMULATION["zone"],
    log:
        log_file("finite_jerk", "finite_jerk"),
    benchmark:
        benchmark_file("finite_jerk", "finite_jerk")
    conda:
        ENV
    script:
        "../scripts/compute_finite_jerk.py"
